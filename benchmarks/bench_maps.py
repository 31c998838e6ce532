"""Cost of the maps' exact tangents against the central differences they replace (side by side, one process; ratios).

Run:  python benchmarks/bench_maps.py

Paper body, θ0 = 0.95π, ε = 1e-2, at the start (Q_R, Q_J, Θ) = (1e-3, −2e-5, 1).  For each map, the least CPU time
over interleaved rounds of: one step (``__call__``), ``jacobian`` (the slow map: the compiled kernel's tangent map,
three kernel steps; the exact map: three variational runs through the rock), and fourth-order central differences
of ``__call__`` (period_doubling's steps 1e-6, 1e-6, 1e-5; 12 steps: what periodic orbits used before) and
second-order ones (6 steps).  Measured (2 shared cores, other jobs running): slow map (order 1): one step 13 µs,
jacobian 24 µs (1.9 steps), 0.14× the fourth-order and 0.31× the second-order differences; exact map: one step
26 ms, jacobian 26 ms (1.0 step: the three variational runs are leaner than a ``simulate`` run), 0.08× the
fourth-order and 0.16× the second-order differences.
"""

from __future__ import annotations

import math
import time

import numpy as np

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map.maps import ExactMap, SlowMap
from rocknroller.analysis.slow.dynamics.period_doubling import _central_jacobian

X = np.array([1e-3, -2e-5, 1.0])


def best_of(fns, n):
    """The least CPU time of each of ``fns`` over ``n`` interleaved rounds."""
    best = [math.inf] * len(fns)
    for _ in range(n):
        for i, fn in enumerate(fns):
            t0 = time.process_time()
            fn()
            best[i] = min(best[i], time.process_time() - t0)
    return best


def second_order(F, x):
    """(F(x + h e_j) − F(x − h e_j))/2h, steps 1e-6, 1e-6, 1e-5."""
    cols = []
    for j, h in enumerate((1e-6, 1e-6, 1e-5)):
        e = np.zeros(3)
        e[j] = h
        cols.append((F(x + e) - F(x - e)) / (2 * h))
    return np.stack(cols, axis=1)


def main() -> None:
    body = Body.paper(0.0)
    for name, F, rounds in (("slow (order 1)", SlowMap(body, 0.95 * math.pi, 1e-2), 200),
                            ("exact", ExactMap(body, 0.95 * math.pi, 1e-2), 5)):
        F.jacobian(X)  # compile / load, and the tangent rows
        step, jac, cd4, cd2 = best_of([lambda: F(X), lambda: F.jacobian(X), lambda: _central_jacobian(F, X),
                                       lambda: second_order(F, X)], rounds)
        print(f"{name:15s} step {step * 1e3:9.3f} ms   jacobian {jac * 1e3:9.3f} ms ({jac / step:5.1f} steps)   "
              f"central 4th {cd4 * 1e3:9.3f} ms (jacobian/central = {jac / cd4:.2f})   "
              f"central 2nd {cd2 * 1e3:9.3f} ms (jacobian/central = {jac / cd2:.2f})")


if __name__ == "__main__":
    main()
