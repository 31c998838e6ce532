"""Cost of the averaged predictions against the direct ODE (side by side, one process).

Run:  python benchmarks/bench_averaging.py

Paper body, ε = 1e-3, θ0 = 0.95π, ψ0 = π/4, 1000 time units.  Reports best-of-5 wall times of
* the direct ODE: numerics.integrate.simulate (heyoka, events, Trajectory; output every 100 t.u.);
* the averaged map once its tables exist (analysis.averaging.predict_slow_motion), and its loop
  alone (analysis.averaging.iterate_slow_map) per step;
* the closed form (analysis.slow_pendulum.pendulum_prediction, constants precomputed) and the
  one-dimensional quadratures of its constants;
* the one-off table build (first use per body and θ0; cached on disk afterwards).
"""

from __future__ import annotations

import math
import time

from analysis import averaging as av
from analysis.body import Body
from analysis.slow_pendulum import pendulum_constants, pendulum_prediction
from numerics.equations import EulerState
from numerics.integrate import simulate

THETA0, PSI0, EPS, T_END = 0.95 * math.pi, math.pi / 4, 1e-3, 1000.0


def best_of(fn, n=5):
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    body = Body.paper(EPS)
    t0 = time.perf_counter()
    table = av.build_table(body, THETA0)
    t_build = time.perf_counter() - t0
    consts = pendulum_constants(body, THETA0)
    simulate(body, EulerState(THETA0, 0.0, PSI0), 10.0)  # compile / load the integrator
    av.predict_slow_motion(body, THETA0, PSI0, T_END, table=table)  # run-time form of the table
    t_ode = best_of(lambda: simulate(body, EulerState(THETA0, 0.0, PSI0), T_END, dt=100.0))
    t_map = best_of(lambda: av.predict_slow_motion(body, THETA0, PSI0, T_END, table=table))
    n_steps = av.iterate_slow_map(table, EPS, PSI0, T_END).t.size + 1  # the step past t_end included
    t_loop = best_of(lambda: av.iterate_slow_map(table, EPS, PSI0, T_END), n=20)
    t_cf = best_of(lambda: pendulum_prediction(body, THETA0, PSI0, T_END, constants=consts))
    t_const = best_of(lambda: pendulum_constants(body, THETA0), n=3)
    print(f"direct ODE (heyoka, 1000 t.u.)       {t_ode * 1e3:9.2f} ms")
    print(f"averaged map (tables built)          {t_map * 1e3:9.2f} ms   ODE/map = {t_ode / t_map:6.1f}x")
    print(f"  of which the map loop ({n_steps} steps)    {t_loop * 1e3:9.2f} ms   {t_loop / n_steps * 1e6:6.1f} us/step")
    print(f"closed form (constants known)        {t_cf * 1e3:9.3f} ms   ODE/closed = {t_ode / t_cf:6.0f}x")
    print(f"closed-form constants (quadratures)  {t_const * 1e3:9.2f} ms")
    print(f"table build (once per body, theta0)  {t_build:9.2f} s")


if __name__ == "__main__":
    main()
