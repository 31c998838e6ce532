"""The pool's workers run one BLAS thread each (numerics/parallel.py, ``WORKER_THREADS``): the pool is the
parallelism, and a worker's own BLAS threads oversubscribed the cores (OpenBLAS's idle threads spin: a release and a
second-order table built by 2 processes took 10 % more CPU and wall time).  A setting of the caller's wins, and the
caller's environment is left as it was."""

from __future__ import annotations

import os

from rocknroller.numerics import parallel

NAMES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def test_workers_run_one_blas_thread_unless_the_caller_sets_it(monkeypatch):
    assert set(parallel.WORKER_THREADS) == set(NAMES)
    for name in NAMES:
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("MKL_NUM_THREADS", "3")
    assert parallel.map_blocks(os.getenv, [(name,) for name in NAMES], [1, 1, 1], processes=2) == ["1", "1", "3"]
    assert "OPENBLAS_NUM_THREADS" not in os.environ and "OMP_NUM_THREADS" not in os.environ
    assert os.environ["MKL_NUM_THREADS"] == "3"
    # in this process (one process: no pool) nothing is set
    assert parallel.map_blocks(os.getenv, [("OPENBLAS_NUM_THREADS",)], [1], processes=1) == [None]
