"""Long run with only the turning points kept: 10⁵ rocks (θ0 = 0.95π, ε = 1e-3), peak memory and time.

    python benchmarks/bench_long_run.py [ROCKS]

The run keeps the turning points only (``simulate(..., samples=False)``): the integrator's dense
output is processed stretch by stretch and dropped, so memory does not grow with the series.  Peak
memory is the process's maximum resident set size (``resource.getrusage``), which includes the
interpreter, numpy, scipy and heyoka (≈ 0.2 GB before the run starts).  Keeping every sample of this
run (≈ 2.6·10⁷ samples at the default spacing) would need ≈ 14 GB and is refused by the limits.

It also counts the run's minor page faults and system time: each stretch's buffers must be reused from the heap,
not mapped anew (at ``CHUNK_RADIANS`` = 2e4 a 2e5-time-unit run took 245 000 faults, 10 % of its CPU in the
kernel; at 5e3, with 2**14-point grid pieces, 19 000 and 1 %).
"""

from __future__ import annotations

import math
import resource
import sys
import time

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.numerics.integrate import heyoka_integrator, simulate


def peak_rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # Linux: kB


def main(rocks: int = 100_000) -> None:
    body = Body.paper(1e-3)
    start = EulerState(0.95 * math.pi, psi=math.pi / 4)
    heyoka_integrator()
    base = peak_rss_mb()
    probe = simulate(body, start, 1000.0, samples=False)
    t_end = 1000.0 * rocks / len(probe.maxima)
    before = resource.getrusage(resource.RUSAGE_SELF)
    t0 = time.perf_counter()
    run = simulate(body, start, t_end, samples=False, progress=None)
    elapsed = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_SELF)
    print(f"t_end = {t_end:.6g}: {len(run.maxima)} maxima, {len(run.minima)} minima, {run.n_steps} steps")
    print(f"time {elapsed:.1f} s ({1e6 * elapsed / run.n_steps:.1f} µs/step); peak RSS {peak_rss_mb():.0f} MB "
          f"(interpreter and libraries before the run: {base:.0f} MB)")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    print(f"minor page faults {after.ru_minflt - before.ru_minflt}; system time {after.ru_stime - before.ru_stime:.2f} s "
          f"of {cpu:.2f} s CPU")
    print(f"energy error {run.energy_rel_error:.2e} (bound {run.energy_tolerance:.2e}); Phi = {run.Phi:.6f}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 100_000)
