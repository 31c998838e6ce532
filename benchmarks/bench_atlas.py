"""Cost of a recession atlas: 100 × 100 releases from rest over (ψ0, θ0), from cached tables.

Run:  python benchmarks/bench_atlas.py [N]      (N × N points, default 100)
Builds (once, cached) the release tables of N values of θ0 in [0.75π, 0.95π] (~7 s each), then times the atlas
from the cached tables in a fresh process state (tables read from disk, their run-time form built) and a sample of
its ODE confirmation (1 point in 50) in this process, one at a time, against the map's cost per point.
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np

from rocknroller.analysis import atlas as at
from rocknroller.analysis import averaging as av
from rocknroller.analysis.body import Body


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 100
    body = Body.paper(1e-3)
    theta0 = np.linspace(0.75, 0.95, n) * math.pi
    psi0 = np.linspace(0.0, 0.5, n) * math.pi
    t0 = time.perf_counter()
    for th in theta0:
        av.load_or_build_table(body, th)
    print(f"tables of {n} release angles ready in {time.perf_counter() - t0:.0f} s (built or read from the cache)")
    av._TABLES.clear()
    av._FAST.clear()
    t0 = time.perf_counter()
    atlas = at.atlas_from_rest(body, theta0, psi0, 1000.0, progress=False)
    t_map = time.perf_counter() - t0
    print(f"{n} x {n} atlas from cached tables: {t_map:.1f} s ({1e3 * t_map / n**2:.2f} ms a point)")
    t0 = time.perf_counter()
    check = at.confirm_atlas(atlas, body, every=50, progress=False)
    t_ode = time.perf_counter() - t0
    k = len(check.index)
    print(f"ODE confirmation of {k} points (1 in 50), in process: {t_ode:.1f} s ({1e3 * t_ode / k:.0f} ms a point, "
          f"{t_ode / k / (t_map / n**2):.0f}x the map's cost)")
    for name in at.ATLAS_OBSERVABLES:
        err = np.ma.abs(check.rel_error[name])
        print(f"  largest map-ODE {'difference' if name.endswith('reversals') else 'relative error'} of {name}: "
              f"{np.ma.max(err):.3g} (median {np.ma.median(err):.3g})")


if __name__ == "__main__":
    main()
