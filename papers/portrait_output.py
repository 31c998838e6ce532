"""What a phase portrait (:func:`rocknroller.papers.portrait.slow_portrait`) writes for people: each map orbit's
verdict, indicators and predictability horizon (:func:`orbit_rows`, :func:`orbit_horizons`), and the figure with the
samples' and the orbits' CSV files (:func:`write_portrait`).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike

from rocknroller.analysis.slow.dynamics.chaos import CRITERION, HORIZON_FRACTION, PROBE_ROCKS
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.slow.map.family import maximum_state
from rocknroller.numerics.budget import (DIRECT_RUN_SECONDS, HEYOKA_SECONDS_PER_RADIAN, WORK_BUDGET_SECONDS,
                                         check_work)
from rocknroller.numerics.run_limits import rate_bound
from rocknroller.numerics.megno import MEGNO_CHAOTIC, MIN_SAMPLES
from rocknroller.papers.output import angle_text, save_figure, write_csv
from rocknroller.papers.portrait import SlowPortrait, plot_portrait, portrait_values

__all__ = ["horizons_seconds", "orbit_horizons", "orbit_rows", "write_portrait"]


def horizons_seconds(body: Body, theta0: float, n_orbits: int) -> float:
    """The estimated CPU seconds of :func:`orbit_horizons` for ``n_orbits`` orbits at the energy of a release from rest
    at θ0 (every orbit of a portrait has it): one direct run of ``PROBE_ROCKS`` T_θ(0) each, at Λ of that energy and
    :data:`~rocknroller.numerics.budget.HEYOKA_SECONDS_PER_RADIAN`, with ``DIRECT_RUN_SECONDS`` a run besides (the
    probe of 40 rocks is mostly that: 0.036-0.040 s measured an orbit at θ0 = 0.95π)."""
    from rocknroller.analysis.slow.map.limits import check_map_theta0
    from rocknroller.analysis.slow.work import rocking_period

    theta0 = check_map_theta0(theta0)
    window = PROBE_ROCKS * rocking_period(body, theta0)
    rate = rate_bound(body, EulerState(theta0).to_body_state())
    return n_orbits * (rate * window * HEYOKA_SECONDS_PER_RADIAN + DIRECT_RUN_SECONDS)


def orbit_horizons(portrait: SlowPortrait, budget: float | None = WORK_BUDGET_SECONDS) -> list[Any]:
    """Each map orbit's predictability horizon (:class:`rocknroller.analysis.slow.dynamics.chaos.Horizon`), as
    ``predict_slow_motion`` measures it for a release: the map − ODE error over the first ``PROBE_ROCKS`` rocks from
    the orbit's start (the direct ODE from the same maximum, :func:`rocknroller.analysis.slow.map.family.maximum_state`),
    extrapolated by the growth law its verdict gives.  None for an orbit without indicators (fewer than
    ``MIN_SAMPLES`` maxima, or a portrait made with ``chaos=False``) or without extent (a fixed point of the map).
    Costs one direct run of ``PROBE_ROCKS`` rocks an orbit (~0.02 s; :func:`horizons_seconds`, checked against
    ``budget`` before any run: a ``WorkBudgetError``, a ValueError, beyond it)."""
    from rocknroller.analysis.slow.dynamics.chaos import HorizonProbe
    from rocknroller.analysis.slow.work import rocking_period

    n = len(portrait.orbits)
    check_work(horizons_seconds(portrait.body, portrait.theta0, n),
               f"the horizons of {n} orbits (a direct run of {PROBE_ROCKS} rocks each)", budget)
    sym, eps = portrait.body.symmetric(), portrait.body.epsilon
    rock_time = portrait.rock_time if math.isfinite(portrait.rock_time) else rocking_period(portrait.body,
                                                                                             portrait.theta0)
    window = PROBE_ROCKS * rock_time  # the tables' T_θ(0), as predict_slow_motion's window
    along = float(portrait.grad_W @ portrait.e)
    out: list[Any] = []
    for k, s in enumerate(portrait.orbits):
        c = portrait.chaos[k] if k < len(portrait.chaos) else None
        if c is None or not (np.ptp(s.QR) > 0.0 and np.ptp(s.QJ) > 0.0):
            out.append(None)
            continue
        QR, QJ = (float(portrait.p0[k]) / along) * portrait.e
        state = maximum_state(sym, eps, portrait.E, QR, QJ, 0.5 * float(portrait.Theta0[k]))[2]
        probe = portrait.probes[k] if k < len(portrait.probes) else None
        series, extents = probe if probe is not None else (s, None)  # the span's run, as a release's prediction
        out.append(HorizonProbe(portrait.body, state, series, c, window, extents).horizon())
    return out


def orbit_rows(portrait: SlowPortrait, horizons: bool = True,
               budget: float | None = WORK_BUDGET_SECONDS) -> dict[str, list]:
    """One row per map orbit, as columns: its index and start (Θ0, p0), whether it left the tables before t_end, its
    number of θ-maxima, the span over which its indicators were measured (from its start to its last maximum), its
    verdict over that span (regular, chaotic or undecided, by MEGNO and λ together as for ``predict_slow_motion``,
    :func:`rocknroller.analysis.slow.dynamics.chaos.map_verdict`; None without indicators: fewer than
    ``MIN_SAMPLES`` maxima or a portrait made with ``chaos=False``), MEGNO and the finite-time Lyapunov exponent per
    unit time and per rock (None where there is no verdict), and with ``horizons`` its predictability horizon and the
    method that found it (:func:`orbit_horizons`; None where there is none, the horizon None also where it is
    infinite; ``budget`` as for :func:`orbit_horizons`)."""
    keys = ["orbit", "Theta0", "p0", "left_tables", "n_maxima", "span", "verdict", "megno", "lyapunov",
            "lyapunov_per_rock"] + (["horizon", "horizon_method"] if horizons else [])
    cols: dict[str, list] = {k: [] for k in keys}
    left = set(portrait.left)
    found = orbit_horizons(portrait, budget) if horizons else []
    for k, s in enumerate(portrait.orbits):
        c = portrait.chaos[k] if k < len(portrait.chaos) else None
        row = {"orbit": k, "Theta0": float(portrait.Theta0[k]), "p0": float(portrait.p0[k]),
               "left_tables": k in left, "n_maxima": int(s.t.size), "span": float(s.t[-1]) if s.t.size else 0.0,
               "verdict": None if c is None else c.verdict, "megno": None if c is None else c.megno,
               "lyapunov": None if c is None else c.lyapunov,
               "lyapunov_per_rock": None if c is None else c.lyapunov_per_rock}
        if horizons:
            h = found[k]
            row["horizon"] = None if h is None or not math.isfinite(h.t) else h.t
            row["horizon_method"] = None if h is None else h.method
        for key in keys:
            cols[key].append(row[key])
    return cols


def write_portrait(portrait: SlowPortrait, out: str | Path, name: str = "portrait",
                   values: ArrayLike | None = None, orbits: Sequence[Any] | None = None,
                   rows: dict[str, list] | None = None) -> list[Path]:
    """Save the figure (:func:`plot_portrait`) as ``name.png`` and ``name.pdf``, the samples as ``name.csv``
    (one row per θ-maximum: source ``map`` or ``ode``, orbit index, its start (Θ0, p0), colour value (empty where
    not measured), t, Θ mod 2π, p, Q_R, Q_J; header with the parameters) and the map's orbits as
    ``name_orbits.csv`` (one row per orbit: :func:`orbit_rows`, or ``rows`` if already made, as the command line
    does for its JSON: each orbit's horizon costs a short direct run); returns the paths.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> import tempfile
    >>> portrait = rr.slow_portrait(rr.Body.paper(epsilon=5e-3), 0.95 * math.pi, [0.5, 1.5], [0.0], 200.0)
    >>> with tempfile.TemporaryDirectory() as out:
    ...     print([p.name for p in rr.write_portrait(portrait, out)])
    ...
    ['portrait.png', 'portrait.pdf', 'portrait.csv', 'portrait_orbits.csv']
    """
    vals, label = portrait_values(portrait, values, orbits)
    paths = save_figure(plot_portrait(portrait, values, orbits=orbits), out, name)
    cols: dict[str, list] = {k: [] for k in ("source", "orbit", "Theta0", "p0", "value", "t", "Theta", "p", "QR",
                                              "QJ")}

    def add(source: str, k: int, th0: float, p0: float, v: float | None, t: Any, Th: Any, QR: Any, QJ: Any) -> None:
        m = len(t)
        for key, col in (("source", [source] * m), ("orbit", [k] * m), ("Theta0", [th0] * m), ("p0", [p0] * m),
                         ("value", [v] * m), ("t", list(t)), ("Theta", list(np.mod(Th, 2.0 * math.pi))),
                         ("p", list(portrait.p(QR, QJ))), ("QR", list(QR)), ("QJ", list(QJ))):
            cols[key].extend(col)

    for k, s in enumerate(portrait.orbits):
        v = float(vals[k])
        add("map", k, float(portrait.Theta0[k]), float(portrait.p0[k]), v if math.isfinite(v) else None, s.t, s.Theta,
            s.QR, s.QJ)
    for k, (m, (th0, p0)) in enumerate(zip(portrait.ode, portrait.ode_starts)):
        add("ode", k, th0, p0, None, m.t, 2.0 * m.psi, m.QR, m.QJ)
    header = [f"rocknroller portrait: body {portrait.body.describe()}",
              f"theta0 {angle_text(portrait.theta0)} (E {float(portrait.E)!r}), K = eps kappa {float(portrait.K)!r}, "
              f"map order {portrait.order}, t_end {float(portrait.t_end)!r}",
              f"p = gradW(0).Q with gradW(0) = ({float(portrait.grad_W[0])!r}, {float(portrait.grad_W[1])!r}); grid "
              f"starts at Q = (p0 / gradW.e) e, e = ({float(portrait.e[0])!r}, {float(portrait.e[1])!r}); Theta = 2 psi "
              "mod 2 pi",
              f"value: {label}" + (f" of the map's orbit over its run (> {MEGNO_CHAOTIC:g}: chaotic; empty: fewer than "
                                   f"{MIN_SAMPLES} maxima)" if label == "MEGNO" else "")
              + f"; orbits that left the tables before t_end: {list(portrait.left)}",
              "source ode: the direct ODE from the same maxima (value empty)"]
    paths.append(write_csv(Path(out) / f"{name}.csv", cols, header))
    paths.append(write_csv(Path(out) / f"{name}_orbits.csv", orbit_rows(portrait) if rows is None else rows, header[:2] + [
        f"one row per map orbit: its start, left_tables (true: it left the tables before t_end), its maxima, span (the "
        f"time from its start to its last maximum, over which its indicators are measured: the portrait's t_end), "
        f"verdict ({CRITERION}; empty: fewer than {MIN_SAMPLES} maxima or no indicators), MEGNO and the finite-time "
        f"Lyapunov exponent per unit time and per rock, horizon (the time at which the map - ODE error reaches "
        f"{HORIZON_FRACTION:.0%} of the extents, from a direct probe of {PROBE_ROCKS} rocks; empty: none, or infinite) "
        f"and the method that found it"]))
    return paths
