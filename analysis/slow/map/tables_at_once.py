"""The release tables of many energies at once, and the tables over energy.

A scan over the release angle θ0 (an atlas's rows, a bifurcation diagram) needs one release table per θ0.
:func:`build_release_tables` builds those not yet cached together: each table's chart and symmetric orbits
(quadratures) in this process, then the node blocks of all of them (one variational orbit per node) on one scheduler
of :func:`rocknroller.numerics.ensembles.blocks.run_blocks` (threads, spawned processes, a local or remote
dask.distributed cluster); each table is fitted and checked from its own nodes in its own order, as ``build_table``
fits it, and cached as ``load_or_build_table`` caches it.  A node's numbers depend only on the node (the lanes are
independent; :func:`~rocknroller.numerics.ensembles.ensemble.cluster_map` checks the workers' versions), so the tables
are the one-process build's bit for bit (tests/analysis/slow/map/test_tables_at_once.py).
:func:`build_second_order_tables` does the same for the second-order tables, after their release tables.

Tables over energy (:class:`EnergyTables`, :func:`build_energy_tables`, :func:`load_energy_tables`): one build per
body serves every θ0 of ``THETA0_RANGE``.  A release table's drifts T_θ, W, Δφ on its chart come from quadratures
(0.07 s); its cost is the ε-responses at its nodes (a variational orbit each, 0.5 s a table) and, at order 2, k₂
(8 s).  Those, with the kick at rest that orients each chart, are tabulated at Chebyshev nodes in s = log(π − θ0),
their growth towards π (k₂ ~10⁵) divided out as a power law of π − θ0 fitted to each function's size, and
interpolated by the barycentric formula (Berrut & Trefethen, SIAM Rev. 46, 2004).  At any θ0 the release table is
fitted (:func:`~rocknroller.analysis.slow.map.table.fit_reduced`) from its drifts and the interpolated responses,
reduced by the part that the second half-drift carries, which near π is most of the Θ, t and φ responses
(:func:`~rocknroller.analysis.slow.map.table.reduce_responses`), and k₂'s coefficients are interpolated on its chart.
:func:`release_tables` gives the tables of a release: over energy where they are cached for the body, else per θ0.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map.chart import SecondOrderTable, SlowMapTable, cheb_nodes
from rocknroller.analysis.slow.map.limits import THETA0_RANGE, check_map_theta0
from rocknroller.analysis.slow.map.second_order import (build_second_order_table, check_k2_nu, fit_k2, k2_block,
                                                        k2_blocks, k2_check_error, k2_spec,
                                                        load_or_build_second_order_table)
from rocknroller.analysis.slow.map.table import (TableNotCachedError, assemble_nodes, build_table, cached_table,
                                                 check_grid, fit_reduced, fit_release_table, is_cached,
                                                 load_or_build_table, node_block, node_blocks, nodes_done,
                                                 reduce_responses, release_frame, store_table)
from rocknroller.numerics.budget import RELEASE_TABLE_SECONDS, WORK_BUDGET_SECONDS, check_work
from rocknroller.numerics.cache import MemoryCache
from rocknroller.numerics.ensembles.blocks import run_blocks
from rocknroller.numerics.ensembles.ensemble import check_cluster
from rocknroller.numerics.parallel import check_processes

__all__ = ["MAX_TABLES", "build_release_tables", "build_second_order_tables", "EnergyTables", "build_energy_tables",
           "load_energy_tables", "release_tables", "ENERGY_NODES_FIRST", "ENERGY_NODES_SECOND", "energy_tables_cached",
           "kick_error", "k2_error"]

#: Most release angles of one call (each table ~0.1 MB in memory at the default grid).
MAX_TABLES = 1000
#: Nodes of the default release grid (nu × nv = 128 × 6), which ``RELEASE_TABLE_SECONDS`` was measured on.
_DEFAULT_NODES = 128 * 6


def build_release_tables(body: Body, theta0: ArrayLike, *, scheduler: str | None = None, workers: int | None = None,
                         threads: int | None = None, processes: int | None = None, progress: bool | None = None,
                         use_cache: bool = True, budget: float | None = WORK_BUDGET_SECONDS,
                         **grid: Any) -> list[SlowMapTable]:
    """The release tables of (body, θ0) for every θ0 given, those not cached built together (module docstring).

    Parameters
    ----------
    body : Body
        Its symmetric part is used (the tables do not depend on ε).
    theta0 : array_like
        Release angles, each in ``THETA0_RANGE``; at most ``MAX_TABLES``.  Repeated angles are built once.
    scheduler, workers, threads, processes : optional, at most one
        Where the nodes run (:func:`rocknroller.numerics.ensembles.blocks.run_blocks`): the workers of the dask
        scheduler at this TCP address; a local dask.distributed cluster of this many worker processes; this many
        threads of this process; this many "spawn" processes (which import the calling script: guard its top level
        with ``if __name__ == "__main__":``).  None of them: a loop in this process.  The tables do not depend on it.
    progress : bool or None
        A tqdm bar over all the nodes (None: only if stderr is a terminal).
    use_cache : bool
        Read and write the disk cache, as :func:`rocknroller.analysis.slow.map.table.load_or_build_table`.
    budget : float or None
        CPU seconds the builds may take together (:mod:`rocknroller.numerics.budget`; None: no limit), estimated
        before any work from ``RELEASE_TABLE_SECONDS`` per table, scaled by its nodes; however many workers share them.
    grid : keyword arguments of :func:`rocknroller.analysis.slow.map.table.build_table` (nu, nv, u_factor, v_ratio).

    Returns
    -------
    list of SlowMapTable
        One per θ0, in the order given; each the same bit for bit as ``build_table(body, θ0, **grid)``.

    Raises
    ------
    ValueError
        Naming the parameter: a θ0 outside ``THETA0_RANGE`` or too many of them, bad grid options, a bad
        ``scheduler``, ``workers``, ``threads`` or ``processes`` or two of them, an estimate over ``budget``; all
        before any work.  As ``build_table`` for a body whose tables cannot be built.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> tables = rr.build_release_tables(body, [0.9 * math.pi, 0.95 * math.pi], threads=2, progress=False)
    >>> print([f"{t.theta0 / math.pi:.2f}pi" for t in tables], tables[1].coef.shape)
    ['0.90pi', '0.95pi'] (18, 128, 6)
    """
    angles_list = _check_angles(theta0)
    _check_where(scheduler, workers, threads, processes)
    allowed = {"nu", "nv", "u_factor", "v_ratio"}
    if set(grid) - allowed:
        raise ValueError(f"unknown table options {sorted(set(grid) - allowed)}; allowed: {sorted(allowed)}")
    check_grid(grid.get("nu", 128), grid.get("nv", 6))
    tables: dict[float, SlowMapTable] = {}
    todo = []
    for t in dict.fromkeys(angles_list):
        try:
            tables[t] = load_or_build_table(body, t, build=False, use_cache=use_cache, **grid)
        except TableNotCachedError:
            todo.append(t)
    nodes = grid.get("nu", 128) * grid.get("nv", 6)
    check_work(len(todo) * RELEASE_TABLE_SECONDS * nodes / _DEFAULT_NODES,
               f"{len(todo)} release table{'s' if len(todo) != 1 else ''} to build ({nodes} nodes each)", budget)
    frames = [release_frame(body, t, **grid) for t in todo]
    blocks, owner, done = _frame_blocks(frames)
    names = ", ".join(f"{t / math.pi:.6g}pi" for t in todo)
    rows = run_blocks(node_block, blocks, done, scheduler=scheduler, workers=workers,
                      threads=threads, processes=processes, desc=f"release tables, theta0 in ({names})", unit="node",
                      progress=progress)
    for k, (t, (frame, T, W, dphi, thX)) in enumerate(zip(todo, frames)):
        resp = assemble_nodes([r for r, o in zip(rows, owner) if o == k], T.shape)[3]
        table = fit_release_table(frame, T, W, dphi, resp)
        store_table(build_table, body, t, f"theta0={t!r}", table, use_cache=use_cache, **grid)
        tables[t] = table
    return [tables[t] for t in angles_list]


def _frame_blocks(frames: list[tuple[SlowMapTable, NDArray, NDArray, NDArray, NDArray]]
                  ) -> tuple[list[Any], list[int], list[int]]:
    """The node blocks of the release tables ``frames`` (:func:`release_frame`'s results) for one scheduler: the
    blocks, the index of the table each belongs to, and the nodes each provides (for the progress bar)."""
    blocks, owner, done = [], [], []
    for k, (frame, T, _, _, thX) in enumerate(frames):
        QR, QJ = frame.nodes()
        mine = node_blocks(frame.body, frame.E0, QR, QJ, thX)
        blocks += mine
        owner += [k] * len(mine)
        done += nodes_done(mine, T.size)
    return blocks, owner, done


def build_second_order_tables(body: Body, theta0: ArrayLike, *, scheduler: str | None = None,
                              workers: int | None = None, threads: int | None = None, processes: int | None = None,
                              progress: bool | None = None, use_cache: bool = True,
                              budget: float | None = WORK_BUDGET_SECONDS, nu: int = 64,
                              nv: int = 6) -> list[SecondOrderTable]:
    """The second-order tables of (body, θ0) for every θ0 given (each on the chart of θ0's release table at its
    default grid), those not cached built together: the release tables first (:func:`build_release_tables`, on the
    same scheduler), then the k₂ node blocks of all of them on it, each table fitted and checked here as
    :func:`rocknroller.analysis.slow.map.second_order.build_second_order_table` does, the same bit for bit, and
    cached as ``load_or_build_second_order_table`` caches it.

    Parameters as :func:`build_release_tables`; ``nu``, ``nv`` those of ``build_second_order_table``.  ``budget``
    bounds the release tables' builds (the second-order ones are not estimated, as elsewhere: built once per θ0,
    then cached).
    """
    angles_list = _check_angles(theta0)
    _check_where(scheduler, workers, threads, processes)
    check_k2_nu(nu)
    where: dict[str, Any] = dict(scheduler=scheduler, workers=workers, threads=threads, processes=processes,
                                 progress=progress)
    seconds: dict[float, SecondOrderTable] = {}
    todo = []
    for t in dict.fromkeys(angles_list):
        try:
            seconds[t] = load_or_build_second_order_table(body, t, build=False, use_cache=use_cache, nu=nu, nv=nv)
        except TableNotCachedError:
            todo.append(t)
    firsts = build_release_tables(body, todo, use_cache=use_cache, budget=budget, **where) if todo else []
    blocks, owner = [], []
    for k, first in enumerate(firsts):
        mine = k2_blocks(first, nu, nv)
        blocks += mine
        owner += [k] * len(mine)
    names = ", ".join(f"{t / math.pi:.6g}pi" for t in todo)
    rows = run_blocks(k2_block, blocks, [len(b[1]) for b in blocks], desc=f"second-order tables, theta0 in ({names})",
                      unit="node", **where)
    for k, (t, first) in enumerate(zip(todo, firsts)):
        table = fit_k2(first, t, "release", nu, nv, [r for r, o in zip(rows, owner) if o == k])
        store_table(build_second_order_table, body, t, f"theta0={t!r}", table, use_cache=use_cache, spec_of=k2_spec,
                    nu=nu, nv=nv)
        seconds[t] = table
    return [seconds[t] for t in angles_list]


def _check_angles(theta0: ArrayLike) -> list[float]:
    """The release angles as floats, each in ``THETA0_RANGE`` and at most ``MAX_TABLES`` (ValueError naming theta0)."""
    angles = np.atleast_1d(np.asarray(theta0, dtype=float))
    if angles.ndim != 1 or angles.size > MAX_TABLES:
        raise ValueError(f"theta0 must be a number or a 1-D sequence of at most MAX_TABLES = {MAX_TABLES} angles, "
                         f"got shape {angles.shape}")
    return [check_map_theta0(float(t)) for t in angles]


def _check_where(scheduler: Any, workers: Any, threads: Any, processes: Any) -> None:
    """ValueError naming the parameter unless at most one scheduler of :func:`run_blocks` is given, valid."""
    if processes is not None:
        check_processes(processes, "processes")
        if (scheduler, workers, threads) != (None, None, None):
            raise ValueError("processes (spawned processes of this machine) is one scheduler: give it without "
                             "scheduler, workers or threads")
    else:
        check_cluster(scheduler, workers, threads)


# ----------------------------------------------------------------------------- tables over energy
#: Chebyshev nodes in s = log(π − θ0) of the ε-responses (first order) and of k₂ (second order) of the default
#: tables over energy: the fewest that meet their accuracy over ``THETA0_RANGE`` (docs/slow_validation.md, "Tables
#: over energy": the first-order coefficients to ≤ 1e-7 of each kick, k₂ to ≤ 1e-4, a tenth of what the order-2
#: map's own ε³ step error allows at ε = 1e-3).
ENERGY_NODES_FIRST = 96
ENERGY_NODES_SECOND = 26
#: The interpolated tables of the release angles asked for most recently (~0.2 MB each).
_ENERGY_CACHE = MemoryCache(1 << 26)


@dataclass(frozen=True)
class EnergyTables:
    """The slow map's ε-responses and k₂ tabulated over the release angle: one build per body
    (:func:`build_energy_tables`; module docstring).

    Attributes
    ----------
    a, I1, I3, g : float
        The symmetric body.
    theta0_lo, theta0_hi : float
        The release angles spanned (Chebyshev nodes in s = log(π − θ0) between them).
    C0 : ndarray (n_first, 2)
        The kick at rest (``kick_at_rest``), which orients each release table's chart, at each node in s.
    resp : ndarray (n_first, 5, nu, nv, 3)
        The ε-responses' harmonics at the release tables' nodes, reduced (``reduce_responses``: the part the second
        half-drift carries taken out), at each node in s.
    k2 : ndarray (n_second, 25, k2_nu, nv)
        The second-order tables' coefficients at each node in s.
    first_error, second_error : float
        The largest relative error, at off-node release angles checked when built, of the interpolated release
        tables' kicks against per-θ0 tables and of k₂ against k₂ computed directly there
        (:func:`~rocknroller.analysis.slow.map.second_order.k2_check_error`, as a second-order table is checked; at
        the low end and the middle of the span: near π, k₂'s own interpolation in Q on any release chart dominates).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> span = rr.build_energy_tables(rr.Body.paper(), 0.9 * math.pi, theta0_hi=0.901 * math.pi, n_first=2,
    ...                               n_second=2, k2_nu=8, progress=False)
    >>> table = span.release_table(0.9005 * math.pi)
    >>> print(span.covers(0.9005 * math.pi), table.coef.shape, span.second_order_table(0.9005 * math.pi).coef.shape)
    True (18, 128, 6) (25, 8, 6)
    """

    a: float
    I1: float
    I3: float
    g: float
    theta0_lo: float
    theta0_hi: float
    C0: NDArray[np.float64]
    resp: NDArray[np.float64]
    k2: NDArray[np.float64]
    first_error: float
    second_error: float

    @property
    def body(self) -> Body:
        """The symmetric body the tables were built for."""
        return Body(a=self.a, I1=self.I1, I2=self.I1, I3=self.I3, g=self.g)

    def covers(self, theta0: float) -> bool:
        """Whether θ0 lies in the span."""
        return self.theta0_lo <= theta0 <= self.theta0_hi

    def release_table(self, theta0: float) -> SlowMapTable:
        """The release table of θ0 in the span: its drifts by quadrature on its chart (``release_frame``), the chart
        oriented by the interpolated kick at rest, its kicks fitted from the interpolated ε-responses (no orbit is run);
        ``interp_error`` is ``first_error``."""
        key = (self.body.params, self.theta0_lo, self.theta0_hi, self.resp.shape, self.C0.tobytes(), self.first_error,
               theta0)  # the tables over energy of one build, and the angle
        table = _ENERGY_CACHE.get(key)
        if table is None:
            theta0 = check_map_theta0(theta0)
            if not self.covers(theta0):
                raise ValueError(f"theta0 must lie in [{self.theta0_lo / math.pi:.6g}pi, {self.theta0_hi / math.pi:.6g}"
                                 f"pi] for these tables over energy, got theta0={theta0!r}")
            x = _position(theta0, self.theta0_lo, self.theta0_hi)
            frame, T, W, dphi, _ = release_frame(self.body, theta0, nu=self.resp.shape[2], nv=self.resp.shape[3],
                                                 C0=_interpolate(self.C0[:, None, :], x)[0])
            resp = _interpolate(self.resp, x)
            table = replace(fit_reduced(frame, T, W, dphi, resp), interp_error=self.first_error)
            _ENERGY_CACHE[key] = table
        return table

    def second_order_table(self, theta0: float) -> SecondOrderTable:
        """k₂ of θ0 in the span on the chart of :meth:`release_table`; ``interp_error`` is ``second_error``."""
        first = self.release_table(theta0)
        return SecondOrderTable(theta0=first.theta0, E0=first.E0, interp_error=self.second_error,
                                coef=_interpolate(self.k2, _position(first.theta0, self.theta0_lo, self.theta0_hi)))


def _s_nodes(n: int, lo: float, hi: float) -> NDArray[np.float64]:
    """The n release angles at Chebyshev points (first kind, descending) in s = log(π − θ0) over [lo, hi]."""
    s_lo, s_hi = math.log(math.pi - hi), math.log(math.pi - lo)
    return math.pi - np.exp(0.5 * (s_hi + s_lo) + 0.5 * (s_hi - s_lo) * cheb_nodes(n))


def _position(theta0: float, lo: float, hi: float) -> float:
    """θ0's coordinate x ∈ [−1, 1] of :func:`_s_nodes` (descending nodes: x = 1 at lo)."""
    s_lo, s_hi = math.log(math.pi - hi), math.log(math.pi - lo)
    return (2.0 * math.log(math.pi - theta0) - s_hi - s_lo) / (s_hi - s_lo)


def _interpolate(values: NDArray[np.float64], x: float) -> NDArray[np.float64]:
    """Values (n, F, ...) at the n Chebyshev nodes, at x: each function's size (rms over its trailing axes) fitted by
    a power law of π − θ0 (a line in log size over s, by least squares) and divided out, the rest by the barycentric
    formula of the first-kind points (weights (−1)^k sin((k + ½)π/n)), the size put back.  A function that vanishes
    at some node is interpolated as it is."""
    n = values.shape[0]
    xs = cheb_nodes(n)
    size = np.sqrt(np.mean(values.reshape(n, values.shape[1], -1) ** 2, axis=-1))  # (n, F)
    law = np.zeros((2, values.shape[1]))
    fitted = np.all(size > 0.0, axis=0)
    if fitted.any():
        law[:, fitted] = np.polyfit(xs, np.log(size[:, fitted]), 1)
    scale = np.where(fitted, np.exp(law[0] * xs[:, None] + law[1]), 1.0)  # (n, F)
    shape = (n, values.shape[1]) + (1,) * (values.ndim - 2)
    hit = np.flatnonzero(xs == x)
    if hit.size:
        return np.array(values[hit[0]], float)
    k = np.arange(n)
    c = (-1.0) ** k * np.sin((k + 0.5) * math.pi / n) / (x - xs)
    inner = np.tensordot(c / c.sum(), values / scale.reshape(shape), axes=1)
    at = np.where(fitted, np.exp(law[0] * x + law[1]), 1.0)
    return np.asarray(inner * at.reshape(shape[1:]), float)


def _energy_spec(opts: dict[str, Any]) -> dict[str, tuple[int, ...]]:
    """The fields of a tables-over-energy file, in checksum order."""
    return {"a": (), "I1": (), "I3": (), "g": (), "theta0_lo": (), "theta0_hi": (),
            "C0": (opts["n_first"], 2), "resp": (opts["n_first"], 5, 128, 6, 3),
            "k2": (opts["n_second"], 25, opts["k2_nu"], 6), "first_error": (), "second_error": ()}


def _check_positions(n: int) -> list[float]:
    """Off-node release angles, as positions x of :func:`_position`, where a new build is checked against per-θ0
    tables: midway between the outermost nodes at each end and between two middle ones (where an interpolant errs
    most)."""
    xs = cheb_nodes(n)
    return [0.5 * (xs[0] + xs[1]), 0.5 * (xs[n // 2 - 1] + xs[n // 2]), 0.5 * (xs[-2] + xs[-1])]


def build_energy_tables(body: Body, theta0_lo: float, *, theta0_hi: float = THETA0_RANGE[1],
                        n_first: int = ENERGY_NODES_FIRST, n_second: int = ENERGY_NODES_SECOND, k2_nu: int = 64,
                        workers: int = 1, progress: bool | None = None) -> EnergyTables:
    """Tabulate the slow map's ε-responses and k₂ over the release angles [theta0_lo, theta0_hi] (module docstring).

    Parameters
    ----------
    body : Body
        Its symmetric part is used.
    theta0_lo : float
        The smallest release angle, in ``THETA0_RANGE`` (the default tables: ``THETA0_RANGE[0]``).
    theta0_hi : float
        The largest, in ``THETA0_RANGE`` and above ``theta0_lo``.
    n_first, n_second : int
        Chebyshev nodes in s = log(π − θ0) of the ε-responses and of k₂: 2–128 each.
    k2_nu : int
        The second-order tables' nodes along (as ``build_second_order_table``'s nu).
    workers : int
        Processes that share the orbits; the tables do not depend on it.
    progress : bool or None
        tqdm bars over the nodes (None: only if stderr is a terminal).

    Returns
    -------
    EnergyTables
        With its errors against per-θ0 tables built at off-node angles (``_check_positions``).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.slow.map.tables_at_once import build_energy_tables
    >>> span = build_energy_tables(rr.Body.paper(), 0.9 * math.pi, theta0_hi=0.91 * math.pi, n_first=4,
    ...                            n_second=2, k2_nu=8, progress=False)
    >>> span.resp.shape, span.k2.shape, span.first_error < 1e-6
    ((4, 5, 128, 6, 3), (2, 25, 8, 6), True)
    """
    lo, hi = check_map_theta0(theta0_lo, "theta0_lo"), check_map_theta0(theta0_hi, "theta0_hi")
    if not lo < hi:
        raise ValueError(f"theta0_hi must exceed theta0_lo, got {theta0_lo!r}, {theta0_hi!r}")
    for name, val in (("n_first", n_first), ("n_second", n_second)):
        if isinstance(val, bool) or int(val) != val or not 2 <= val <= 128:
            raise ValueError(f"{name} must be an integer in [2, 128], got {name}={val!r}")
    check_k2_nu(k2_nu)
    sym = body.symmetric()
    where: dict[str, Any] = dict(processes=check_processes(workers, "workers"), progress=progress)
    angles = _s_nodes(n_first, lo, hi)
    frames = [release_frame(sym, float(t)) for t in angles]
    blocks, owner, done = _frame_blocks(frames)
    rows = run_blocks(node_block, blocks, done, desc="tables over energy: first order", unit="node", **where)
    resp = np.stack([reduce_responses(*frames[k][:4], assemble_nodes([r for r, o in zip(rows, owner) if o == k],
                                                                      frames[k][1].shape)[3]) for k in range(n_first)])
    span = EnergyTables(a=sym.a, I1=sym.I1, I3=sym.I3, g=sym.g, theta0_lo=lo, theta0_hi=hi,
                        C0=np.array([f[0].C0 for f in frames]), resp=resp, k2=np.zeros((n_second, 25, k2_nu, 6)),
                        first_error=0.0, second_error=0.0)
    # k₂ at its nodes, each on the chart of the release table interpolated there (within ~1e-7 of its own, a
    # thousandth of k₂'s interpolation error; no release table is built for it)
    firsts = [span.release_table(float(t)) for t in _s_nodes(n_second, lo, hi)]
    blocks2, owner2 = [], []
    for k, first in enumerate(firsts):
        mine2 = k2_blocks(first, k2_nu, 6)
        blocks2 += mine2
        owner2 += [k] * len(mine2)
    rows2 = run_blocks(k2_block, blocks2, [len(b[1]) for b in blocks2], desc="tables over energy: second order",
                       unit="node", **where)
    k2 = np.stack([fit_k2(first, first.theta0, "release", k2_nu, 6, [r for r, o in zip(rows2, owner2) if o == k],
                          check=False).coef for k, first in enumerate(firsts)])  # the span is checked below
    span = replace(span, k2=k2)
    first_err, second_err = 0.0, 0.0
    for x in _check_positions(n_first):
        t = _angle(x, lo, hi)
        first_err = max(first_err, kick_error(span.release_table(t), build_table(sym, t, progress=False)))
    for x in _check_positions(n_second)[:2]:  # near π k₂'s own interpolation in Q dominates (6.7e-2 at 0.999π)
        t = _angle(x, lo, hi)
        second_err = max(second_err, k2_check_error(span.release_table(t), span.second_order_table(t)))
    _ENERGY_CACHE.clear()
    return replace(span, first_error=first_err, second_error=second_err)


def _angle(x: float, lo: float, hi: float) -> float:
    """The release angle at the position x of :func:`_position`."""
    s_lo, s_hi = math.log(math.pi - hi), math.log(math.pi - lo)
    return float(math.pi - math.exp(0.5 * (s_hi + s_lo) + 0.5 * (s_hi - s_lo) * x))


def _points(chart: SlowMapTable, nu: int, nv: int) -> list[tuple[float, float]]:
    """The points Q of the nu × nv Chebyshev nodes of ``chart``'s chart pulled in by a thousandth (inside both charts
    of two tables compared, the tables over energy orienting theirs by an interpolated kick at rest)."""
    QR, QJ = chart.chart(*np.meshgrid(0.999 * cheb_nodes(nu), 0.999 * cheb_nodes(nv), indexing="ij"))
    return list(zip(QR.ravel().tolist(), QJ.ravel().tolist()))


def kick_error(table: SlowMapTable, ref: SlowMapTable) -> float:
    """The largest error of ``table``'s functions against ``ref``'s at ``ref``'s nodes (:func:`_points`): T, W and Δφ
    each relative to its largest value, each kick's harmonics relative to that kick's largest."""
    pts = _points(ref, *ref.coef.shape[1:])
    a, b = np.array([table.evaluate(q) for q in pts]).T, np.array([ref.evaluate(q) for q in pts]).T
    groups = [[0], [1], [2]] + [list(range(3 + 3 * g, 6 + 3 * g)) for g in range(5)]
    return float(max(np.abs(a[g] - b[g]).max() / np.abs(b[g]).max() for g in groups))


def k2_error(first: SlowMapTable, second: SecondOrderTable, ref_first: SlowMapTable, ref: SecondOrderTable) -> float:
    """The largest error of k₂'s harmonics of ``second`` (on ``first``'s chart) against ``ref`` (on ``ref_first``'s)
    at ``ref``'s nodes, relative to each component's largest harmonic there (as second-order tables are checked)."""
    pts = _points(ref_first, *ref.coef.shape[1:])
    a = np.array([second.harmonics(first, q) for q in pts])
    b = np.array([ref.harmonics(ref_first, q) for q in pts])
    return float((np.abs(a - b).max(axis=(0, 2)) / np.abs(b).max(axis=(0, 2))).max())


def load_energy_tables(body: Body, *, build: bool = True, use_cache: bool = True, **grid: Any) -> EnergyTables:
    """The tables over energy of ``body`` (default: all of ``THETA0_RANGE``) from memory, the disk cache, or built
    (:func:`build_energy_tables` with ``grid``: theta0_lo and its keyword options) and cached, as
    :func:`~rocknroller.analysis.slow.map.table.cached_table` keeps every table (``build=False``: TableNotCachedError
    if they are not cached).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> try:  # tables over [0.8pi, 0.999pi] on 3 nodes: never built
    ...     rr.load_energy_tables(rr.Body.paper(), build=False, theta0_lo=0.8 * math.pi, n_first=3)
    ... except ValueError as exc:
    ...     print(type(exc).__name__)
    TableNotCachedError
    """
    lo = grid.pop("theta0_lo", THETA0_RANGE[0])
    return cached_table(build_energy_tables, body, lo, f"theta0 in [{lo!r}, ...]", build=build, use_cache=use_cache,
                        table_type=EnergyTables, spec_of=_energy_spec, **grid)


def energy_tables_cached(body: Body) -> bool:
    """Whether the default tables over energy of ``body`` are in memory or the disk cache, and in use: the environment
    variable ``ROCKNROLLER_ENERGY_TABLES=off`` sets them aside (every release then on its per-θ0 tables, to reproduce
    a result made without them)."""
    if os.environ.get("ROCKNROLLER_ENERGY_TABLES", "").strip().lower() == "off":
        return False
    return is_cached(build_energy_tables, body, THETA0_RANGE[0])


def release_tables(body: Body, theta0: float, order: int, *, build: bool = True, progress: bool | None = None,
                   workers: int = 1) -> tuple[SlowMapTable, SecondOrderTable | None]:
    """The release table of (body, θ0) and, for ``order`` 2, its second-order table: from the tables over energy
    where they are cached for the body (``rocknroller warm --tables``), else per θ0 (built and cached if needed,
    unless ``build`` is False; also where the cached file fails its checks, with a CacheWarning)."""
    theta0 = check_map_theta0(theta0)
    if energy_tables_cached(body):
        try:
            span = load_energy_tables(body, build=False)
        except TableNotCachedError:  # the file failed its checks (a CacheWarning said so): per θ0 instead
            pass
        else:
            return span.release_table(theta0), span.second_order_table(theta0) if order == 2 else None
    table = load_or_build_table(body, theta0, build=build, progress=progress, workers=workers)
    second = (load_or_build_second_order_table(body, theta0, build=build, progress=progress, workers=workers)
              if order == 2 else None)
    return table, second
