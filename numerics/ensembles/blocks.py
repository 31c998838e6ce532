"""Blocks of independent work on any of the ensembles' schedulers: this process, its threads, spawned processes, or a
dask.distributed cluster (local or at an address).

The table builds of many energies at once (:mod:`rocknroller.analysis.slow.map.tables_at_once`) hand their node
blocks here.  Each block's result depends only on the block, so the results do not depend on where the blocks run.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from typing import Any, Callable, Sequence

from rocknroller.numerics.ensembles.ensemble import check_cluster, cluster_map
from rocknroller.numerics.parallel import check_processes, map_blocks

__all__ = ["run_blocks"]


def run_blocks(fn: Callable[..., Any], blocks: Sequence[tuple[Any, ...]], sizes: Sequence[int], *,
               scheduler: str | None = None, workers: int | None = None, threads: int | None = None,
               processes: int | None = None, desc: str = "", unit: str = "item",
               progress: bool | None = False) -> list[Any]:
    """``[fn(*b) for b in blocks]`` on one scheduler, in block order.

    Parameters
    ----------
    fn : callable
        A module-level function (sent to other processes by pickling).
    blocks, sizes
        The arguments of each call, and its size for the progress bar.
    scheduler, workers, threads : optional
        As for :func:`rocknroller.numerics.ensembles.ensemble.run_ensemble` (checked by its ``check_cluster``): the
        workers of the dask scheduler at this TCP address, a local cluster of this many worker processes, or this
        many threads of this process.
    processes : int, optional
        This many "spawn" processes (:func:`rocknroller.numerics.parallel.map_blocks`), in
        [1, ``parallel.MAX_PROCESSES``]; not with the others.  None of the four: a loop in this process.
    desc, unit, progress
        The tqdm bar's name and unit, and whether to show it (None: only on a terminal).

    Raises
    ------
    ValueError
        Naming the parameter: a bad ``scheduler``, ``workers``, ``threads`` or ``processes``, or two of them given.
    """
    if processes is not None:
        if (scheduler, workers, threads) != (None, None, None):
            raise ValueError("processes (spawned processes of this machine) is one scheduler: give it without "
                             "scheduler, workers or threads")
        return map_blocks(fn, blocks, sizes, processes=check_processes(processes, "processes"), desc=desc, unit=unit,
                          progress=progress)
    scheduler, workers = check_cluster(scheduler, workers, threads)
    if not blocks:
        return []
    if scheduler is not None or workers is not None:
        return cluster_map(fn, blocks, sizes, scheduler=scheduler, workers=workers, progress=progress, unit=unit)
    if threads is None or int(threads) == 1:
        return map_blocks(fn, blocks, sizes, processes=1, desc=desc, unit=unit, progress=progress)
    from tqdm.auto import tqdm

    with tqdm(total=sum(sizes), desc=desc, unit=unit, disable=None if progress is None else not progress) as bar, \
            ThreadPoolExecutor(max_workers=min(int(threads), len(blocks))) as pool:
        futures = [pool.submit(fn, *b) for b in blocks]
        try:
            for future, n in zip(futures, sizes):
                future.result()
                bar.update(n)
        except BaseException:
            pool.shutdown(cancel_futures=True)
            raise
        return [future.result() for future in futures]
