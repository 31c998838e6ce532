"""Throughput per trajectory of an ensemble of direct runs, side by side in one process.

Run:  python benchmarks/bench_ensemble.py [--jobs N] [--t-end T]

An atlas-like ensemble (paper body, ε = 1e-3, released from rest at θ0 = 0.95π, ψ0 spread over [0, π/2), each run
1000 time units by default).  Reports the wall time per trajectory of
* one-at-a-time calls of simulate(..., samples=False) and the summary of each (the reference);
* run_ensemble in this process: a loop, and two threads;
* run_ensemble on dask.distributed (if installed): a local cluster of two worker processes started for the call
  (``workers=2``, its start-up included), and an existing two-worker cluster (``scheduler=``, start-up excluded);
and the ratio of each to the reference (> 1: faster per trajectory).  Every path's summaries are checked to be
bit-identical to the reference's.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import time
from typing import Callable

import numpy as np

from rocknroller.analysis.model.body import Body
from rocknroller.numerics.ensemble import Job, RunSummary, run_ensemble
from rocknroller.analysis.model.equations import EulerState
from rocknroller.numerics.integrate import heyoka_integrator, simulate
from rocknroller.numerics.trajectory import TurningPoints


def best_of(fn: Callable[[], list[RunSummary]], n: int) -> tuple[float, list[RunSummary]]:
    times, out = [], []
    for _ in range(n):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def identical(a: list[RunSummary], b: list[RunSummary]) -> bool:
    return all(all(np.array_equal(getattr(x.maxima, f.name), getattr(y.maxima, f.name))
                   for f in dataclasses.fields(TurningPoints))
               and all(getattr(x, f.name) == getattr(y, f.name) for f in dataclasses.fields(RunSummary)[1:])
               for x, y in zip(a, b, strict=True))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=48)
    parser.add_argument("--t-end", type=float, default=1000.0)
    args = parser.parse_args()
    body = Body.paper(1e-3)
    jobs = [Job(body, EulerState(0.95 * math.pi, psi=0.5 * math.pi * k / args.jobs), args.t_end)
            for k in range(args.jobs)]
    heyoka_integrator()  # compiled or loaded from the disk cache once, outside the timings
    load = os.getloadavg()[0]  # the parallel paths gain only on idle cores: say how busy the machine was

    def one_at_a_time() -> list[RunSummary]:
        return [RunSummary.from_run(simulate(j.body, j.initial, j.t_end, samples=False)) for j in jobs]

    t_ref, ref = best_of(one_at_a_time, 3)
    rows = [("one-at-a-time simulate(samples=False)", t_ref, True)]
    for label, kwargs in (("run_ensemble, in-process loop", {}), ("run_ensemble, threads=2", {"threads": 2})):
        t, out = best_of(lambda: run_ensemble(jobs, progress=False, **kwargs), 3)
        rows.append((label, t, identical(out, ref)))
    try:
        import distributed
    except ImportError:
        print('(dask.distributed not installed: python -m pip install -e ".[distributed]" in a clone for the cluster rows)')
    else:
        t, out = best_of(lambda: run_ensemble(jobs, workers=2, progress=False), 1)
        rows.append(("run_ensemble, workers=2 (LocalCluster start included)", t, identical(out, ref)))
        with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                      dashboard_address=":0") as cluster:
            address = cluster.scheduler_address
            run_ensemble(jobs[:2], scheduler=address, progress=False)  # the workers load the integrator
            t, out = best_of(lambda: run_ensemble(jobs, scheduler=address, progress=False), 3)
            rows.append(("run_ensemble, scheduler= (running 2-worker cluster)", t, identical(out, ref)))
    n_max = sum(s.n_maxima for s in ref) / len(ref)
    print(f"{len(jobs)} jobs of {args.t_end:g} time units ({n_max:.0f} maxima, {ref[0].n_steps} steps each), "
          f"best of 3 (cluster start: 1 run); {os.cpu_count()} cores, load average {load:.2f} at the start")
    print(f"{'path':56s} {'ms/trajectory':>14s} {'ratio':>7s}  bit-identical")
    for label, t, same in rows:
        print(f"{label:56s} {t / len(jobs) * 1e3:14.2f} {t_ref / t:6.2f}x  {same}")


if __name__ == "__main__":
    main()
