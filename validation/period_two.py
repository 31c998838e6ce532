"""Regenerates docs/averaging.md, "The period-2 orbit": the slow map's period-2 orbit against the exact map's.

Run:  python validation/period_two.py  [--order2]

Paper body, θ0 = 0.9π and 0.95π, ε = 1.05, 1.2, 1.5 × ε_pd (the exact map's, ``period_doubling``).  Prints Markdown:
per (θ0, ε), the period-2 orbit of the first-order slow map and of the exact one-step map (and with --order2 of the
second-order map, whose tables are built once and cached): Θ at the maxima, u along the kick direction, the kick
phase ϑ = Θ + W(Q)/2, Greene's residue, and the differences slow − exact; then the time each took.
"""

from __future__ import annotations

import argparse
import math
import time

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.dynamics.period_doubling import period_doubling
from rocknroller.analysis.slow.dynamics.periodic_orbits import periodic_orbit

FRACTIONS = (1.05, 1.2, 1.5)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--order2", action="store_true", help="also the second-order map")
    args = parser.parse_args()
    body = Body.paper(0.0)
    times: list[str] = []
    print("| θ0 | ε/ε_pd | map | Θ − π | u | ϑ − π | R | stable | Θ: slow − exact | u: slow − exact | "
          "ϑ: slow − exact | R: slow − exact |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for fraction in (0.9, 0.95):
        theta0 = fraction * math.pi
        t = time.perf_counter()
        pd = period_doubling(body, theta0)
        times.append(f"{fraction}π: period_doubling (exact ε_pd = {pd.eps_exact:.9g}, 4/κ = {pd.eps_first_order:.9g}) "
                     f"{time.perf_counter() - t:.2f} s")
        for f in FRACTIONS:
            eps = f * pd.eps_exact
            orbits = {}
            for name, kw in (("slow, order 1", {}), ("slow, order 2", {"order": 2, "workers": 2}), ("exact", {})):
                if name == "slow, order 2" and not args.order2:
                    continue
                if name == "exact":
                    kw = {"map": "exact", "start": orbits["slow, order 1"].points[0]}
                t = time.perf_counter()
                orbits[name] = periodic_orbit(body, theta0, eps, 2, **kw)
                times.append(f"{fraction}π, {f} ε_pd, {name}: {time.perf_counter() - t:.2f} s "
                             f"({orbits[name].iterations} Newton iterations)")
            e = orbits["exact"]
            for name, o in orbits.items():
                d = "" if name == "exact" else (
                    f" {o.points[0, 2] - e.points[0, 2]:+.1e} | {o.points[0, 0] - e.points[0, 0]:+.2e} | "
                    f"{o.kick_phase[0] - e.kick_phase[0]:+.2e} | {o.residue - e.residue:+.2e} |")
                print(f"| {fraction}π | {f} | {name} | {o.points[0, 2] - math.pi:+.1e} | {o.points[0, 0]:.7f} | "
                      f"±{o.kick_phase[0] - math.pi:.6f} | {o.residue:.6f} | {o.stable} |" + (d or " | | | |"))
    print()
    for line in times:
        print(f"- {line}")


if __name__ == "__main__":
    main()
