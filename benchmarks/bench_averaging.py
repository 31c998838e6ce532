"""Cost of the averaged predictions against the direct ODE (side by side, one process).

Run:  python benchmarks/bench_averaging.py

Paper body, ε = 1e-3, θ0 = 0.95π, ψ0 = π/4, 1000 time units.  Reports best-of-5 wall times of
* the direct ODE producing the same prediction (rocknroller.papers.averaging_check.ode_slow_summary: heyoka with
  events, then the same slow diagnostics at its θ-maxima), and the integration alone
  (rocknroller.numerics.integrate.simulate, output every 100 t.u.);
* the averaged map once its tables exist (rocknroller.analysis.slow.prediction.predict_slow_motion: the compiled
  step loop, then the diagnostics), and its loop alone (rocknroller.analysis.slow.prediction.iterate_slow_map) per step;
* the closed form (rocknroller.analysis.slow.dynamics.pendulum.pendulum_prediction, constants precomputed) and the
  one-dimensional quadratures of its constants;
* the one-off table build (first use per body and θ0; cached on disk afterwards).
"""

from __future__ import annotations

import math
import time
import warnings

from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.dynamics.pendulum import pendulum_constants, pendulum_prediction
from rocknroller.analysis.model.equations import EulerState
from rocknroller.numerics.integrate import simulate
from rocknroller.papers.averaging_check import ode_slow_summary

THETA0, PSI0, EPS, T_END = 0.95 * math.pi, math.pi / 4, 1e-3, 1000.0
PSI0_GRID = {"pi/8": math.pi / 8, "pi/4": math.pi / 4, "3pi/8": 3 * math.pi / 8, "3.9pi/8": 3.9 * math.pi / 8}


def best_of(fn, n=5):
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    warnings.simplefilter("ignore")  # K > 4 at eps = 1e-2 warns: the timing is still meaningful
    body = Body.paper(EPS)
    t0 = time.perf_counter()
    table = av.build_table(body, THETA0)
    t_build = time.perf_counter() - t0
    consts = pendulum_constants(body, THETA0)
    simulate(body, EulerState(THETA0, 0.0, PSI0), 10.0)  # compile / load the integrator
    av.predict_slow_motion(body, THETA0, PSI0, T_END, table=table, order=1)  # run-time form of the table
    t_ode = best_of(lambda: ode_slow_summary(body, THETA0, PSI0, T_END))
    t_sim = best_of(lambda: simulate(body, EulerState(THETA0, 0.0, PSI0), T_END, dt=100.0))
    t_map = best_of(lambda: av.predict_slow_motion(body, THETA0, PSI0, T_END, table=table, order=1), n=20)
    n_steps = av.iterate_slow_map(table, EPS, PSI0, T_END).t.size + 1  # the step past t_end included
    t_loop = best_of(lambda: av.iterate_slow_map(table, EPS, PSI0, T_END), n=20)
    t_cf = best_of(lambda: pendulum_prediction(body, THETA0, PSI0, T_END, constants=consts))
    t_const = best_of(lambda: pendulum_constants(body, THETA0), n=3)
    print(f"direct ODE + diagnostics (1000 t.u.) {t_ode * 1e3:9.2f} ms")
    print(f"  of which the integration (heyoka)  {t_sim * 1e3:9.2f} ms")
    print(f"averaged map + diagnostics           {t_map * 1e3:9.2f} ms   ODE/map = {t_ode / t_map:6.1f}x"
          f"   (integration alone / map = {t_sim / t_map:.1f}x)")
    print(f"  of which the map loop ({n_steps} steps)    {t_loop * 1e3:9.2f} ms   {t_loop / n_steps * 1e6:6.1f} us/step")
    print(f"closed form (constants known)        {t_cf * 1e3:9.3f} ms   ODE/closed = {t_ode / t_cf:6.0f}x")
    print(f"closed-form constants (quadratures)  {t_const * 1e3:9.2f} ms")
    print(f"table build (once per body, theta0)  {t_build:9.2f} s")
    print("\nODE/map (both with the diagnostics) over the acceptance grid of psi0 and eps:")
    print("   eps     " + "".join(f"{name:>10}" for name in PSI0_GRID))
    for eps in (1e-2, 1e-3, 1e-4):
        b = Body.paper(eps)
        ratios = []
        for psi0 in PSI0_GRID.values():
            t_o = best_of(lambda: ode_slow_summary(b, THETA0, psi0, T_END), n=3)
            t_m = best_of(lambda: av.predict_slow_motion(b, THETA0, psi0, T_END, table=table, order=1), n=10)
            ratios.append(t_o / t_m)
        print(f"  {eps:7.0e}  " + "".join(f"{r:9.1f}x" for r in ratios))


if __name__ == "__main__":
    main()
