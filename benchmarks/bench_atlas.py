"""Cost of a recession atlas: 100 × 100 releases from rest over (ψ0, θ0), from cached tables; and the plane of
rates (φ̇0, ψ̇0) of the paper's reversal starts by the direct ODE.

Run:  python benchmarks/bench_atlas.py [N]          (N × N releases, default 100)
      python benchmarks/bench_atlas.py rates [N]    (N × N rates at θ0 = 0.95π, ψ0 = π/4, default 26)
Builds (once, cached) the release tables of N values of θ0 in [0.75π, 0.95π] (~7 s each), ψ0 in [0.01π, 0.49π],
then times the atlas
from the cached tables in a fresh process state (tables read from disk, their run-time form built) and a sample of
its ODE confirmation (1 point in 50) in this process, one at a time, against the map's cost per point.
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np

from rocknroller.analysis.slow import atlas as at
from rocknroller.analysis.slow.atlas_check import confirm_atlas
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.map import compiled_map as slow_map, table as slow_table
from rocknroller.analysis.model.body import Body


def rates(n: int) -> None:
    """The default rates plane of ``rocknroller atlas --plane rates`` by the ODE: one run after another, in two
    threads, and on a local dask cluster of two workers (startup included) when distributed is installed; the
    atlases must be identical."""
    body = Body.paper(1e-3)
    grid = np.linspace(-0.05, 0.45, n)
    where: list[tuple[str, dict]] = [("one at a time", {}), ("2 threads", {"threads": 2})]
    try:
        import distributed  # noqa: F401

        where.append(("local dask cluster, 2 workers (startup included)", {"workers": 2}))
    except ImportError:
        pass
    at.atlas_of_rates(body, 0.95 * math.pi, math.pi / 4, grid[:2], grid[:1], 10.0, progress=False)  # compile/load
    first, t_first = None, 0.0
    for label, kw in where:
        t0 = time.perf_counter()
        atlas = at.atlas_of_rates(body, 0.95 * math.pi, math.pi / 4, grid, grid, 1000.0, progress=False, **kw)
        dt = time.perf_counter() - t0
        if first is None:
            first, t_first = atlas, dt
        same = all(np.array_equal(atlas.values[k].filled(np.nan), first.values[k].filled(np.nan), equal_nan=True)
                   for k in at.ATLAS_OBSERVABLES)
        print(f"{n} x {n} rates plane by the ODE, {label}: {dt:.1f} s ({1e3 * dt / n**2:.1f} ms a run; "
              f"throughput {t_first / dt:.2f}x one at a time; identical: {same})")


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "rates":
        rates(int(sys.argv[2]) if len(sys.argv) > 2 else 26)
        return
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 100
    body = Body.paper(1e-3)
    theta0 = np.linspace(0.75, 0.95, n) * math.pi
    psi0 = np.linspace(0.01, 0.49, n) * math.pi  # not the equilibria ψ0 = 0, π/2 themselves (see below)
    t0 = time.perf_counter()
    for th in theta0:
        av.load_or_build_table(body, th)
    print(f"tables of {n} release angles ready in {time.perf_counter() - t0:.0f} s (built or read from the cache)")
    t_one = {}
    for workers, chaos in ((1, False), (1, True), (2, True)):
        slow_table._TABLES.clear()
        slow_map._FAST.clear()
        t0 = time.perf_counter()
        atlas = at.atlas_from_rest(body, theta0, psi0, 1000.0, progress=False, processes=workers, chaos=chaos)
        t_map = time.perf_counter() - t0
        if workers == 1:
            t_one[chaos] = t_map
        print(f"{n} x {n} atlas from cached tables, {workers} process(es), "
              f"{'with' if chaos else 'without'} its MEGNO layer: {t_map:.1f} s ({1e3 * t_map / n**2:.2f} ms a point)")
    print(f"the MEGNO layer: {t_one[True] / t_one[False]:.2f}x the atlas without it (one process)")
    t_map = t_one[True]
    t0 = time.perf_counter()
    confirm_atlas(atlas, body, every=50, progress=False, chaos=False)
    t_plain = time.perf_counter() - t0
    t0 = time.perf_counter()
    check = confirm_atlas(atlas, body, every=50, progress=False)
    t_ode = time.perf_counter() - t0
    k = len(check.index)
    print(f"ODE confirmation of {k} points (1 in 50), in process: {t_ode:.1f} s ({1e3 * t_ode / k:.0f} ms a point, "
          f"{t_ode / k / (t_map / n**2):.0f}x the map's cost), {t_ode / t_plain:.2f}x the confirmation without the "
          f"variational runs; regular/chaotic verdicts agree at {int(check.verdict_agrees.sum())} of "
          f"{int(check.verdict_agrees.count())} points")
    # near the separatrix of the slow pendulum (ψ0 → 0, the unstable rocking) the slow period diverges and the
    # runs depend sensitively on their start: the largest errors sit there; the percentiles say how typical they are
    for name in at.ATLAS_OBSERVABLES:
        err = np.ma.abs(check.rel_error[name]).compressed()
        what = "difference" if name.endswith("reversals") else "relative error"
        print(f"  map-ODE {what} of {name}: median {np.median(err):.3g}, 95th percentile "
              f"{np.percentile(err, 95):.3g}, largest {err.max():.3g}")


if __name__ == "__main__":
    main()
