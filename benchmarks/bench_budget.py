"""The rates behind the work estimates of ``rocknroller.numerics.budget``, measured again beside its constants.

Run:  python benchmarks/bench_budget.py
CPU seconds (process time, threads included) of: the direct ODE per radian of Λ·t with heyoka and with scipy's
DOP853 (turning points only, the same start), one release table and one region table built in one process (in a
fresh cache folder), one mpmath precession point at 30, 120 and 240 digits, the averaged map per θ-maximum at
orders 1 and 2, and the exact map's ε_pd and one of its periodic orbits.  Each line prints the measurement,
the constant, and their ratio: an estimate is meant to hold within a factor of about two (the constants are rounded
up; the machine's load, printed first, moves the measurements).
"""

from __future__ import annotations

import math
import os
import tempfile
import time


def cpu(fn) -> float:
    t = time.process_time()
    fn()
    return time.process_time() - t


def main() -> None:
    os.environ["ROCKNROLLER_CACHE"] = tempfile.mkdtemp(prefix="bench_budget_")
    from rocknroller.analysis.model.body import Body
    from rocknroller.analysis.model.equations import EulerState
    from rocknroller.analysis.routh.quadrature_mp import precession_mp
    from rocknroller.analysis.slow.map.family import rest_energy
    from rocknroller.analysis.slow.map.region import build_region_table
    from rocknroller.analysis.slow.map.table import build_table
    from rocknroller.numerics import budget
    from rocknroller.numerics.integrate import check_run, simulate

    print(f"load average: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    body, start = Body.paper(1e-3), EulerState(0.95 * math.pi, 0.0, 0.5)
    simulate(body, start, 10.0, samples=False)  # the compiled integrator, from heyoka's cache
    rows = []
    simulate(body, start, 10.0, samples=False, precision="extended")
    for method, precision, t_end, const in (("heyoka", "double", 20000.0, budget.HEYOKA_SECONDS_PER_RADIAN),
                                            ("heyoka", "extended", 3000.0, budget.HEYOKA_EXTENDED_SECONDS_PER_RADIAN),
                                            ("scipy", "double", 500.0, budget.DOP853_SECONDS_PER_RADIAN)):
        radians = check_run(body, start, t_end, samples=False).rate * t_end
        rate = cpu(lambda: simulate(body, start, t_end, samples=False, method=method, precision=precision)) / radians
        rows.append((f"direct ODE, {method} {precision}, s per radian", rate, const))
    sym = Body.paper()
    rows.append(("release table (theta0 = 0.93pi)", cpu(lambda: build_table(sym, 0.93 * math.pi, progress=False)),
                 budget.RELEASE_TABLE_SECONDS))
    E = rest_energy(sym, 0.7 * math.pi)  # the band chart: the region tables' dearer kind
    rows.append(("region table (E of a release at 0.7pi)", cpu(lambda: build_region_table(sym, E, progress=False)),
                 budget.REGION_TABLE_SECONDS))
    from rocknroller.analysis.slow.dynamics.period_doubling import period_doubling
    from rocknroller.analysis.slow.dynamics.periodic_orbits import periodic_orbit
    from rocknroller.analysis.slow.prediction import predict_slow_motion

    th, mapped = 0.95 * math.pi, Body.paper(5e-3)
    for order, const in ((1, budget.MAP_SECONDS_PER_MAXIMUM), (2, budget.MAP_ORDER2_SECONDS_PER_MAXIMUM)):
        predict_slow_motion(mapped, th, 0.3, 100.0, order=order)  # its tables, built once
        found = []
        seconds = cpu(lambda: found.append(predict_slow_motion(mapped, th, 0.3, 2e5, order=order)))
        rows.append((f"slow map order {order}, s per theta-maximum", seconds / found[0].series.t.size, const))
    pd = []
    rows.append(("exact map's eps_pd (theta0 = 0.93pi)", cpu(lambda: pd.append(period_doubling(sym, 0.93 * math.pi))),
                 budget.PERIOD_DOUBLING_SECONDS))
    rows.append(("exact map's period-1 orbit", cpu(lambda: periodic_orbit(sym, 0.93 * math.pi, 0.9 * pd[0].eps_exact,
                                                                          1, map="exact")),
                 budget.EXACT_ORBIT_SECONDS))
    for dps in (30, 120, 240):
        rows.append((f"mpmath point, {dps} digits", cpu(lambda: precession_mp(1.0, 0.01, 0.02, sym, dps=dps)),
                     budget.mp_point_seconds(dps)))
    print(f"{'what':42s} {'measured':>10s} {'constant':>10s} {'constant/measured':>18s}")
    for what, measured, const in rows:
        print(f"{what:42s} {measured:10.3g} {const:10.3g} {const / measured:18.2f}")


if __name__ == "__main__":
    main()
