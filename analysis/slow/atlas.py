"""Recession atlas: the slow motion over a plane of starts, by the averaged map or the direct ODE.  It holds the
atlas of releases from rest (:func:`atlas_from_rest`) and of initial rates (:func:`atlas_of_rates`), their result
:class:`Atlas`, the reversal counts per 1000 time units, crossings of the critical lines Q_J,0^crit and Q_J,π^crit
(:func:`reversal_counts`; paper eqs. QJcrit_0, QJcrit_pi).  The check of a map-made atlas by the direct ODE
(:func:`~rocknroller.analysis.slow.atlas_check.confirm_atlas`) is :mod:`rocknroller.analysis.slow.atlas_check`.

Two planes: releases from rest over (ψ0, θ0) (:func:`atlas_from_rest`, by the map, or by the ODE), and initial rates
(φ̇0, ψ̇0) at fixed θ0, ψ0 (:func:`atlas_of_rates`, the plane of the paper's reversal starts, by the ODE: each
of its starts has its own energy, and the map's tables are per energy).

For each release angle θ0 the map runs on the tables of that release
(:func:`rocknroller.analysis.slow.map.tables_at_once.release_tables` in ``THETA0_RANGE``: the tables over energy where
they are cached for the body, else the release table and at order 2 the second-order table of θ0; below it the region
tables of the release's energy), so a row of ψ0 costs its tables and a small fraction of a direct run a point.  Its
order (:func:`atlas_order`) is 2 where the tables over energy (``rocknroller warm --tables``) cover every row, else 1
(a second-order table would cost each row ~10 s; docs/performance.md); ``order`` asks for either.  Each point gives
the slow period of Θ = 2ψ, the azimuth span Φ, the Q_R and Q_J extents and the full-angle (Q_J,0^crit) and
visible-angle (Q_J,π^crit) reversals per 1000 time units: crossings of the critical lines by the maxima's (Q_R,
Q_J), as :func:`rocknroller.analysis.slow.prediction_result.critical_regions` counts them for the map and the ODE.
A sample of the points (and any the caller names) is run by the direct ODE as an ensemble
(:func:`rocknroller.numerics.ensembles.ensemble.run_ensemble`: the same numbers bit for bit wherever it runs), and the
map's relative errors there are returned beside the atlas.

Order and chaos.  A map-made release atlas also carries, by default, the map's chaos indicators at every point
(``CHAOS_OBSERVABLES``): MEGNO and the finite-time Lyapunov exponent per unit time over the span ``slow`` uses for the
same start, max(t_end, 1000 rocks) (:func:`~rocknroller.analysis.slow.dynamics.chaos.indicator_span`: a start taken
from an atlas row gets the same MEGNO and verdict from ``predict_slow_motion`` at the atlas's order, to the bit), by
:func:`rocknroller.analysis.slow.dynamics.chaos.map_indicators` (the tangent vector ``predict_slow_motion`` carries,
~1.5-1.8x the map's cost: benchmarks/bench_chaos_map.py), masked where a run has fewer than
:data:`~rocknroller.numerics.megno.MIN_SAMPLES` maxima; :attr:`Atlas.regular` is MEGNO ≤
:data:`~rocknroller.numerics.megno.MEGNO_CHAOTIC` = 3.  ``confirm_atlas`` checks that layer at its sample against
the direct motion's indicators over the same span (:func:`rocknroller.numerics.variational.direct_chaos_indicators`,
on ``threads`` threads of this process) and reports where the verdicts agree.  An atlas made by the ODE has no chaos
layer (``direct_chaos_indicators`` gives it for any start).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import RATE_MAX, EulerState
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.map.limits import ANGLE_MAX
from rocknroller.numerics.budget import WORK_BUDGET_SECONDS, check_work
from rocknroller.numerics.megno import MEGNO_CHAOTIC
from rocknroller.numerics.parallel import check_processes, map_blocks

if TYPE_CHECKING:
    import pandas

__all__ = [
    "ATLAS_OBSERVABLES", "CHAOS_OBSERVABLES", "PLANES", "METHODS", "MAX_ATLAS_POINTS", "MAX_ODE_ATLAS_POINTS", "Atlas",
    "reversal_counts", "atlas_from_rest", "atlas_of_rates", "atlas_seconds", "atlas_order", "FILES_SECONDS",
    "FILES_SECONDS_PER_POINT"
]


def atlas_order(body: Body, theta0: ArrayLike) -> int:
    """The default order in ε of a map-made release atlas over the rows ``theta0``: 2 where the tables over energy of
    the body are cached and cover every row (``THETA0_RANGE``), else 1 (module docstring); every output of the atlas
    names its order.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> atlas_order(rr.Body.paper(1e-3), [0.5 * math.pi, 0.9 * math.pi])  # a row below the release tables' range
    1
    """
    from rocknroller.analysis.slow.map.tables_at_once import energy_tables_cached

    th = np.atleast_1d(np.asarray(theta0, float))
    covered = bool(np.all((th >= av.THETA0_RANGE[0]) & (th <= av.THETA0_RANGE[1])))
    return 2 if covered and energy_tables_cached(body) else 1

#: What the atlas maps, per point: the map's diagnostics and the reversals per 1000 time units.
ATLAS_OBSERVABLES = ("slow_period", "Phi", "QR_extent", "QJ_extent", "full_reversals", "visible_reversals")
#: The chaos layer of a map-made release atlas (module docstring): the map's MEGNO and its finite-time Lyapunov
#: exponent per unit time.
CHAOS_OBSERVABLES = ("megno", "lyapunov")
#: Most points of one atlas (≈ 1 ms and 48 bytes each once the tables are cached).
MAX_ATLAS_POINTS = 250_000


def reversal_counts(crossings: Sequence[tuple[float, str, str, str]] | None, t_end: float) -> tuple[float, float]:
    """(full-angle, visible-angle) reversals per 1000 time units: crossings of Q_J,0^crit and of Q_J,π^crit."""
    lines = [c[3] for c in crossings or []]
    scale = 1000.0 / t_end
    return (scale * sum("QJ0crit" in s for s in lines), scale * sum("QJpicrit" in s for s in lines))


def _values(pred: Any, t_end: float, chaos: bool) -> list[float | None]:
    full, visible = reversal_counts(pred.crossings, t_end)
    out = [pred.slow_period, pred.Phi, pred.QR_extent, pred.QJ_extent, full, visible]
    if chaos:
        ch = pred.chaos
        out += [None, None] if ch is None else [ch.megno, ch.lyapunov]
    return out


#: The planes of starts an atlas covers: the initial values along its rows and its columns.
PLANES = {"release": ("theta0", "psi0"), "rates": ("psi_dot0", "phi_dot0")}
#: How an atlas computes each point: the averaged map, or the direct ODE.
METHODS = ("map", "ode")


@dataclass(frozen=True)
class Atlas:
    """The slow-motion diagnostics over a plane of starts.

    Attributes
    ----------
    eps, t_end : the body's asymmetry and the time span of each run.
    plane : ``"release"`` (rows θ0, columns ψ0, released from rest) or ``"rates"`` (rows ψ̇0, columns φ̇0, at the
        fixed tilt and spin angle ``at`` with θ̇0 = 0, φ0 = 0).
    rows, cols : the grid's values along the rows and the columns (``PLANES[plane]`` names them).
    at : (θ0, ψ0) of a ``"rates"`` plane; None for ``"release"``.
    method : ``"map"`` (the averaged map) or ``"ode"`` (the direct ODE at every point).
    order : the map's order in ε (:func:`atlas_order`); None for an atlas made by the ODE.
    values : dict
        For each of ``ATLAS_OBSERVABLES`` (and, for a map-made atlas with its chaos layer, ``CHAOS_OBSERVABLES``), a
        masked array (len(rows), len(cols)); masked where the quantity is undefined (the slow period of a run with
        fewer than two crossings of its mean; the indicators of a run with fewer than ``MIN_SAMPLES`` maxima, or of
        pure rocking at ε = 0).
    warnings : the distinct validity warnings of the predictions (e.g. K = ε κ > 4, coarse region tables).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> atlas = rr.atlas_from_rest(body, [0.95 * math.pi], [0.3, 0.8], 200.0)
    >>> print(atlas.plane, atlas.method, atlas.observables[-2:], atlas.values["megno"].shape)
    release map ('megno', 'lyapunov') (1, 2)
    """

    eps: float
    t_end: float
    plane: str
    rows: NDArray[np.float64]
    cols: NDArray[np.float64]
    values: dict[str, np.ma.MaskedArray] = field(repr=False)
    at: tuple[float, float] | None = None
    method: str = "map"
    warnings: tuple[str, ...] = ()
    order: int | None = None

    @property
    def observables(self) -> tuple[str, ...]:
        """The names of the layers in ``values``: ``ATLAS_OBSERVABLES``, then ``CHAOS_OBSERVABLES`` if it has them."""
        return ATLAS_OBSERVABLES + (CHAOS_OBSERVABLES if "megno" in self.values else ())

    @property
    def regular(self) -> np.ma.MaskedArray:
        """The map's verdict at each point, MEGNO ≤ ``MEGNO_CHAOTIC`` (regular) or not, masked where MEGNO is.

        Raises
        ------
        ValueError
            An atlas without the chaos layer (made by the ODE, or with ``chaos=False``).
        """
        if "megno" not in self.values:
            raise ValueError("this atlas has no chaos layer (made by the ODE, or by the map with chaos=False): "
                             "make it with atlas_from_rest(..., method='map', chaos=True)")
        return self.values["megno"] <= MEGNO_CHAOTIC

    @property
    def row_name(self) -> str:
        """The initial value along the rows: ``"theta0"`` or ``"psi_dot0"``."""
        return PLANES[self.plane][0]

    @property
    def col_name(self) -> str:
        """The initial value along the columns: ``"psi0"`` or ``"phi_dot0"``."""
        return PLANES[self.plane][1]

    def to_dataframe(self) -> "pandas.DataFrame":
        """One row per grid point: its row and column values and the observables, missing where masked (pandas)."""
        from rocknroller.analysis.model.frames import dataframe

        R, C = np.meshgrid(self.rows, self.cols, indexing="ij")
        return dataframe({self.row_name: R, self.col_name: C, **{n: self.values[n] for n in self.observables}})

    def plot(self, fig: Any = None) -> Any:
        """The observables on ``fig`` (a new pyplot figure of
        :func:`~rocknroller.analysis.slow.dynamics.atlas_figure.atlas_figsize` without one) as heat maps over the plane
        or lines along a single row or column, the figure of ``rocknroller atlas``: panels titled in words, colour bars
        labelled with units, MEGNO on the fixed scale [0, ``MEGNO_CLIP``]
        (:func:`~rocknroller.analysis.slow.dynamics.atlas_figure.atlas_figure`).  Returns the figure.

        Examples
        --------
        >>> import math, matplotlib.figure, rocknroller as rr
        >>> atlas = rr.atlas_from_rest(rr.Body.paper(1e-3), [0.95 * math.pi], [0.3, 0.8], 200.0)
        >>> fig = atlas.plot(matplotlib.figure.Figure(figsize=(17, 7.5), layout="constrained"))
        >>> print(fig.axes[4].get_title(), "|", fig.axes[4].get_ylabel())
        full-angle reversals | per 1000 time units
        """
        from rocknroller.analysis.slow.dynamics.atlas_figure import atlas_figure

        return atlas_figure(self, fig)

    def state(self, i: int, j: int) -> EulerState:
        """The initial state of grid point (row i, column j)."""
        if self.plane == "release":
            return EulerState(float(self.rows[i]), 0.0, float(self.cols[j]))
        assert self.at is not None
        return EulerState(self.at[0], 0.0, self.at[1], 0.0, float(self.cols[j]), float(self.rows[i]))


def _check_grid(name: str, values: ArrayLike, lo: float, hi: float) -> NDArray[np.float64]:
    a = np.atleast_1d(np.asarray(values, float))
    if a.ndim != 1 or a.size == 0 or not np.all(np.isfinite(a)) or np.any((a < lo) | (a > hi)):
        raise ValueError(f"{name} must be a non-empty 1-D grid of finite values in [{lo:.6g}, {hi:.6g}], got {values!r}")
    return a


def _rows(body: Body, theta0: NDArray[np.float64], psi0: NDArray[np.float64], t_end: float, build: bool,
          chaos: bool, order: int) -> tuple[NDArray[np.float64], NDArray[np.bool_], list[str]]:
    """The map's observables (len(names), len(theta0), len(psi0)), names ``ATLAS_OBSERVABLES`` and, with ``chaos``,
    ``CHAOS_OBSERVABLES``, where they are undefined, and the validity warnings, for some rows of a release atlas (in
    this process), at ``order``; the indicators over ``predict_slow_motion``'s own span."""
    from rocknroller.analysis.slow.map.tables_at_once import release_tables

    out = np.zeros((len(ATLAS_OBSERVABLES) + (len(CHAOS_OBSERVABLES) if chaos else 0), theta0.size, psi0.size))
    mask = np.zeros_like(out, dtype=bool)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", av.AveragingValidityWarning)
        for i, t0 in enumerate(theta0):
            table, second = ((None, None) if av.releases_on_region_tables(t0) else
                             release_tables(body, float(t0), order, build=build))
            for j, p0 in enumerate(psi0):
                pred = av.predict_slow_motion(body, float(t0), float(p0), t_end, table=table, second=second,
                                              build=build, order=order, indicators=chaos)
                for k, v in enumerate(_values(pred, t_end, chaos)):
                    mask[k, i, j] = v is None
                    out[k, i, j] = 0.0 if v is None else v
    return out, mask, [str(w.message) for w in caught if issubclass(w.category, av.AveragingValidityWarning)]


def _ode_values(body: Body, states: Sequence[EulerState], t_end: float, scheduler: str | None, workers: int | None,
                threads: int | None, progress: bool | None,
                budget: float | None) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """The direct ODE's observables (len(ATLAS_OBSERVABLES), len(states)) and where they are undefined, the runs
    made as one ensemble (:func:`rocknroller.numerics.ensembles.ensemble.run_ensemble`); the reversals are the crossings of the
    critical lines by the maxima's (Q_R, Q_J), counted as for the map."""
    from rocknroller.numerics.ensembles.ensemble import Job, run_ensemble

    runs = run_ensemble([Job(body, s, t_end) for s in states], scheduler=scheduler, workers=workers,
                        threads=threads, progress=progress, budget=budget)
    out = np.zeros((len(ATLAS_OBSERVABLES), len(runs)))
    mask = np.zeros_like(out, dtype=bool)
    sym = body.symmetric()
    for r, run in enumerate(runs):
        m = run.maxima
        full, visible = reversal_counts(av.critical_regions(m.QR, m.QJ, m.t, sym)[2], t_end)
        for k, v in enumerate((run.slow_period, run.Phi, run.QR_extent, run.QJ_extent, full, visible)):
            mask[k, r] = v is None
            out[k, r] = 0.0 if v is None else v
    return out, mask


def _check_size(n_rows: int, n_cols: int, limit: int, what: str) -> None:
    if n_rows * n_cols > limit:
        raise ValueError(f"the atlas has {n_rows} x {n_cols} = {n_rows * n_cols} points, more than {what} = {limit}")


def _ode_atlas(body: Body, plane: str, rows: NDArray[np.float64], cols: NDArray[np.float64],
               at: tuple[float, float] | None, t_end: float, scheduler: str | None, workers: int | None,
               threads: int | None, progress: bool | None, budget: float | None) -> Atlas:
    """Every point of the grid by the direct ODE (the states are checked, by ``Job``, before any run)."""
    _check_size(rows.size, cols.size, MAX_ODE_ATLAS_POINTS, "MAX_ODE_ATLAS_POINTS")
    grid = Atlas(eps=body.epsilon, t_end=float(t_end), plane=plane, rows=rows, cols=cols, values={}, at=at,
                 method="ode")
    states = [grid.state(i, j) for i in range(rows.size) for j in range(cols.size)]
    out, mask = _ode_values(body, states, float(t_end), scheduler, workers, threads, progress, budget)
    shape = (rows.size, cols.size)
    return replace(grid, values={name: np.ma.MaskedArray(out[k].reshape(shape), mask[k].reshape(shape))
                                 for k, name in enumerate(ATLAS_OBSERVABLES)})


#: Most points of an atlas made by the direct ODE (≈ 16 ms a run of 1000 time units at θ0 = 0.95π, ≈ 0.2 s at
#: small amplitude; its maxima, 136 bytes each, are held until the run's diagnostics are taken).
MAX_ODE_ATLAS_POINTS = 20_000


#: CPU seconds of an atlas's files (``rocknroller atlas``: its CSV and figures) besides its points: ~3.5 s measured (an
#: atlas of 40 points: the command's 6.6 s less its two tables and its confirmation; benchmarks/bench_budget.py).
FILES_SECONDS = 5.0
#: The same per point of the grid: ~3e-4 s inferred (an atlas of 3000 points: the command's 19.2 s less its runs and
#: its confirmation), not measured apart.
FILES_SECONDS_PER_POINT = 5.0e-4


def atlas_seconds(body: Body, theta0: ArrayLike, n_psi0: int, t_end: float, *, chaos: bool = True,
                  build: bool = True, files: bool = False, order: int | None = None) -> tuple[float, str]:
    """The estimated CPU seconds of a map-made release atlas (:func:`atlas_from_rest`) over the rows ``theta0`` and
    ``n_psi0`` columns, and a phrase saying what they count (:mod:`rocknroller.numerics.budget`), without building or
    running anything: with ``build`` the tables not cached (one per θ0: a release table, or below ``THETA0_RANGE`` the
    region tables of the release's energy, at ``order`` 2 the second-order tables, none where the tables over energy
    serve; :func:`rocknroller.analysis.slow.work.tables_seconds`), every point's run of the map of ``order``
    (None: :func:`atlas_order`) over t_end, or with its tangent vector if ``chaos`` over the indicators' span
    (:func:`rocknroller.analysis.slow.work.map_runs_seconds`, ``ATLAS_POINT_SECONDS`` a point besides), and with
    ``files`` the command's CSV and figures (``FILES_SECONDS``, ``FILES_SECONDS_PER_POINT``).

    Raises
    ------
    ValueError
        t_end not a finite number > 0.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> plain, _ = atlas_seconds(body, [0.95 * math.pi], 100, 1000.0, chaos=False, build=False)
    >>> chaos, what = atlas_seconds(body, [0.95 * math.pi], 100, 1000.0, build=False)
    >>> print(chaos > plain, "|", what.split(" (")[0])
    True | the atlas's 100 points
    """
    from rocknroller.analysis.slow.work import map_runs_seconds, tables_seconds
    from rocknroller.numerics.budget import ATLAS_POINT_SECONDS

    t_end = float(t_end)
    if not 0.0 < t_end < np.inf:  # also NaN; each run checks its own upper limit
        raise ValueError(f"t_end must be a finite number > 0, got t_end={t_end!r}")
    th = np.atleast_1d(np.asarray(theta0, float))
    order = atlas_order(body, th) if order is None else _check_order(order)
    tables, built = tables_seconds(body, th, order) if build else (0.0, "no tables to build")
    runs, n_max = map_runs_seconds(body, th, n_psi0, t_end, order, tangent=chaos, indicator_span=chaos,
                                   per_run=ATLAS_POINT_SECONDS)
    n = th.size * n_psi0
    output = FILES_SECONDS + n * FILES_SECONDS_PER_POINT if files else 0.0
    what = (f"the atlas's {n} points ({built}; {n} map runs of order {order} over t_end = {t_end:g}"
            f"{' with their tangent vectors (the chaos layer)' if chaos else ''}, about {n_max:.2g} theta-maxima"
            f"{'; its CSV and figures' if files else ''})")
    return tables + runs + output, what


def _check_order(order: Any) -> int:
    """``order`` if it is 1 or 2, else a ValueError naming it."""
    if order not in (1, 2) or isinstance(order, bool):
        raise ValueError(f"order must be 1 or 2 (or None: atlas_order), got order={order!r}")
    return int(order)


def _check_method(method: str) -> str:
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got method={method!r}")
    return method


def atlas_from_rest(body: Body, theta0: ArrayLike, psi0: ArrayLike, t_end: float = 1000.0, *,
                    method: str = "map", progress: bool | None = None, build: bool = True, processes: int = 1,
                    scheduler: str | None = None, workers: int | None = None,
                    threads: int | None = None, budget: float | None = WORK_BUDGET_SECONDS,
                    chaos: bool | None = None, order: int | None = None) -> Atlas:
    """Map the slow motion over the releases from rest at every (θ0, ψ0) of the grid (module docstring).

    Parameters
    ----------
    body : Body
        The asymmetric body (ε = body.epsilon).
    theta0 : array_like
        Release tilts, 0 < θ0 ≤ ``THETA0_RANGE[1]`` (0.999π).
    psi0 : array_like
        Spin angles (any finite values; ψ0 and ψ0 + π give the same motion).
    t_end : float
        Time span of each run (``predict_slow_motion``'s limits, or ``simulate``'s for the ODE).
    method : {"map", "ode"}
        The averaged map at every point (at most ``MAX_ATLAS_POINTS``), or the direct ODE at every point as one
        ensemble (at most ``MAX_ODE_ATLAS_POINTS``).
    progress : bool or None
        A tqdm bar over the rows, or over the ODE runs (None: only on a terminal).
    build : bool
        Build the tables that are not cached (else ValueError); the map only.
    processes : int
        Processes that share the map's rows, 1 ≤ processes ≤ ``parallel.MAX_PROCESSES`` (each point is computed the same
        way wherever it runs; more than one starts "spawn" processes, which import the calling script: guard a
        script's top level with ``if __name__ == "__main__":``).
    scheduler, workers, threads
        Where the ODE's runs go (method "ode"), as for :func:`rocknroller.numerics.ensembles.ensemble.run_ensemble`;
        for the map, where the release tables of the rows not yet cached are built, the nodes of all of them on that
        scheduler at once (:func:`rocknroller.analysis.slow.map.tables_at_once.build_release_tables`: the tables are
        the same bit for bit wherever they are built) before the rows run.
    budget : float or None
        CPU seconds the atlas may take (:mod:`rocknroller.numerics.budget`; None: no limit), estimated before any
        work: for the map all of it together (:func:`atlas_seconds`: the tables not cached, the runs' θ-maxima with
        the chaos layer's tangent vectors, each point's overhead); for the ODE, the runs' radians.
    chaos : bool or None
        The map: add the chaos layer, ``CHAOS_OBSERVABLES`` (module docstring; the map's tangent vector, ~1.5-1.8x the
        map's cost without it); None: True for the map, False for the ODE (an atlas made by the ODE has no chaos
        layer: True is refused there).
    order : 1, 2 or None
        The map's order in ε; None: :func:`atlas_order` (2 where the tables over energy cover every row, else 1).

    Raises
    ------
    ValueError
        A grid out of range or larger than its method's limit, or an estimated cost over ``budget`` (before
        anything is built or run), naming it.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> atlas = rr.atlas_from_rest(body, [0.95 * math.pi], [0.3, 0.8], 200.0, order=1)
    >>> print(atlas.values["Phi"].shape, [f"{v:.4f}" for v in atlas.values["Phi"][0]])
    (1, 2) ['2.3971', '1.4716']
    """
    th = _check_grid("theta0", theta0, np.nextafter(0.0, 1.0), av.THETA0_RANGE[1])
    ps = _check_grid("psi0", psi0, -ANGLE_MAX, ANGLE_MAX)
    if chaos is not None and not isinstance(chaos, bool):
        raise ValueError(f"chaos must be True, False or None, got chaos={chaos!r}")
    if _check_method(method) == "ode":
        if chaos:
            raise ValueError("chaos=True needs method='map': an atlas made by the direct ODE has no chaos layer "
                             "(give chaos=False; rocknroller.numerics.variational.direct_chaos_indicators gives the "
                             "ODE's MEGNO of any start, and confirm_atlas checks the map's layer against it)")
        return _ode_atlas(body, "release", th, ps, None, t_end, scheduler, workers, threads, progress, budget)
    _check_size(th.size, ps.size, MAX_ATLAS_POINTS, "MAX_ATLAS_POINTS")
    chaos = chaos is not False
    order = atlas_order(body, th) if order is None else _check_order(order)
    processes = check_processes(processes, "processes")
    check_work(*atlas_seconds(body, th, ps.size, t_end, chaos=chaos, build=build, order=order), budget)  # before work
    if build:
        from rocknroller.analysis.slow.map import tables_at_once as ta

        if (scheduler, workers, threads) != (None, None, None) and not ta.energy_tables_cached(body):
            builder = ta.build_second_order_tables if order == 2 else ta.build_release_tables
            builder(body, [t0 for t0 in th if not av.releases_on_region_tables(t0)], scheduler=scheduler,
                    workers=workers, threads=threads, progress=progress, budget=None)  # checked above
    blocks = np.array_split(np.arange(th.size), min(processes, th.size) if processes > 1 else th.size)
    parts = map_blocks(_rows, [(body, th[rows], ps, float(t_end), build, chaos, order) for rows in blocks],
                       [b.size for b in blocks],
                       processes=processes, desc="atlas rows", unit="theta0", progress=progress)
    out = np.concatenate([p[0] for p in parts], axis=1)
    mask = np.concatenate([p[1] for p in parts], axis=1)
    caught_all = [msg for p in parts for msg in p[2]]
    names = ATLAS_OBSERVABLES + (CHAOS_OBSERVABLES if chaos else ())
    return Atlas(eps=body.epsilon, t_end=float(t_end), plane="release", rows=th, cols=ps,
                 values={name: np.ma.MaskedArray(out[k], mask[k]) for k, name in enumerate(names)},
                 warnings=tuple(dict.fromkeys(caught_all)), order=order)


def atlas_of_rates(body: Body, theta0: float, psi0: float, phi_dot0: ArrayLike, psi_dot0: ArrayLike,
                   t_end: float = 1000.0, *, method: str = "ode", progress: bool | None = None,
                   scheduler: str | None = None, workers: int | None = None, threads: int | None = None,
                   budget: float | None = WORK_BUDGET_SECONDS) -> Atlas:
    """The slow motion over a plane of initial rates (φ̇0, ψ̇0) at fixed θ0, ψ0 (θ̇0 = 0, φ0 = 0): the plane of
    the paper's reversal starts (figs. 7–11: θ0 = 0.95π, ψ0 = π/4), by the direct ODE at every point.

    Each start of the plane has its own energy, and the averaged map's tables are per (body, energy): the map
    would need a table for every point (each far dearer than a direct run: docs/performance.md), and at the paper's θ0 = 0.95π its tables do not yet reach
    the accuracy an atlas needs near Q_J,π^crit (docs/averaging.md), so ``method`` accepts "ode" only, and says so.

    Parameters
    ----------
    body : Body
        The body.
    theta0, psi0 : float
        The fixed tilt, 0 < θ0 < π, and spin angle (finite).
    phi_dot0, psi_dot0 : array_like
        The grid's columns and rows: finite rates within ``EulerState``'s bound.
    t_end, progress, scheduler, workers, threads, budget
        As for :func:`atlas_from_rest` with method "ode".

    Raises
    ------
    ValueError
        A method other than "ode", a grid out of range or larger than ``MAX_ODE_ATLAS_POINTS``, or a start with no
        motion (before any run), naming it.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> atlas = rr.atlas_of_rates(body, 0.95 * math.pi, math.pi / 4, [0.0, 0.1], [0.0], 100.0)
    >>> print(atlas.plane, atlas.values["Phi"].shape)
    rates (1, 2)
    """
    if _check_method(method) != "ode":
        raise ValueError("method must be 'ode' for a plane of rates: each start has its own energy and the map's "
                         "tables are per (body, energy) (atlas_from_rest maps releases from rest with the map)")
    th = float(_check_grid("theta0", [theta0], np.nextafter(0.0, 1.0), np.nextafter(np.pi, 0.0))[0])
    ps = float(_check_grid("psi0", [psi0], -ANGLE_MAX, ANGLE_MAX)[0])
    pd = _check_grid("phi_dot0", phi_dot0, -RATE_MAX, RATE_MAX)
    sd = _check_grid("psi_dot0", psi_dot0, -RATE_MAX, RATE_MAX)
    return _ode_atlas(body, "rates", sd, pd, (th, ps), t_end, scheduler, workers, threads, progress, budget)
