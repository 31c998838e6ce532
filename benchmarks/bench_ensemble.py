"""Throughput per trajectory of an ensemble of direct runs, side by side in one process.

Run:  python benchmarks/bench_ensemble.py [--jobs N] [--t-end T] [--repeats R] [--no-cluster]

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

Then the same jobs at equal energy error: the batch lanes at tol = ``TOL_EQUAL`` (heyoka's level nearest CyRK's best
energy error: order 14; :mod:`rocknroller.numerics.run_limits`) against CyRK at its smallest rtol, each energy error
measured (heyoka's over the run's unwrapping grid, CyRK's over a 3001-point grid of its dense output, in an untimed
run); with, to show where the lanes' time goes, heyoka's batch propagation alone (integration and events, with and
without the dense output the turning points and the unwrapping are evaluated on).  It prints the two ratios asked of
the ensembles: lanes at ``TOL_EQUAL`` against CyRK, and lanes at tol = ε against the scalar loop.

Every path runs once per round, the rounds interleaved (``--repeats``, best of them per path), so that a change in the
machine's load during the run falls on all paths alike; times are this process's CPU time (``time.process_time``).
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib.util
import math
import os
import resource
import time
from typing import Callable

import numpy as np

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.numerics.ensembles.batch import BATCH_CHUNK_RADIANS, batch_integrator
from rocknroller.numerics.ensembles.lanes import default_lanes
from rocknroller.numerics.ensembles.ensemble import Job, RunSummary, run_ensemble
from rocknroller.analysis.model.invariants import energy
from rocknroller.numerics.integrate import DT_RADIANS, _stretch_end, default_dt, heyoka_integrator, rate_bound, simulate
from rocknroller.numerics.run_limits import DEFAULT_TOL
from rocknroller.numerics.run_limits import energy_scale
from rocknroller.numerics.trajectory import TurningPoints

#: heyoka's tolerance at CyRK's best energy error (the Taylor order 14 level: ≈ 2e-13 on these runs and on the figure-5
#: run, where DOP853 at its smallest rtol reaches 3-4e-13; benchmarks/bench_integrate.py scans both).
TOL_EQUAL = 1e-11


#: Minor page faults of each path in its round of least CPU time (:func:`interleaved`).
FAULTS: dict[str, int] = {}


def interleaved(paths: dict[str, Callable[[], object]], rounds: int) -> dict[str, tuple[float, float, object]]:
    """Each path once per round, the rounds interleaved: the best (CPU seconds of this process, wall seconds) of each
    path over the rounds, and its last result (the page faults of its best round in ``FAULTS``)."""
    best: dict[str, tuple[float, float, object]] = {k: (math.inf, math.inf, None) for k in paths}
    for _ in range(rounds):
        for name, fn in paths.items():
            f0 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
            c0, w0 = time.process_time(), time.perf_counter()
            out = fn()
            cpu, wall = time.process_time() - c0, time.perf_counter() - w0
            if cpu < best[name][0]:
                FAULTS[name] = resource.getrusage(resource.RUSAGE_SELF).ru_minflt - f0
            best[name] = (min(best[name][0], cpu), min(best[name][1], wall), out)
    return best


def propagation_only(jobs: list[Job], tol: float, dense: bool) -> Callable[[], None]:
    """heyoka's batch propagation of the jobs alone, stretch by stretch as :func:`run_batch` integrates them
    (``BATCH_CHUNK_RADIANS`` of each lane's rate bound), integration and turning-point events (their Python callback
    recording each), with or without the dense output: the part of the lanes' work that is not bookkeeping.  (heyoka
    adds ≈ 1 ms per call that returns a dense output, whatever its length, so the stretches matter.)"""
    width = default_lanes()
    ta = batch_integrator(width, tol)

    def run() -> None:
        for k in range(0, len(jobs), width):
            batch = jobs[k:k + width]
            batch += batch[:1] * (width - len(batch))
            ta.set_time(0.0)
            ta.state[:] = np.stack([j.initial.to_body_state() for j in batch], axis=1)
            ta.pars[:] = np.stack([np.asarray(j.body.params, float) for j in batch], axis=1)
            t_end = np.array([j.t_end for j in batch])
            stretch = np.array([max(BATCH_CHUNK_RADIANS / rate_bound(j.body, j.initial.to_body_state()),
                                    default_dt(j.t_end, rate_bound(j.body, j.initial.to_body_state()), False))
                                for j in batch])
            t_a = np.zeros(width)
            while np.any(t_a < t_end):
                t_b = np.array([_stretch_end(a, e, s) if a < e else a for a, e, s in zip(t_a, t_end, stretch)])
                ta.nt_events[0].callback.events.clear()
                ta.propagate_until(t_b, c_output=dense)
                t_a = t_b
    return run


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
    batch_integrator(default_lanes())
    batch_integrator(default_lanes(), TOL_EQUAL)
    equal = [dataclasses.replace(j, tol=TOL_EQUAL) for j in jobs]
    load = os.getloadavg()[0]

    def before() -> list[RunSummary]:
        return [RunSummary.from_run(simulate(j.body, j.initial, j.t_end, samples=False,
                                             dt=DT_RADIANS / rate_bound(j.body, j.initial.to_body_state())))
                for j in jobs]

    paths: dict[str, Callable[[], object]] = {
        "before": before, "scalar": lambda: run_ensemble(jobs, progress=False, lanes=1),
        "lanes": lambda: run_ensemble(jobs, progress=False),
        "threads": lambda: run_ensemble(jobs, progress=False, threads=2),
        "lanes equal": lambda: run_ensemble(equal, progress=False),
        "propagation dense": propagation_only(equal, TOL_EQUAL, True),
        "propagation": propagation_only(equal, TOL_EQUAL, False)}
    run, why = cyrk_runner(body)
    rtol = 100 * float(np.finfo(float).eps)
    if run is not None:
        paths["cyrk"] = lambda: [run(np.asarray(j.initial.to_body_state(), float), np.asarray(j.body.params, float),
                                     j.t_end, rtol, 1e-20, np.empty(0)) for j in jobs]
    best = interleaved(paths, args.repeats)
    c_ref, w_ref, ref = best["before"]
    c_scalar, _, scalar = best["scalar"]
    c_lanes, _, lanes = best["lanes"]
    rows = [("fixed 0.15-radian grid: scalar, one by one", c_ref, w_ref, "reference"),
            ("run_ensemble(lanes=1): scalar, one by one", c_scalar, best["scalar"][1],
             "same turning points" if same_turning_points(scalar, ref) else "DIFFERENT turning points"),
            (f"run_ensemble: batches of {default_lanes()} lanes", c_lanes, best["lanes"][1], "batch reference"),
            (f"run_ensemble: batches of {default_lanes()} lanes, threads=2", *best["threads"][:2],
             "bit-identical" if identical(best["threads"][2], lanes) else "NOT bit-identical")]
    if not args.no_cluster:
        if importlib.util.find_spec("distributed") is None:
            print('(dask.distributed not installed: python -m pip install -e ".[distributed]" for the cluster row)')
        else:
            _, w, out = interleaved({"cluster": lambda: run_ensemble(jobs, workers=2, progress=False)}, 1)["cluster"]
            rows.append(("run_ensemble: workers=2 (LocalCluster start included)", math.nan, w,
                         "bit-identical" if identical(out, lanes) else "NOT bit-identical"))
    if run is None:
        print(why)
    else:
        rows.append((f"CyRK DOP853 compiled + events, rtol {rtol:.1e}, one by one", *best["cyrk"][:2], "peer"))
    n_max = sum(s.n_maxima for s in lanes) / len(lanes)
    print(f"{len(jobs)} jobs of {args.t_end:g} time units ({n_max:.0f} maxima each), best of {args.repeats} "
          f"interleaved rounds; {os.cpu_count()} cores, load average {load:.2f} at the start, "
          f"{os.getloadavg()[0]:.2f} at the end")
    print(f"{'path':62s} {'CPU ms/traj':>11s} {'wall ms/traj':>12s} {'CPU ratio':>9s}  check")
    for label, c, w, check in rows:  # a cluster's CPU time is its workers', not this process's: not shown
        cpu, ratio = ("-", "-") if math.isnan(c) else (f"{c / len(jobs) * 1e3:.2f}", f"{c_ref / c:.2f}x")
        print(f"{label:62s} {cpu:>11s} {w / len(jobs) * 1e3:12.2f} {ratio:>9s}  {check}")

    print("minor page faults per trajectory (system time, in the CPU times above; numerics.ensembles.batch."
          "_steady_malloc): " + ", ".join(f"{k} {FAULTS[k] / len(jobs):.0f}" for k in ("scalar", "lanes", "threads")))

    c_equal, _, at_equal = best["lanes equal"]
    print(f"\nat equal energy error (the same {len(jobs)} jobs; energy error: the largest of the jobs')")
    print(f"{'path':62s} {'CPU ms/traj':>11s} {'energy err':>11s}")
    rows_equal = [(f"run_ensemble: batches of {default_lanes()} lanes, tol {TOL_EQUAL:g}", c_equal,
                   f"{max(s.energy_rel_error for s in at_equal):.2e}"),
                  (f"  of which heyoka's batch propagation with dense output", best["propagation dense"][0], ""),
                  (f"  of which heyoka's batch propagation alone (no dense output)", best["propagation"][0], "")]
    if run is not None:
        grid = np.linspace(0.0, args.t_end, 3001)
        errors = []
        for j in jobs:  # untimed: CyRK's dense output on the grid
            states = np.asarray(run(np.asarray(j.initial.to_body_state(), float), np.asarray(j.body.params, float),
                                    j.t_end, rtol, 1e-20, grid)[2])
            E = energy(j.body, states[:, 0:3].T, states[:, 3:6].T)
            errors.append(float(np.max(np.abs(E - E[0])) / energy_scale(j.body, E[0])))
        rows_equal.append((f"CyRK DOP853 compiled + events, rtol {rtol:.1e}", best["cyrk"][0], f"{max(errors):.2e}"))
    for label, c, err in rows_equal:
        print(f"{label:62s} {c / len(jobs) * 1e3:11.2f} {err:>11s}")
    if run is not None:
        print(f"ratio CyRK / lanes at tol {TOL_EQUAL:g}: {best['cyrk'][0] / c_equal:.2f}x (asked: >= 1.5x); CyRK / "
              f"heyoka's propagation with dense output: {best['cyrk'][0] / best['propagation dense'][0]:.2f}x, "
              f"without: {best['cyrk'][0] / best['propagation'][0]:.2f}x")
    print(f"ratio scalar loop / lanes at tol = eps ({DEFAULT_TOL:.3g}): {c_scalar / c_lanes:.2f}x (asked: >= 3x)")


if __name__ == "__main__":
    main()
