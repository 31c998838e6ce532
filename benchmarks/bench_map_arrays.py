"""The maps on arrays of points against the Python loop over their rows (side by side, one process; wall and CPU).

Run:  python benchmarks/bench_map_arrays.py

Paper body, θ0 = 0.95π, ε = 1e-2, 1000 maxima x = (Q_R, Q_J, Θ) drawn inside the release table (chart coordinates
|u| ≤ 4e-3, |v| ≤ 2e-5 about Q = 0, Θ in [−6, 6]; seed 0).  For each case, the least wall (``perf_counter``) and CPU
(``process_time``) time over interleaved rounds of the array call (``F(X)``, ``F.jacobian(X)``, ``F.iterate(X, 10)``)
and of the loop ``[F(x) for x in X]`` (the same for the others), their ratio, and a check that both give the same
numbers bit for bit.  Also the period-2 start's scan of :func:`rocknroller.analysis.slow.dynamics.periodic_orbits.
periodic_orbit` (64 points of G = F − S on a line, the slow map), as it now runs (one array call) against a call per
point (as it ran before), and the exact map on 4 points (one direct run per row either way: no gain expected).

The slow map's array call makes one compiled-kernel call per row (its chart rotation, Θ continuation and checks are
NumPy operations on all rows at once); what it saves is the interpreter's work per call.  Measured (2 shared cores,
Intel Xeon with AVX-512F, load average ~1-2): F 7.3x wall and CPU (4.5 against 32 ms CPU for 1000 points), order 2
5.2x, the Jacobian 3.9x (its three kernel calls with the tangent vector per row dominate), iterate(x, 10) 2.8x, the
scan 6.1x, the exact map 1.0x CPU (its wall time follows the machine's other load).
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.dynamics.periodic_orbits import _SCAN, _Problem
from rocknroller.analysis.slow.map.maps import ExactMap, SlowMap

THETA0, EPS, N = 0.95 * math.pi, 1e-2, 1000


def best_of(fns, n):
    """The least (wall, CPU) time of each of ``fns`` over ``n`` interleaved rounds."""
    best = [[math.inf, math.inf] for _ in fns]
    for _ in range(n):
        for i, fn in enumerate(fns):
            w0, c0 = time.perf_counter(), time.process_time()
            fn()
            best[i][0] = min(best[i][0], time.perf_counter() - w0)
            best[i][1] = min(best[i][1], time.process_time() - c0)
    return best


def points(F: SlowMap, n: int) -> np.ndarray:
    """n maxima inside F's release table (module docstring)."""
    rng = np.random.default_rng(0)
    u, v = rng.uniform(-4e-3, 4e-3, n), rng.uniform(-2e-5, 2e-5, n)
    Q = np.outer(u, F.table.e) + np.outer(v, F.table.n)
    return np.column_stack([Q, rng.uniform(-6.0, 6.0, n)])


def compare(name: str, array, loop, rounds: int) -> None:
    assert np.array_equal(array(), loop(), equal_nan=True), f"{name}: the array call and the loop differ"
    (wa, ca), (wl, cl) = best_of([array, loop], rounds)
    print(f"{name:34s} array {wa * 1e3:9.2f} ms wall {ca * 1e3:9.2f} ms CPU   loop {wl * 1e3:9.2f} ms wall "
          f"{cl * 1e3:9.2f} ms CPU   speed-up {wl / wa:5.1f}x wall {cl / ca:5.1f}x CPU")


def vector_unit() -> str:
    info = Path("/proc/cpuinfo")
    flags = next((line.split(":", 1)[1].split() for line in info.read_text().splitlines()
                  if line.startswith("flags")), []) if info.exists() else []
    return next((unit for flag, unit in (("avx512f", "AVX-512F"), ("avx2", "AVX2"), ("sse4_2", "SSE4.2"))
                 if flag in flags), "unknown")


def main() -> None:
    print(f"CPU vector unit: {vector_unit()}; {N} points")
    body = Body.paper(0.0)
    for order in (1, 2):
        F = SlowMap(body, THETA0, EPS, order)
        X = points(F, N)
        F.jacobian(X[:1])  # the run-time form and the tangent rows, built once
        compare(f"slow (order {order}) F", lambda: F(X), lambda: np.array([F(x) for x in X]), 30)
        if order == 1:
            compare("slow (order 1) jacobian", lambda: F.jacobian(X), lambda: np.array([F.jacobian(x) for x in X]),
                    10)
            compare("slow (order 1) iterate(x, 10)", lambda: F.iterate(X, 10),
                    lambda: np.array([F.iterate(x, 10) for x in X]), 10)
    P = _Problem(body, THETA0, 1.2 * 4.0 / abs(F.kappa), "slow", 1, 1)
    us = float(P.table.U) * np.geomspace(*_SCAN)
    line = np.column_stack([us, np.zeros_like(us), np.full_like(us, P.theta_star)])
    compare("periodic_orbit's scan (64 points)", lambda: P.G(line, failed="nan")[:, 0],
            lambda: np.array([P.G(x, failed="nan")[0] for x in line]), 100)
    E = ExactMap(body, THETA0, EPS)
    XE = points(F, 4)
    compare("exact F (4 points)", lambda: E(XE), lambda: np.array([E(x) for x in XE]), 3)


if __name__ == "__main__":
    main()
