"""The release tables of many energies at once: every node of every table on one scheduler.

A scan over the release angle θ0 (an atlas's rows, a bifurcation diagram, portraits at several energies) needs one
release table per θ0 (:func:`rocknroller.analysis.slow.map.table.build_table`).  :func:`build_release_tables` builds
those not yet cached together: each table's chart and its symmetric orbits (quadratures, cheap) in this process, then
the node blocks of all of them (one variational orbit per node, the cost) on one scheduler of
:func:`rocknroller.numerics.ensembles.blocks.run_blocks`: threads of this process, spawned processes, a local
dask.distributed cluster or the workers of a dask scheduler at an address, the schedulers of
:func:`rocknroller.numerics.ensembles.ensemble.run_ensemble`.  Each table is then fitted and checked here from its own
nodes in its own node order, by the same functions as ``build_table``, and cached as ``load_or_build_table`` caches
it.  A node's numbers depend only on the node (the batch integrator's lanes are independent, and every worker runs
the same versions: :func:`~rocknroller.numerics.ensembles.ensemble.cluster_map` checks), so the tables are the same
bit for bit as the one-process build's, wherever their nodes ran (tests/analysis/slow/map/test_tables_at_once.py).
:func:`build_second_order_tables` does the same for the second-order tables (k₂ on each release table's chart,
:mod:`rocknroller.analysis.slow.map.second_order`), after their release tables.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map.chart import SecondOrderTable, SlowMapTable
from rocknroller.analysis.slow.map.limits import check_map_theta0
from rocknroller.analysis.slow.map.second_order import (build_second_order_table, check_k2_nu, fit_k2, k2_block,
                                                        k2_blocks, k2_spec, load_or_build_second_order_table)
from rocknroller.analysis.slow.map.table import (TableNotCachedError, assemble_nodes, build_table, check_grid,
                                                 fit_release_table, load_or_build_table, node_block, node_blocks,
                                                 nodes_done, release_frame, store_table)
from rocknroller.numerics.budget import RELEASE_TABLE_SECONDS, WORK_BUDGET_SECONDS, check_work
from rocknroller.numerics.ensembles.blocks import run_blocks
from rocknroller.numerics.ensembles.ensemble import check_cluster
from rocknroller.numerics.parallel import check_processes

__all__ = ["MAX_TABLES", "build_release_tables", "build_second_order_tables"]

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
    blocks, owner, done = [], [], []
    for k, (frame, T, _, _, thX) in enumerate(frames):
        mine = node_blocks(frame.body, frame.E0, *frame.nodes(), thX)
        blocks += mine
        owner += [k] * len(mine)
        done += nodes_done(mine, T.size)
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
