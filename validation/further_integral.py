"""Regenerates docs/further_integral.md: is there a further integral of the rock'n'roller?  Borisov and Mamaev's
M² − 2K r² with and without gravity, beside the direct motion's chaos indicators in the separatrix layer.

Run:  python validation/further_integral.py  [--t-end 20000]

Paper body (a = 0.05, I3 = 0.4, I1 = 0.35, I2 = (1 + ε) I1) at ε = 1e-3, 3e-3, 1e-2, 2e-2.  Prints Markdown:
1. B = M² − 2E r² (:func:`rocknroller.analysis.model.invariants.borisov_mamaev`) along direct runs of 500 time
   units from θ0 = 0.6π, ω0 = (0.3, 1, −0.7), at g = 0 and g = 9.87: its swing max B − min B over the run relative
   to the scale of its terms (M² + 2E r²), beside the run's energy error; and M² − 2T r² with the kinetic energy T,
   the other reading of K, at g = 9.87.
2. In the chaotic layer about the unstable rocking (releases from rest at θ0 = 0.95π, ψ0 = 0.003 and 0.1, g = 9.87):
   the direct ODE's MEGNO and finite-time maximal Lyapunov exponent (heyoka's variational equations,
   :func:`rocknroller.numerics.variational.direct_chaos_indicators`) over t_end, and the same with a start 1e-10
   away in ψ0 (the twin).  A positive exponent with MEGNO growing like λt/2 on an orbit that fills a layer is
   numerical evidence that no further smooth integral exists there (such an integral would confine the orbit to a
   2-torus of the 3-dimensional energy surface of the reduced motion, where MEGNO tends to 2).
Then the cost of each part.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.model.invariants import borisov_mamaev, contact_momentum, energy
from rocknroller.numerics.integrate import simulate
from rocknroller.numerics.variational import direct_chaos_indicators

EPSILONS = (1e-3, 3e-3, 1e-2, 2e-2)
START = EulerState.from_omega(0.6 * math.pi, 0.0, 0.0, (0.3, 1.0, -0.7))
LAYER_PSI0 = (0.003, 0.1)


def swings(body: Body, t_end: float) -> tuple[float, float, float]:
    """Relative swings of M² − 2E r² and M² − 2T r² along a direct run, and the run's energy error."""
    traj = simulate(body, START, t_end)
    gam, om = traj.gamma, traj.omega
    M = contact_momentum(body, gam, om)
    M2 = np.sum(M * M, axis=0)
    r2 = gam[0] ** 2 + gam[1] ** 2 + (gam[2] - body.a) ** 2
    E = energy(body, gam, om)
    T = E - body.g * body.a * (1.0 - gam[2])
    scale = float(np.max(M2 + 2.0 * np.abs(E) * r2))
    with_E = float(np.ptp(borisov_mamaev(body, gam, om))) / scale
    with_T = float(np.ptp(M2 - 2.0 * T * r2)) / scale
    return with_E, with_T, traj.energy_rel_error


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--t-end", type=float, default=20000.0, help="span of the chaos indicators (default 20000)")
    args = parser.parse_args()
    t0 = time.process_time()
    print("| ε | g | swing of M² − 2E r² | swing of M² − 2T r² | energy error |")
    print("|---|---|---|---|---|")
    for eps in (0.0,) + EPSILONS:
        for g in (0.0, 9.87):
            body = Body(0.05, 0.35, 0.35 * (1.0 + eps), 0.4, g)
            with_E, with_T, err = swings(body, 500.0)
            print(f"| {eps:g} | {g:g} | {with_E:.1e} | {with_T:.1e} | {err:.1e} |")
    cost_b = time.process_time() - t0
    print()
    print(f"| ε | ψ0 | MEGNO | λ (1/time unit) | Lyapunov time | twin: MEGNO | twin: λ | verdict (MEGNO > 3) |")
    print("|---|---|---|---|---|---|---|---|")
    t1 = time.process_time()
    for eps in EPSILONS:
        body = Body(0.05, 0.35, 0.35 * (1.0 + eps), 0.4, 9.87)
        for psi0 in LAYER_PSI0:
            runs = [direct_chaos_indicators(body, EulerState(0.95 * math.pi, psi=psi0 + d), args.t_end, budget=None)
                    for d in (0.0, 1e-10)]
            a, b = (r.indicators for r in runs)
            verdict = "chaotic" if a.megno > 3.0 and b.megno > 3.0 else ("regular" if a.megno <= 3.0 and
                                                                          b.megno <= 3.0 else "undecided")
            print(f"| {eps:g} | {psi0:g} | {a.megno:.2f} | {a.lyapunov:.2e} | {1.0 / a.lyapunov if a.lyapunov else math.inf:.3g} | "
                  f"{b.megno:.2f} | {b.lyapunov:.2e} | {verdict} |")
    cost_c = time.process_time() - t1
    print()
    print(f"- cost: the integral's runs {cost_b:.1f} s CPU; the chaos indicators ({2 * len(EPSILONS) * len(LAYER_PSI0)} "
          f"variational runs of {args.t_end:g} time units) {cost_c:.1f} s CPU")


if __name__ == "__main__":
    main()
