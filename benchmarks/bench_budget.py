"""The rates behind the work estimates of ``rocknroller.numerics.budget``, measured again beside its constants.

Run:  python benchmarks/bench_budget.py            (the rates)
      python benchmarks/bench_budget.py commands [portrait] [atlas] [bifurcation]   (their whole estimates, below)
CPU seconds (process time, threads included) of: the direct ODE per radian of Λ·t with heyoka and with scipy's
DOP853 (turning points only, the same start), one release table and one region table built in one process (in a
fresh cache folder), one mpmath precession point at 30, 120 and 240 digits, the averaged map per θ-maximum at
orders 1 and 2, and the exact map's ε_pd and one of its periodic orbits.  Each line prints the measurement,
the constant, and their ratio: an estimate is meant to hold within a factor of about two (the constants are rounded
up; the machine's load, printed first, moves the measurements).

``commands``: ``rocknroller portrait``, ``atlas`` and ``bifurcation`` run in this process (``rocknroller.cli.main``,
CPU seconds of the whole command, its spawned builders' included: tables, runs, probes, confirmations, files) at
three sizes each, in an empty cache folder (the tables each needs first built by the run that needs them: the
portrait's first, the atlas's first; the bifurcation's first only when run alone), against the estimate the command checks its ``--budget`` with, taken just
before it runs (so that the cache is in the same state): estimate/measured is meant to lie in [1, 3].
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


def _command(argv: list[str], estimate) -> tuple[float, float]:
    """(estimate, measured CPU seconds) of ``rocknroller ARGV`` in this process, the estimate taken first."""
    from rocknroller.cli import main as cli

    before = estimate()
    t, wall = _cpu(), time.perf_counter()
    status = cli(argv)
    measured, wall = _cpu() - t, time.perf_counter() - wall
    if status != 0:
        raise RuntimeError(f"rocknroller {' '.join(argv)} failed")
    print(f"[{' '.join(argv[:1])}: {measured:.3g} s of CPU, {wall:.3g} s of wall time]", flush=True)
    return before, measured


def _cpu() -> float:
    """CPU seconds of this process (threads included) and of its finished children (spawned builders)."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def commands(which: tuple[str, ...] = ("portrait", "atlas", "bifurcation")) -> None:
    """The three commands' estimates against their measured CPU seconds, three sizes each (module docstring), or
    those of the commands in ``which``."""
    os.environ["ROCKNROLLER_CACHE"] = tempfile.mkdtemp(prefix="bench_budget_commands_")
    import numpy as np

    from rocknroller.analysis.model.body import Body
    from rocknroller.analysis.slow.atlas import atlas_seconds
    from rocknroller.analysis.slow.atlas_check import confirm_seconds
    from rocknroller.cli.atlas import CONFIRM_EVERY
    from rocknroller.papers.bifurcation import FILES_SECONDS, bifurcation_seconds
    from rocknroller.papers.portrait_limits import portrait_seconds

    print(f"load average: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    out = tempfile.mkdtemp(prefix="bench_budget_out_")
    rows = []
    th = 0.95 * math.pi
    portrait_body = Body.paper(5e-3)
    for label, n_theta, n_p, t_end, order in (("18 orbits, t_end 2000, order 2, empty cache", 2, 9, 2000.0, 2),
                                               ("90 orbits, t_end 2000, order 2 (the default)", 10, 9, 2000.0, 2),
                                               ("400 orbits, t_end 20000, order 1", 40, 10, 20000.0, 1)
                                               )[:3 if "portrait" in which else 0]:
        argv = ["portrait", "--eps", "5e-3", "--Theta", f"0.05pi:1.95pi:{n_theta}", "--t-end", f"{t_end:g}",
                "--order", str(order), "--out", os.path.join(out, f"portrait{len(rows)}"), "--quiet", "--budget", "inf"]
        if n_p != 9:
            argv[5:5] = ["--p", f"-0.1:0.1:{n_p}"]
        est = lambda: portrait_seconds(portrait_body, th, n_theta * n_p, t_end, order=order, horizons=True,
                                       files=True)[0]
        rows.append(("portrait " + label, *_command(argv, est)))
    atlas_body = Body.paper(1e-3)
    for label, n_psi, t_end in (("2 x 20 points, t_end 1000, empty cache", 20, 1000.0),
                                ("2 x 500 points, t_end 1000", 500, 1000.0),
                                ("2 x 1500 points, t_end 2000", 1500, 2000.0))[:3 if "atlas" in which else 0]:
        theta0, psi0 = np.linspace(0.9 * math.pi, 0.95 * math.pi, 2), np.linspace(0.0, 3.0, n_psi)
        argv = ["atlas", "--eps", "1e-3", "--theta0", "0.9pi:0.95pi:2", "--psi0", f"0:3:{n_psi}", "--t-end",
                f"{t_end:g}", "--out", os.path.join(out, f"atlas{len(rows)}"), "--quiet", "--budget", "inf"]
        est = lambda: (atlas_seconds(atlas_body, theta0, n_psi, t_end, files=True)[0]
                       + confirm_seconds(atlas_body, theta0, psi0, t_end, every=CONFIRM_EVERY)[0])
        rows.append(("atlas " + label, *_command(argv, est)))
    sym = Body.paper()
    for label, points, exact, order in (("5 points, exact at 0.9, order 1", 5, [0.9], 1),
                                        ("40 points, exact at 0.9 1.2, order 1", 40, [0.9, 1.2], 1),
                                        ("111 points, 4 exact fractions, order 2", 111, [0.9, 1.05, 1.2, 1.5], 2)
                                        )[:3 if "bifurcation" in which else 0]:
        argv = ["bifurcation", "--theta0", "0.95pi", "--points", str(points), "--exact-at", *map(str, exact),
                "--order", str(order), "--out", os.path.join(out, f"bif{len(rows)}"), "--quiet", "--budget", "inf"]
        est = lambda: bifurcation_seconds(sym, [th], points, exact, order) + FILES_SECONDS
        rows.append(("bifurcation " + label, *_command(argv, est)))
    print(f"{'command':62s} {'estimate':>9s} {'measured':>9s} {'estimate/measured':>18s}")
    for what, est, measured in rows:
        print(f"{what:62s} {est:9.3g} {measured:9.3g} {est / measured:18.2f}", flush=True)


if __name__ == "__main__":
    import sys

    if sys.argv[1:2] == ["commands"]:
        commands(tuple(sys.argv[2:]) or ("portrait", "atlas", "bifurcation"))
    else:
        main()
