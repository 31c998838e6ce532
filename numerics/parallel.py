"""Blocks of independent work shared by "spawn" processes, with a progress bar: the table builds and the atlas.

Each block's result depends only on the block, so the results do not depend on the number of processes.  Spawned
processes import the calling script: guard a script's top level with ``if __name__ == "__main__":``.
"""

from __future__ import annotations

import os
import sys
import time
from contextlib import contextmanager
from typing import Any, Callable, Iterator, Sequence

from rocknroller.numerics.cache import note_after

__all__ = ["MAX_PROCESSES", "QUIET_NOTE_AFTER", "WORKER_THREADS", "check_processes", "map_blocks"]

#: Most processes one call may start.
MAX_PROCESSES = 64
#: Seconds after which work whose bar is hidden (``progress`` None, stderr not a terminal) says so in one line.
QUIET_NOTE_AFTER = 2.0
#: The BLAS threads of each spawned worker, unless the caller's environment sets them: the pool is the parallelism,
#: and a worker's own BLAS threads would oversubscribe the cores (their idle threads spin).  Measured on 2 cores, a
#: release and a second-order table built by 2 processes: 18.4 s CPU and 10.2 s wall with OpenBLAS's default 2 threads
#: per worker, 16.7 s and 9.2 s with 1; the tables bit for bit the same (and as one process builds them).
WORKER_THREADS = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def check_processes(value: Any, name: str = "workers") -> int:
    """``value`` as an int in [1, ``MAX_PROCESSES``], else a ValueError naming ``name``."""
    if isinstance(value, bool) or int(value) != value or not 1 <= value <= MAX_PROCESSES:
        raise ValueError(f"{name} must be an integer in [1, {MAX_PROCESSES}], got {name}={value!r}")
    return int(value)


def _advance(bar: Any, n: int) -> Callable[[Any], None]:
    """A future's done-callback that advances the progress bar ``bar`` by ``n``."""
    def callback(_: Any) -> None:
        bar.update(n)

    return callback


@contextmanager
def _noted(desc: str, total: int, unit: str, shown: bool) -> Iterator[None]:
    """Where the bar is hidden because stderr is not a terminal, work still running after ``QUIET_NOTE_AFTER`` seconds
    says what it is in one line on stderr, and another when it is done (a log otherwise shows nothing for as long as
    a table build takes)."""
    if shown or not desc:
        yield
        return
    start = time.perf_counter()
    with note_after(QUIET_NOTE_AFTER, f"rocknroller: {desc}: {total} {unit}s (no progress bar: stderr is not a "
                                      "terminal) ...") as said:
        try:
            yield
        finally:
            if said.is_set():
                print(f"rocknroller: {desc}: done in {time.perf_counter() - start:.1f} s", file=sys.stderr, flush=True)


@contextmanager
def _worker_environment() -> Iterator[None]:
    """``os.environ`` with ``WORKER_THREADS`` (those the caller has not set) while a pool spawns its processes, which
    read it as they start, before they import numpy; restored afterwards."""
    added = {k: v for k, v in WORKER_THREADS.items() if k not in os.environ}
    os.environ.update(added)
    try:
        yield
    finally:
        for k in added:
            os.environ.pop(k, None)


def map_blocks(fn: Callable[..., Any], blocks: Sequence[tuple[Any, ...]], sizes: Sequence[int], *, processes: int = 1,
               desc: str = "", unit: str = "item", progress: bool | None = False) -> list[Any]:
    """``[fn(*b) for b in blocks]``, in this process or in ``processes`` spawned ones (each with one BLAS thread,
    ``WORKER_THREADS``); a tqdm bar advances by ``sizes[i]`` as block i completes (``progress`` None: only on a
    terminal)."""
    from tqdm.auto import tqdm

    processes = check_processes(processes, "processes")
    shown = progress is not None or sys.stderr.isatty()
    with _noted(desc, sum(sizes), unit, shown), \
            tqdm(total=sum(sizes), desc=desc, unit=unit, disable=None if progress is None else not progress) as bar:
        if processes == 1:
            out = []
            for b, n in zip(blocks, sizes):
                out.append(fn(*b))
                bar.update(n)
            return out
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        with _worker_environment(), \
                ProcessPoolExecutor(processes, mp_context=multiprocessing.get_context("spawn")) as pool:
            futures = [pool.submit(fn, *b) for b in blocks]
            for fut, n in zip(futures, sizes):
                fut.add_done_callback(_advance(bar, n))
            return [fut.result() for fut in futures]
