"""The atlases' direct runs in the scalar integrator one by one and in heyoka's batch lanes, side by side in one process.

Run:  python benchmarks/bench_atlas_lanes.py [N]     (N × N, default 26)

* the plane of rates (φ̇0, ψ̇0) of the paper's reversal starts by the ODE (``rocknroller atlas --plane rates``,
  θ0 = 0.95π, ψ0 = π/4, 1000 time units, N × N runs);
* the ODE confirmation of every point of an N × N release atlas (θ0 in [0.75π, 0.95π], ψ0 in [0.01π, 0.49π],
  1000 time units; its release tables are built once and cached);
each with ``run_ensemble(lanes=1)`` (the scalar integrator, one run after another: the path before the batch lanes, its
turning points to the bit) and with the default batches, in this process, CPU seconds.  The two atlases of each
kind are compared: their observables agree to the integrators' rounding (the batches' turning points are the
scalar ones' within round-off, tests/numerics/ensembles/test_batch.py).
"""

from __future__ import annotations

import functools
import math
import os
import sys
import time

import numpy as np

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow import atlas as at
from rocknroller.analysis.slow.atlas_check import confirm_atlas
from rocknroller.numerics.ensembles import ensemble as ens


def timed(fn):
    c = time.process_time()
    out = fn()
    return out, time.process_time() - c


def largest_difference(a: at.Atlas, b: at.Atlas) -> float:
    """The largest difference of the two atlases' observables relative to each one's range."""
    worst = 0.0
    for k in at.ATLAS_OBSERVABLES:
        x, y = a.values[k].filled(np.nan), b.values[k].filled(np.nan)
        scale = np.nanmax(np.abs(x)) if np.any(np.isfinite(x)) else 1.0
        worst = max(worst, float(np.nanmax(np.abs(x - y), initial=0.0)) / (scale or 1.0))
    return worst


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 26
    body = Body.paper(1e-3)
    run_ensemble = ens.run_ensemble
    paths = {"lanes=1 (scalar)": functools.partial(run_ensemble, lanes=1), "batches": run_ensemble}
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    grid = np.linspace(-0.05, 0.45, n)
    at.atlas_of_rates(body, 0.95 * math.pi, math.pi / 4, grid[:2], grid[:1], 10.0, progress=False)  # compile/load
    results = {}
    for label, runner in paths.items():
        ens.run_ensemble = runner
        results[label] = timed(lambda: at.atlas_of_rates(body, 0.95 * math.pi, math.pi / 4, grid, grid, 1000.0,
                                                         progress=False))
    ens.run_ensemble = run_ensemble
    (a, c_a), (b, c_b) = results.values()
    print(f"{n} x {n} rates plane by the ODE: scalar one by one {c_a:.1f} s CPU, batch lanes {c_b:.1f} s: "
          f"{c_a / c_b:.2f}x; "
          f"observables differ by at most {largest_difference(a, b):.1e} of their range")

    theta0, psi0 = np.linspace(0.75, 0.95, n) * math.pi, np.linspace(0.01, 0.49, n) * math.pi
    atlas = at.atlas_from_rest(body, theta0, psi0, 1000.0, progress=False, chaos=False)  # the map, tables built once
    checks = {}
    for label, runner in paths.items():
        ens.run_ensemble = runner
        checks[label] = timed(lambda: confirm_atlas(atlas, body, every=1, progress=False, chaos=False))
    ens.run_ensemble = run_ensemble
    (a, c_a), (b, c_b) = checks.values()
    worst = max(float(np.nanmax(np.abs(a.ode[k].filled(np.nan) - b.ode[k].filled(np.nan)), initial=0.0))
                for k in at.ATLAS_OBSERVABLES)
    print(f"{n * n}-point ODE confirmation of the release atlas: scalar one by one {c_a:.1f} s CPU, batch lanes "
          f"{c_b:.1f} s: "
          f"{c_a / c_b:.2f}x; the ODE's observables differ by at most {worst:.1e}")


if __name__ == "__main__":
    main()
