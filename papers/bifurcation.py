"""The bifurcation diagram of rocking near the period doubling: the rocking fixed points and the period-2 orbit of
the slow map continued in ε (:mod:`rocknroller.analysis.slow.dynamics.periodic_orbits`), stable solid and unstable dashed,
with the exact one-step map's orbits (direct ODE) as markers; the standard map's angle ϑ = Θ + W(Q)/2 at the kick
against ε/ε_pd (ε_pd of the exact map, :func:`rocknroller.analysis.slow.dynamics.period_doubling.period_doubling`), and
Greene's residues below.  :func:`bifurcation_data` computes, :func:`bifurcation_diagram` writes PNG, PDF and CSV.
Over a range of release angles, :func:`period_doubling_line` gives the period doubling's ε_pd(θ0) of the slow map at
orders 1 (4/κ) and 2 (the map's own root), :func:`period_doubling_plot` writes its figure and CSV: with the tables
over energy (``rocknroller warm --tables``) a release angle costs no table build.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map.limits import K_PERIOD_DOUBLING, check_map_theta0, default_order
from rocknroller.analysis.slow.map.tables_at_once import build_release_tables, energy_tables_cached, release_tables
from rocknroller.analysis.slow.dynamics.period_doubling import map_period_doubling, period_doubling
from rocknroller.analysis.slow.dynamics.periodic_orbits import (K_MAX, MAX_BRANCH_POINTS, Branch, PeriodicOrbit,
                                                                continue_orbit, periodic_orbit)
from rocknroller.numerics.budget import (EXACT_ORBIT_SECONDS, MAP_SETUP_SECONDS, PERIOD_DOUBLING_SECONDS,
                                         SLOW_ORBIT_SECONDS, WORK_BUDGET_SECONDS, check_work)
from rocknroller.papers.output import angle_text, new_figure, save_figure, write_csv

#: The orbits' colours and their names in the legend (the rows of the CSV's ``orbit`` column).
BRANCH_STYLE = {"fixed_stable_axis": ("C0", "rocking about the stable axis (fixed point)"),
                "fixed_unstable_axis": ("C2", "rocking about the unstable axis (fixed point)"),
                "period2": ("C1", "period-2 orbit (born at the period doubling)")}

__all__ = ["MAX_EXACT_FRACTIONS", "MAX_DIAGRAM_THETA0", "BifurcationData", "check_diagram_counts", "bifurcation_seconds",
           "bifurcation_data", "bifurcation_figure", "bifurcation_diagram", "FILES_SECONDS", "MAX_LINE_THETA0",
           "PeriodDoublingLine", "period_doubling_line", "line_seconds", "period_doubling_plot"]

#: ε/ε_pd at which the exact map's orbits are found (below and past the period doubling).
EXACT_FRACTIONS = (0.9, 1.05, 1.2, 1.5)
#: Most fractions of ε_pd at which the exact map's orbits are found for one θ0 (each a Newton solve on direct-ODE
#: steps, ``EXACT_ORBIT_SECONDS``; above ε_pd a period-2 orbit besides).
MAX_EXACT_FRACTIONS = 16
#: Most release angles of one diagram (a column each, 5 inches wide; each ε_pd is ``PERIOD_DOUBLING_SECONDS``).
MAX_DIAGRAM_THETA0 = 8
#: CPU seconds of the diagram's files (:func:`bifurcation_diagram`: PNG, PDF, CSV): the figure of one θ0 of 111
#: points 1.3 s measured.
FILES_SECONDS = 2.0


@dataclass(frozen=True)
class BifurcationData:
    """The orbits of one release angle.

    Attributes
    ----------
    theta0, eps_pd : the release angle and the exact map's ε_pd.
    fixed, unstable_fixed : the slow map's fixed points about the stable and the unstable axis.
    period2 : the slow map's period-2 branch (from just above its own ε_pd, 4/κ).
    exact_fixed, exact_period2 : the exact map's orbits at ``EXACT_FRACTIONS`` (period 2 above ε_pd only).
    slow_period2 : the slow map's period-2 orbits at the ε of ``exact_period2``, for the comparison.
    order : the slow map's order.
    """

    theta0: float
    eps_pd: float
    fixed: Branch
    unstable_fixed: Branch
    period2: Branch
    exact_fixed: tuple[PeriodicOrbit, ...]
    exact_period2: tuple[PeriodicOrbit, ...]
    slow_period2: tuple[PeriodicOrbit, ...]
    order: int


def check_diagram_counts(n_points: int, exact_fractions: Sequence[float]) -> None:
    """Refuse, before any work, a branch of ``n_points`` outside [3, ``MAX_BRANCH_POINTS``] or more than
    ``MAX_EXACT_FRACTIONS`` exact fractions (:func:`bifurcation_data`'s sizes), naming the parameter.

    Examples
    --------
    >>> from rocknroller.papers.bifurcation import check_diagram_counts
    >>> check_diagram_counts(111, (0.8, 1.2))
    >>> check_diagram_counts(2, ())
    Traceback (most recent call last):
    ...
    ValueError: n_points must be an integer in [3, 2000], got n_points=2
    """
    if int(n_points) != n_points or not 3 <= n_points <= MAX_BRANCH_POINTS:
        raise ValueError(f"n_points must be an integer in [3, {MAX_BRANCH_POINTS}], got n_points={n_points!r}")
    if len(exact_fractions) > MAX_EXACT_FRACTIONS:
        raise ValueError(f"exact_fractions must be at most MAX_EXACT_FRACTIONS = {MAX_EXACT_FRACTIONS} values (each an "
                         f"exact-map solve on direct-ODE steps), got {len(exact_fractions)}")


def bifurcation_seconds(body: Body, theta0s: Sequence[float], n_points: int = 111,
                        exact_fractions: Sequence[float] = EXACT_FRACTIONS, order: int = 1,
                        build: bool = True) -> float:
    """The estimated CPU seconds of :func:`bifurcation_data` at each θ0 of ``theta0s``
    (:mod:`rocknroller.numerics.budget`), found without building or running anything: per θ0 the exact map's ε_pd,
    one exact orbit per fraction (above ε_pd the period-2 orbit besides, counted twice), three slow branches of ``n_points``
    orbits and the slow period-2 orbit at each fraction above ε_pd (and the map's setup), and with ``build`` the tables not cached (the
    release table, and at ``order`` 2 the second-order table: :func:`rocknroller.analysis.slow.work.tables_seconds`).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> warm = bifurcation_seconds(body, [0.95 * math.pi], build=False)
    >>> print(bifurcation_seconds(body, [0.95 * math.pi], order=2) >= warm, f"{warm:.4g}")
    True 13.41
    """
    from rocknroller.analysis.slow.work import tables_seconds

    above = sum(float(f) > 1.0 for f in exact_fractions)
    per_theta0 = (PERIOD_DOUBLING_SECONDS + EXACT_ORBIT_SECONDS * (len(exact_fractions) + 2 * above)
                  + (3 * int(n_points) + above) * SLOW_ORBIT_SECONDS + MAP_SETUP_SECONDS)
    tables = tables_seconds(body, [float(t) for t in theta0s], order)[0] if build else 0.0
    return len(theta0s) * per_theta0 + tables


def _what(theta0s: Sequence[float], n_points: int, exact_fractions: Sequence[float], order: int) -> str:
    """What :func:`bifurcation_seconds` counts, for its message."""
    return (f"a bifurcation diagram at {len(theta0s)} theta0 (per theta0 the exact map's eps_pd, "
            f"{len(exact_fractions)} exact fractions, 3 slow branches of {int(n_points)} points of order {order}, "
            f"and the tables not cached)")


def bifurcation_data(body: Body, theta0: float, *, fractions: tuple[float, float] = (0.6, 1.55), n_points: int = 111,
                     exact_fractions: Sequence[float] = EXACT_FRACTIONS, order: int | None = None,
                     workers: int = 1, budget: float | None = WORK_BUDGET_SECONDS) -> BifurcationData:
    """The orbits of the diagram at θ0: the slow map's branches at ``n_points`` values of ε/ε_pd over ``fractions``
    (within K = εκ ≤ K_MAX), the exact map's at ``exact_fractions``; ``budget``: the CPU seconds it may take
    (:func:`bifurcation_seconds`, estimated before any work; None: no limit).

    Raises
    ------
    ValueError
        θ0 outside ``THETA0_RANGE``, ``n_points`` outside [3, ``MAX_BRANCH_POINTS``], more than
        ``MAX_EXACT_FRACTIONS`` exact fractions, ``fractions`` not 0 < lo < hi with hi past the slow map's period
        doubling K = 4 and K ≤ K_MAX at hi, an exact fraction outside (0, hi], or (``WorkBudgetError``) an estimated
        cost over ``budget``.
    """
    theta0 = check_map_theta0(theta0)
    order = default_order(theta0) if order is None else order  # the one default: 2 on the release tables
    check_diagram_counts(n_points, exact_fractions)
    check_work(bifurcation_seconds(body, [theta0], n_points, exact_fractions, order),
               _what([theta0], n_points, exact_fractions, order), budget)
    lo, hi = (float(f) for f in fractions)
    pd = period_doubling(body, theta0)
    K_pd = pd.eps_exact * pd.kappa  # K = eps*kappa at the exact map's period doubling
    if not (0.0 < lo < hi and K_PERIOD_DOUBLING < hi * K_pd <= K_MAX):
        raise ValueError(f"fractions (lo, hi) of eps_pd must satisfy 0 < lo < hi and "
                         f"{K_PERIOD_DOUBLING / K_pd:.4g} < hi <= {K_MAX / K_pd:.4g} (past the slow map's period "
                         f"doubling K = eps*kappa = {K_PERIOD_DOUBLING:g}, where the period-2 branch begins, and "
                         f"K <= {K_MAX:g}), got fractions={fractions!r}")
    if not all(0.0 < float(f) <= hi for f in exact_fractions):
        raise ValueError(f"exact_fractions must lie in (0, {hi:g}], got exact_fractions={exact_fractions!r}")
    eps = np.linspace(lo, hi, int(n_points)) * pd.eps_exact
    kw: dict[str, Any] = dict(order=order, workers=workers)
    fixed = continue_orbit(body, theta0, eps, 1, **kw)
    unstable = continue_orbit(body, theta0, eps, 1, axis="unstable", **kw)
    # the period-2 branch from 0.2 % above the slow map's own threshold (where its fixed point's residue passes 1)
    above = [o.eps for o in fixed.orbits if o.residue > 1.0]
    e_start = max(1.002 * min(above), eps[0]) if above else hi * pd.eps_exact
    period2 = continue_orbit(body, theta0, np.concatenate([[e_start], eps[eps > e_start]]), 2, **kw)
    exact_fixed = tuple(periodic_orbit(body, theta0, f * pd.eps_exact, 1, map="exact") for f in exact_fractions)
    exact_p2, slow_p2 = [], []
    for f in sorted(f for f in exact_fractions if f > 1.0):
        slow_p2.append(periodic_orbit(body, theta0, f * pd.eps_exact, 2, **kw))  # also the exact map's start
        exact_p2.append(periodic_orbit(body, theta0, f * pd.eps_exact, 2, map="exact", start=slow_p2[-1].points[0]))
    return BifurcationData(theta0=theta0, eps_pd=pd.eps_exact, fixed=fixed, unstable_fixed=unstable, period2=period2,
                           exact_fixed=exact_fixed, exact_period2=tuple(exact_p2), slow_period2=tuple(slow_p2),
                           order=order)


def _rows(d: BifurcationData) -> list[dict[str, Any]]:
    rows = []
    for kind, orbits in (("fixed_stable_axis", d.fixed.orbits), ("fixed_unstable_axis", d.unstable_fixed.orbits),
                         ("period2", d.period2.orbits), ("fixed_stable_axis", d.exact_fixed),
                         ("period2", d.exact_period2), ("period2_at_exact", d.slow_period2)):
        for o in orbits:
            for k in range(o.period):
                rows.append(dict(theta0=d.theta0, map=o.map, order=o.order, orbit=kind, eps=o.eps,
                                 eps_over_pd=o.eps / d.eps_pd, K=o.K, point=k, u=o.points[k, 0], v=o.points[k, 1],
                                 QR=o.Q[k, 0], QJ=o.Q[k, 1], Theta=o.points[k, 2], kick_phase=o.kick_phase[k],
                                 residue=o.residue, stable=int(o.stable), residual=o.residual))
    return rows


def _plot(axes: Any, d: BifurcationData) -> None:
    top, bottom = axes
    for branch, kind in ((d.fixed, "fixed_stable_axis"), (d.unstable_fixed, "fixed_unstable_axis"),
                         (d.period2, "period2")):
        for ax, what in ((top, "kick_phase"), (bottom, "residue")):
            branch.plot(ax, what, x_scale=d.eps_pd, color=BRANCH_STYLE[kind][0])
    for orbits, kind in ((d.exact_fixed, "fixed_stable_axis"), (d.exact_period2, "period2")):
        colour = BRANCH_STYLE[kind][0]
        for o in orbits:
            face = colour if o.stable else "none"
            top.plot([o.eps / d.eps_pd] * o.period, o.kick_phase, "o", mfc=face, mec="k", ms=6)
            bottom.plot(o.eps / d.eps_pd, o.residue, "o", mfc=face, mec="k", ms=6)
    top.set_xlabel("")  # the column's axes share ε/ε_pd, labelled below
    top.set_title(rf"$\theta_0 = {d.theta0 / math.pi:.3g}\pi$, $\varepsilon_{{pd}} = {d.eps_pd:.6g}$")
    top.set_ylabel(r"kick phase $\vartheta = \Theta + W(Q)/2$")
    top.set_ylim(-0.5 * math.pi, 1.5 * math.pi)
    bottom.axhline(0.0, color="0.6", lw=0.7)
    bottom.axhline(1.0, color="0.6", lw=0.7)
    bottom.set_ylim(-1.7, 1.8)
    bottom.set_ylabel("Greene's residue R")
    bottom.set_xlabel(r"$\varepsilon/\varepsilon_{pd}$")


#: Height of the legend strip below the panels (inches).
_LEGEND_INCHES = 0.9


def _legend_entries() -> tuple[list[Any], list[str]]:
    """Proxy artists and labels: the three branches by colour, stability by line style and marker fill."""
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color=colour, lw=1.4) for colour, _ in BRANCH_STYLE.values()]
    labels = [label for _, label in BRANCH_STYLE.values()]
    handles += [Line2D([], [], color="0.3", lw=1.4), Line2D([], [], color="0.3", lw=1.4, ls="--"),
                Line2D([], [], ls="", marker="o", mfc="0.3", mec="k", ms=6),
                Line2D([], [], ls="", marker="o", mfc="none", mec="k", ms=6)]
    labels += ["slow map, stable (0 < R < 1)", "slow map, unstable", "exact map (direct ODE), stable",
               "exact map (direct ODE), unstable"]
    return handles, labels


def bifurcation_figure(data: Sequence[BifurcationData]) -> Any:
    """The diagram of :func:`bifurcation_data` results: one column per θ0, the kick phase above and Greene's residue
    below; slow map lines (solid stable, dashed unstable; blue the stable axis's fixed point, green the unstable
    axis's, orange the period-2 orbit), exact map markers (filled stable, open unstable), and a legend saying so below
    the panels.  Returns the figure."""
    height = 7.0 + _LEGEND_INCHES
    fig = new_figure(figsize=(max(5.0 * len(data), 8.0), height))
    axes = fig.subplots(2, len(data), squeeze=False, sharex="col")
    fig.subplots_adjust(bottom=(0.55 + _LEGEND_INCHES) / height, top=1.0 - 0.75 / height, hspace=0.12)
    for j, d in enumerate(data):
        _plot(axes[:, j], d)
    handles, labels = _legend_entries()
    fig.legend(handles, labels, loc="lower center", ncol=2, fontsize=8, frameon=False,
               bbox_to_anchor=(0.5, 0.08 / height))
    fig.suptitle("Rocking near its period doubling: slow map (lines) and exact map (markers)")
    return fig


def bifurcation_diagram(body: Body, out_dir: str | Path, theta0s: Sequence[float] = (0.9 * math.pi, 0.95 * math.pi),
                        budget: float | None = WORK_BUDGET_SECONDS, scheduler: str | None = None,
                        threads: int | None = None, **kwargs: Any) -> tuple[list[Path], list[BifurcationData]]:
    """Compute (:func:`bifurcation_data`, ``kwargs``) and write ``bifurcation.png``, ``.pdf`` and ``.csv`` to
    ``out_dir`` (the figure: :func:`bifurcation_figure`).  Returns the paths and the data.

    The release tables of all ``theta0s`` not yet cached are built first, together
    (:func:`rocknroller.analysis.slow.map.tables_at_once.build_release_tables`), their nodes on the workers of the
    dask scheduler at ``scheduler``, on ``threads`` threads, or on ``kwargs["workers"]`` spawned processes (which
    also build order 2's second-order tables); the tables, and so the diagram, do not depend on where.

    Raises
    ------
    ValueError
        More than ``MAX_DIAGRAM_THETA0`` release angles, the limits of :func:`bifurcation_data`, or
        (``WorkBudgetError``) the estimated cost of all of them (:func:`bifurcation_seconds`) over ``budget``, before
        any work.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as out:
    ...     paths, data = rr.bifurcation_diagram(rr.Body.paper(), out, theta0s=[0.95 * math.pi], n_points=5,
    ...                                          exact_fractions=())
    ...     print([p.name for p in paths])
    ...
    ['bifurcation.png', 'bifurcation.pdf', 'bifurcation.csv']
    """
    if not 1 <= len(theta0s) <= MAX_DIAGRAM_THETA0:
        raise ValueError(f"theta0s must be 1 to MAX_DIAGRAM_THETA0 = {MAX_DIAGRAM_THETA0} release angles (a column of "
                         f"the figure each), got {len(theta0s)}")
    theta0s = [check_map_theta0(t) for t in theta0s]
    n_points, exact = kwargs.get("n_points", 111), kwargs.get("exact_fractions", EXACT_FRACTIONS)
    check_diagram_counts(n_points, exact)
    order = kwargs.get("order")
    order = max((default_order(float(t)) for t in theta0s), default=1) if order is None else order
    kwargs["order"] = order  # one order for every theta0 of the diagram, as the command's
    check_work(bifurcation_seconds(body, theta0s, n_points, exact, order) + FILES_SECONDS,
               _what(theta0s, n_points, exact, order), budget)
    where = {"scheduler": scheduler, "threads": threads} if (scheduler, threads) != (None, None) else \
        {"processes": kwargs.get("workers", 1)}
    if not energy_tables_cached(body):
        build_release_tables(body, theta0s, progress=False, budget=None, **where)  # the budget is checked above
    data = [bifurcation_data(body, t, budget=None, **kwargs) for t in theta0s]
    paths = save_figure(bifurcation_figure(data), out_dir, "bifurcation")
    rows = [r for d in data for r in _rows(d)]
    header = [f"body: {body.symmetric().describe()}, with I2 = (1 + eps) I1 at the eps of each row",
              f"slow map order {data[0].order if data else 1}; theta0: {', '.join(angle_text(d.theta0) for d in data)}",
              f"eps_pd (exact map): {', '.join(repr(float(d.eps_pd)) for d in data)}",
              f"kwargs: {kwargs!r}",
              "kick_phase = Theta + W(Q)/2 mod 2 pi in [-pi/2, 3 pi/2) (the standard map's angle); residue = (3 - tr M)/4; stable: 0 < R < 1"]
    paths.append(write_csv(Path(out_dir) / "bifurcation.csv", {k: [r[k] for r in rows] for k in rows[0]}, header))
    return paths, data


# ----------------------------------------------------------------------------- the period doubling over θ0
#: Most release angles of one period-doubling line (each its tables and a root of det(DF + 1): ~0.1 s with the
#: tables over energy, a table build per angle without them).
MAX_LINE_THETA0 = 400
#: CPU seconds of the line's root at order 2 per release angle, its tables ready (a few map Jacobians; 0.02-0.05 s
#: measured).
LINE_ROOT_SECONDS = 0.1


@dataclass(frozen=True)
class PeriodDoublingLine:
    """ε_pd(θ0) of the slow map over release angles.

    Attributes
    ----------
    theta0 : the release angles.
    kappa : κ of each (the release table's).
    eps_order1 : 4/|κ|, the first-order map's ε_pd (K = εκ = 4).
    eps_order2 : the root of det(DF + 1) of the second-order map's Jacobian at the stable rocking.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> line = rr.period_doubling_line(rr.Body.paper(), [0.95 * math.pi])
    >>> print(type(line).__name__, line.theta0.shape, f"{line.K_order2[0] - 4.0:+.1e}")
    PeriodDoublingLine (1,) -2.2e-04
    """

    theta0: np.ndarray
    kappa: np.ndarray
    eps_order1: np.ndarray
    eps_order2: np.ndarray

    @property
    def K_order2(self) -> np.ndarray:
        """ε_pd κ at order 2: 4 plus the second order's correction, O(ε_pd)."""
        return self.eps_order2 * np.abs(self.kappa)


def _line_angles(theta0: Any) -> np.ndarray:
    th = np.atleast_1d(np.asarray(theta0, dtype=float))
    if th.ndim != 1 or not 1 <= th.size <= MAX_LINE_THETA0:
        raise ValueError(f"theta0 must be 1 to MAX_LINE_THETA0 = {MAX_LINE_THETA0} release angles, got shape {th.shape}")
    return np.array([check_map_theta0(float(t)) for t in th])


def line_seconds(body: Body, theta0: Any, build: bool = True) -> float:
    """The estimated CPU seconds of :func:`period_doubling_line` over ``theta0``, without building anything: the
    tables not cached (first and second order, none where the tables over energy serve;
    :func:`rocknroller.analysis.slow.work.tables_seconds`), and per angle its tables made ready
    (``MAP_SETUP_SECONDS``) and the root (``LINE_ROOT_SECONDS``).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> print(f"{line_seconds(rr.Body.paper(), [0.9 * math.pi, 0.95 * math.pi], build=False):.2f}")
    1.00
    """
    from rocknroller.analysis.slow.work import tables_seconds

    th = _line_angles(theta0)
    tables = tables_seconds(body, th, 2)[0] if build else 0.0
    return tables + th.size * (MAP_SETUP_SECONDS + LINE_ROOT_SECONDS)


def period_doubling_line(body: Body, theta0: Any, *, budget: float | None = WORK_BUDGET_SECONDS,
                         progress: bool | None = None) -> PeriodDoublingLine:
    """ε_pd of rocking about the stable axis at each release angle of ``theta0`` (in ``THETA0_RANGE``, at most
    ``MAX_LINE_THETA0``): 4/κ of the first-order map and the second-order map's own root
    (:func:`rocknroller.analysis.slow.dynamics.period_doubling.map_period_doubling`), each on the tables of its
    release (:func:`~rocknroller.analysis.slow.map.tables_at_once.release_tables`: the tables over energy where they
    are cached, else built per angle); ``budget``: :func:`line_seconds`, checked before any work; ``progress``: a tqdm
    bar over the angles (None: only on a terminal).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> line = rr.period_doubling_line(rr.Body.paper(), [0.95 * math.pi])
    >>> print(f"{line.eps_order1[0]:.6f} {line.eps_order2[0]:.6f} K = {line.K_order2[0]:.4f}")
    0.009385 0.009384 K = 3.9998
    """
    from tqdm import tqdm

    th = _line_angles(theta0)
    check_work(line_seconds(body, th), f"the period-doubling line at {th.size} theta0 (its tables not cached, a root "
               "each)", budget)
    kappa, e2 = np.empty(th.size), np.empty(th.size)
    with tqdm(total=th.size, desc="period doubling over theta0", unit="theta0",
              disable=None if progress is None else not progress) as bar:
        for k, t in enumerate(th):
            kappa[k] = release_tables(body, float(t), 1)[0].kappa
            e2[k] = map_period_doubling(body, float(t), order=2)
            bar.update(1)
    return PeriodDoublingLine(theta0=th, kappa=kappa, eps_order1=4.0 / np.abs(kappa), eps_order2=e2)


def period_doubling_plot(body: Body, line: PeriodDoublingLine, out_dir: str | Path) -> list[Path]:
    """Write ``period_doubling.png``, ``.pdf`` (ε_pd against θ0/π at orders 1 and 2 above, K = ε_pd κ below) and
    ``period_doubling.csv`` (its header records the body and the tables) to ``out_dir``; returns the paths.

    Examples
    --------
    >>> import math, tempfile
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> line = rr.period_doubling_line(body, [0.9 * math.pi, 0.95 * math.pi])
    >>> with tempfile.TemporaryDirectory() as out:
    ...     print([p.name for p in rr.period_doubling_plot(body, line, out)])
    ['period_doubling.png', 'period_doubling.pdf', 'period_doubling.csv']
    """
    fig = new_figure(figsize=(7.0, 6.5))
    top, bottom = fig.subplots(2, 1, sharex=True)
    x = line.theta0 / math.pi
    top.semilogy(x, line.eps_order1, "C0--", label="order 1: 4/kappa")
    top.semilogy(x, line.eps_order2, "C1-", label="order 2: root of det(DF + 1)")
    top.set_ylabel("eps_pd = (I2 - I1)/I1 at the period doubling")
    top.legend(fontsize=8)
    bottom.plot(x, line.K_order2, "C1.-")
    bottom.axhline(K_PERIOD_DOUBLING, color="0.5", lw=0.8, ls=":")
    bottom.set_ylabel("K = eps_pd kappa (order 2)")
    bottom.set_xlabel("theta0 / pi (release from rest)")
    fig.suptitle(f"Period doubling of rocking about the stable axis over the release angle\n{body.symmetric().describe()}",
                 fontsize=9)
    paths = save_figure(fig, out_dir, "period_doubling")
    header = [f"body: {body.symmetric().describe()}, with I2 = (1 + eps) I1",
              "eps_order1 = 4/|kappa| (first-order map), eps_order2: the second-order map's root of det(DF + 1) at "
              "the stable rocking; K_order2 = eps_order2 |kappa|",
              f"tables: {'over energy' if energy_tables_cached(body) else 'per theta0'}"]
    paths.append(write_csv(Path(out_dir) / "period_doubling.csv",
                           {"theta0": line.theta0.tolist(), "theta0_over_pi": x.tolist(), "kappa": line.kappa.tolist(),
                            "eps_order1": line.eps_order1.tolist(), "eps_order2": line.eps_order2.tolist(),
                            "K_order2": line.K_order2.tolist()}, header))
    return paths
