"""Cost of the direct motion's chaos indicators against the plain run over the same orbit (a ratio, not a time).

    python benchmarks/bench_variational.py [ROCKS]

:func:`rocknroller.numerics.variational.direct_chaos_indicators` (the (γ, ω) system and one tangent vector, 12
equations, the θ-maxima as terminal events, a renormalisation at each) against ``simulate(..., samples=False)``
(the 11-equation system, its turning points checked on the dense output, the angles unwrapped on its grid), from
the same start over the same time: a regular release (θ0 = 0.95π, ε = 1e-2, ψ0 = π/4) and a chaotic one (ψ0 = 0.1).
Each is timed as the best of three (CPU time of this process), after a first call that compiles or loads both
integrators.  Also prints the CPU seconds per radian of Λ t of the variational run, beside the package's estimate
``VARIATIONAL_SECONDS_PER_RADIAN`` used by its work budget.
"""

from __future__ import annotations

import math
import sys
import time

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.numerics.integrate import simulate
from rocknroller.numerics.variational import VARIATIONAL_SECONDS_PER_RADIAN, direct_chaos_indicators


def best_cpu(call, repeats: int = 3) -> float:
    best = math.inf
    for _ in range(repeats):
        t0 = time.process_time()
        call()
        best = min(best, time.process_time() - t0)
    return best


def main(rocks: int = 1000) -> None:
    body = Body.paper(1e-2)
    t_end = 12.6 * rocks  # one θ-maximum per ≈ 12.6 time units at θ0 = 0.95π
    for psi0, kind in ((math.pi / 4, "regular"), (0.1, "chaotic")):
        start = EulerState(0.95 * math.pi, 0.0, psi0)
        run = direct_chaos_indicators(body, start, 200.0)  # compiles (or loads) both integrators
        simulate(body, start, 100.0, samples=False)
        var = best_cpu(lambda: direct_chaos_indicators(body, start, t_end))
        plain = best_cpu(lambda: simulate(body, start, t_end, samples=False))
        radians = run.rate * t_end
        print(f"{kind} (psi0 = {psi0:.4g}), t_end = {t_end:g} ({rocks} rocks): variational / simulate = "
              f"{var / plain:.2f}; variational {var / radians:.2e} s per radian of Lambda t "
              f"(estimate {VARIATIONAL_SECONDS_PER_RADIAN:.1e})")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1000)
