"""Throughput per trajectory of an ensemble of direct runs, side by side in one process.

Run:  python benchmarks/bench_ensemble.py [--jobs N] [--t-end T] [--no-cluster]

An atlas-like ensemble (paper body, ε = 1e-3, released from rest at θ0 = 0.95π, ψ0 spread over [0, π/2), each run
1000 time units by default; 64 jobs, the README's case).  Reports the CPU and wall time per trajectory of
* the former path: one job after another in the scalar integrator with the unwrapping grid of that time
  (``DT_RADIANS``: simulate(..., samples=False, dt=0.15/Λ), the turning points to the bit of today's scalar path);
* run_ensemble(lanes=1): one job after another in the scalar integrator, today's unwrapping grid;
* run_ensemble (default): batches in the lanes of heyoka's batch integrator (numerics/ensembles/batch.py), in this process,
  then in two threads;
* run_ensemble on dask.distributed (if installed, not with --no-cluster): a local cluster of two worker processes;
* CyRK's compiled DOP853 with compiled events (its C++ solver, a Cython right-hand side; needs the extra ``bench``),
  one job after another at its smallest rtol (100 ε: DOP853 reaches no smaller energy error, while heyoka's is at
  machine precision: the peer runs at a *larger* energy error, which favours it);
and the ratio of each to the first (> 1: faster per trajectory).  The batch paths are checked to be bit-identical to
each other, and the scalar ones to each other.
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib.util
import math
import os
import time
from typing import Callable

import numpy as np

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.numerics.ensembles.batch import batch_integrator, batch_width
from rocknroller.numerics.ensembles.ensemble import Job, RunSummary, run_ensemble
from rocknroller.numerics.integrate import DT_RADIANS, heyoka_integrator, rate_bound, simulate
from rocknroller.numerics.trajectory import TurningPoints


def timed(fn: Callable[[], list], n: int) -> tuple[float, float, list]:
    """Best of n: (CPU seconds of this process, wall seconds, result)."""
    best, out = (math.inf, math.inf), []
    for _ in range(n):
        c0, w0 = time.process_time(), time.perf_counter()
        out = fn()
        best = min(best, (time.process_time() - c0, time.perf_counter() - w0))
    return best[0], best[1], out


def identical(a: list[RunSummary], b: list[RunSummary]) -> bool:
    return all(all(np.array_equal(getattr(x.maxima, f.name), getattr(y.maxima, f.name))
                   for f in dataclasses.fields(TurningPoints))
               and all(getattr(x, f.name) == getattr(y, f.name) for f in dataclasses.fields(RunSummary)[1:])
               for x, y in zip(a, b, strict=True))


def same_turning_points(a: list[RunSummary], b: list[RunSummary]) -> bool:
    return all(all(np.array_equal(getattr(x.maxima, f.name), getattr(y.maxima, f.name))
                   for f in dataclasses.fields(TurningPoints)) for x, y in zip(a, b, strict=True))


def cyrk_runner(body: Body):
    """CyRK's compiled DOP853 with compiled events (benchmarks/bench_integrate.py builds it), or None and why not."""
    try:
        from bench_integrate import build_cysolve
    except ImportError as exc:  # pragma: no cover
        return None, f"CyRK row skipped: {exc}"
    built, why, _ = build_cysolve(body)
    if built is None:
        return None, why
    return built[0], ""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=64)
    parser.add_argument("--t-end", type=float, default=1000.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--no-cluster", action="store_true", help="skip the dask rows")
    args = parser.parse_args()
    body = Body.paper(1e-3)
    jobs = [Job(body, EulerState(0.95 * math.pi, psi=0.5 * math.pi * k / args.jobs), args.t_end)
            for k in range(args.jobs)]
    heyoka_integrator()  # compiled or loaded from the disk cache once, outside the timings
    batch_integrator(batch_width())
    load = os.getloadavg()[0]

    def before() -> list[RunSummary]:
        return [RunSummary.from_run(simulate(j.body, j.initial, j.t_end, samples=False,
                                             dt=DT_RADIANS / rate_bound(j.body, j.initial.to_body_state())))
                for j in jobs]

    c_ref, w_ref, ref = timed(before, args.repeats)
    rows = [("fixed 0.15-radian grid: scalar, one by one", c_ref, w_ref, "reference")]
    c, w, scalar = timed(lambda: run_ensemble(jobs, progress=False, lanes=1), args.repeats)
    rows.append(("run_ensemble(lanes=1): scalar, one by one", c, w,
                 "same turning points" if same_turning_points(scalar, ref) else "DIFFERENT turning points"))
    c, w, lanes = timed(lambda: run_ensemble(jobs, progress=False), args.repeats)
    rows.append((f"run_ensemble: batches of {batch_width()} lanes", c, w, "batch reference"))
    c, w, out = timed(lambda: run_ensemble(jobs, progress=False, threads=2), args.repeats)
    rows.append((f"run_ensemble: batches of {batch_width()} lanes, threads=2", c, w,
                 "bit-identical" if identical(out, lanes) else "NOT bit-identical"))
    if not args.no_cluster:
        if importlib.util.find_spec("distributed") is None:
            print('(dask.distributed not installed: python -m pip install -e ".[distributed]" for the cluster row)')
        else:
            _, w, out = timed(lambda: run_ensemble(jobs, workers=2, progress=False), 1)
            rows.append(("run_ensemble: workers=2 (LocalCluster start included)", math.nan, w,
                         "bit-identical" if identical(out, lanes) else "NOT bit-identical"))
    run, why = cyrk_runner(body)
    if run is None:
        print(why)
    else:
        rtol = 100 * float(np.finfo(float).eps)

        def cyrk() -> list:
            return [run(np.asarray(j.initial.to_body_state(), float), np.asarray(j.body.params, float), j.t_end,
                        rtol, 1e-20, np.empty(0)) for j in jobs]

        c, w, _ = timed(cyrk, args.repeats)
        rows.append((f"CyRK DOP853 compiled + events, rtol {rtol:.1e}, one by one", c, w, "peer"))
    n_max = sum(s.n_maxima for s in lanes) / len(lanes)
    print(f"{len(jobs)} jobs of {args.t_end:g} time units ({n_max:.0f} maxima each), best of {args.repeats}; "
          f"{os.cpu_count()} cores, load average {load:.2f} at the start, {os.getloadavg()[0]:.2f} at the end")
    print(f"{'path':62s} {'CPU ms/traj':>11s} {'wall ms/traj':>12s} {'CPU ratio':>9s}  check")
    for label, c, w, check in rows:  # a cluster's CPU time is its workers', not this process's: not shown
        cpu, ratio = ("-", "-") if math.isnan(c) else (f"{c / len(jobs) * 1e3:.2f}", f"{c_ref / c:.2f}x")
        print(f"{label:62s} {cpu:>11s} {w / len(jobs) * 1e3:12.2f} {ratio:>9s}  {check}")


if __name__ == "__main__":
    main()
