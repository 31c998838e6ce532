"""The limits of a phase portrait (:func:`rocknroller.papers.portrait.slow_portrait`), checked before any work: the
number of map orbits and direct starts, and the θ-maxima all of them keep (memory and CSV size), with the grids'
ranges.  Each bad value is a ValueError naming the parameter and the limit.  Its work (:func:`portrait_seconds`: the
tables not cached, the orbits, the direct runs, the horizon probes and the files) is estimated before any of it.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body

__all__ = ["MAX_PORTRAIT_ORBITS", "MAX_ODE_STARTS", "MAX_PORTRAIT_MAXIMA", "BYTES_PER_MAXIMUM", "CSV_BYTES_PER_ROW",
           "OUTPUT_SECONDS", "OUTPUT_SECONDS_PER_MAXIMUM", "check_portrait_size", "portrait_seconds"]

#: Most map orbits of one portrait (grid points; each ~1 ms per 1000 time units).
MAX_PORTRAIT_ORBITS = 10_000
#: Most direct-ODE starts overlaid on one portrait.
MAX_ODE_STARTS = 100
#: Most θ-maxima one portrait may keep, over all its orbits and direct runs (each orbit is kept whole, drawn and
#: written, one CSV row a maximum): t_end/T_θ(0) an orbit (:func:`rocknroller.analysis.slow.work.map_maxima`).
MAX_PORTRAIT_MAXIMA = 1_000_000
#: Peak memory per θ-maximum of a portrait made, drawn and written (:func:`~rocknroller.papers.portrait_output.write_portrait`): 563 bytes measured
#: (20 orbits of 3e5 time units, 4.6e5 maxima).
BYTES_PER_MAXIMUM = 600
#: Bytes of one row of ``portrait.csv``: 147 measured (the same run).
CSV_BYTES_PER_ROW = 150
#: CPU seconds of the files of a portrait (:func:`~rocknroller.papers.portrait_output.write_portrait`: the figure as
#: PNG and PDF, and the CSVs) besides their θ-maxima: ~2 s measured (the default portrait of 90 orbits, 1.4e4
#: maxima; ``benchmarks/bench_budget.py commands``).
OUTPUT_SECONDS = 4.0
#: The same per θ-maximum drawn and written: ~2.7e-5 s measured (400 orbits of 20 000 time units, 6e5 maxima: ~16 s
#: of the command's 34 s).
OUTPUT_SECONDS_PER_MAXIMUM = 4.0e-5


def _check_grid(name: str, values: ArrayLike, lo: float, hi: float) -> NDArray[np.float64]:
    a = np.atleast_1d(np.asarray(values, float))
    if a.ndim != 1 or a.size == 0 or not np.all(np.isfinite(a)) or np.any((a < lo) | (a > hi)):
        raise ValueError(f"{name} must be a non-empty 1-D grid of finite values in [{lo:.6g}, {hi:.6g}], "
                         f"got {values!r}")
    return a


def _size(n: float) -> str:
    """Bytes for people: 150 MB, 12 GB."""
    return f"{n / 1e9:.3g} GB" if n >= 1e9 else f"{n / 1e6:.3g} MB"


def check_portrait_size(body: Body, theta0: float, n_orbits: int, t_end: float, ode_t_ends: Sequence[float] = ()
                        ) -> float:
    """The estimated θ-maxima of a portrait of ``n_orbits`` map orbits over t_end and direct runs over ``ode_t_ends``
    (t_end/T_θ(0) each), or a ValueError naming t_end and the memory and CSV size they would take unless at most
    ``MAX_PORTRAIT_MAXIMA``."""
    from rocknroller.analysis.slow.work import map_maxima

    per_time = float(map_maxima(body, [theta0], 1.0)[0])  # maxima per time unit, 1/T_θ(0)
    n = per_time * (n_orbits * float(t_end) + float(sum(ode_t_ends)))
    if n > MAX_PORTRAIT_MAXIMA:
        most = (MAX_PORTRAIT_MAXIMA / per_time - float(sum(ode_t_ends))) / n_orbits
        raise ValueError(
            f"t_end must be at most {max(most, 0.0):.3g} for a portrait of {n_orbits} orbits (got t_end={t_end!r}): "
            f"it would keep about {n:.2g} theta-maxima, {_size(n * BYTES_PER_MAXIMUM)} of memory and a "
            f"{_size(n * CSV_BYTES_PER_ROW)} CSV, more than MAX_PORTRAIT_MAXIMA = {MAX_PORTRAIT_MAXIMA:.0e} "
            f"({_size(MAX_PORTRAIT_MAXIMA * BYTES_PER_MAXIMUM)}, a {_size(MAX_PORTRAIT_MAXIMA * CSV_BYTES_PER_ROW)} "
            "CSV); give a shorter t_end or fewer starts")
    return n


def portrait_seconds(body: Body, theta0: float, n_orbits: int, t_end: float, *, order: int = 1, chaos: bool = True,
                     ode_t_ends: Sequence[float] = (), horizons: bool = False, files: bool = False
                     ) -> tuple[float, str]:
    """The estimated CPU seconds of a portrait of ``n_orbits`` map orbits over t_end at θ0 and direct runs over
    ``ode_t_ends``, and a phrase saying what they count (:mod:`rocknroller.numerics.budget`), without building or
    running anything: the tables of (body, θ0) not cached (the release table, and at ``order`` 2 the second-order
    table; :func:`rocknroller.analysis.slow.work.tables_seconds`), the orbits' θ-maxima with their tangent vectors if
    ``chaos`` (:func:`rocknroller.analysis.slow.work.map_runs_seconds`), the direct runs, with ``horizons`` (and
    ``chaos``) one horizon probe of ``PROBE_ROCKS`` rocks an orbit
    (:func:`rocknroller.papers.portrait_output.orbit_horizons`), and with ``files`` the figure and the CSVs
    (``OUTPUT_SECONDS`` and ``OUTPUT_SECONDS_PER_MAXIMUM``).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=5e-3)
    >>> plain, _ = portrait_seconds(body, 0.95 * math.pi, 90, 2000.0, chaos=False)
    >>> full, what = portrait_seconds(body, 0.95 * math.pi, 90, 2000.0, horizons=True)
    >>> print(full > plain, "|", what.split(", ")[-1])
    True | 90 horizon probes of 40 rocks)
    """
    from rocknroller.analysis.model.equations import EulerState
    from rocknroller.analysis.slow.dynamics.chaos import PROBE_ROCKS, SPAN_ROCKS
    from rocknroller.analysis.slow.map.limits import check_map_theta0
    from rocknroller.analysis.slow.work import map_runs_seconds, rocking_period, tables_seconds
    from rocknroller.numerics.budget import DIRECT_RUN_SECONDS, HEYOKA_SECONDS_PER_RADIAN
    from rocknroller.numerics.run_limits import rate_bound

    theta0 = check_map_theta0(theta0)
    tables, built = tables_seconds(body, [theta0], order)
    orbits, n_max = map_runs_seconds(body, [theta0], n_orbits, t_end, order, tangent=chaos, indicator_span=chaos)
    rate = rate_bound(body, EulerState(theta0).to_body_state())  # Λ: every start has the release's energy
    ode = sum(rate * float(t) * HEYOKA_SECONDS_PER_RADIAN + DIRECT_RUN_SECONDS for t in ode_t_ends)
    period = rocking_period(body, theta0)
    n_probes = n_orbits if horizons and chaos else 0
    probes = n_probes * (rate * PROBE_ROCKS * period * HEYOKA_SECONDS_PER_RADIAN + DIRECT_RUN_SECONDS)
    kept = n_max + sum(ode_t_ends) / period
    output = OUTPUT_SECONDS + kept * OUTPUT_SECONDS_PER_MAXIMUM if files else 0.0
    tangents = f" with their tangent vectors over the indicators' span, max(t_end, {SPAN_ROCKS} rocks)" if chaos else ""
    what = (f"the portrait ({built}, {n_orbits} map orbits of order {order} over t_end = {float(t_end):g}"
            f"{tangents}, about {n_max:.2g} theta-maxima, {len(ode_t_ends)} "
            f"direct runs{', its figure and CSV files' if files else ''}, {n_probes} horizon probes of "
            f"{PROBE_ROCKS} rocks)")
    seconds = tables + orbits + ode + probes + output
    return (seconds if math.isfinite(seconds) else math.inf), what
