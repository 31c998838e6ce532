"""Regenerates docs/slow_validation.md, "Releases from rest, first order": the map and the closed form vs the ODE.

Run:  python validation/averaging_table.py  [--theta0 0.95pi] [--t-end 1000]

Paper body, released from rest at θ0, ψ0 ∈ {π/8, π/4, 3π/8, 3.9π/8}, ε ∈ {1e-2, 1e-3, 1e-4} (map) and
{1e-3, 1e-4, 1e-5} (closed form; at ε = 1e-5 the run is 3000 time units so that the slow period is
measurable).  Prints Markdown: relative errors of the slow period, the Q_R extent, Φ and the line
slope; the largest maximum-by-maximum differences map − ODE; and the log-log slopes over ε.
"""

from __future__ import annotations

import argparse
import math

from rocknroller.analysis.slow.prediction import load_or_build_table
from rocknroller.papers.averaging_check import compare_with_ode, loglog_slope
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.dynamics.pendulum import pendulum_constants
from rocknroller.cli.options import parse_angle

PSI0 = {"π/8": math.pi / 8, "π/4": math.pi / 4, "3π/8": 3 * math.pi / 8, "3.9π/8": 3.9 * math.pi / 8}
EPS_MAP = (1e-2, 1e-3, 1e-4)
EPS_CF = (1e-3, 1e-4, 1e-5)
QUANT = ("slow_period", "QR_extent", "Phi", "line_slope")


def fmt(x: float | None) -> str:
    return "n/a" if x is None else f"{x:+.2e}"


def print_table(title: str, header: list[str], rows: list[list[str]]) -> None:
    """A Markdown table with a ### title."""
    print(f"\n### {title}\n")
    print("| " + " | ".join(header) + " |")
    print("|---" * len(header) + "|")
    for r in rows:
        print("| " + " | ".join(r) + " |")


def theta0_and_t_end(doc: str) -> tuple[argparse.Namespace, float]:
    """The --theta0 and --t-end options of a validation table script (its first doc line as the description)."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--theta0", default="0.95pi")
    ap.add_argument("--t-end", type=float, default=1000.0)
    args = ap.parse_args()
    return args, parse_angle(args.theta0)


def main() -> None:
    args, theta0 = theta0_and_t_end(__doc__)
    sym = Body.paper(0.0)
    table = load_or_build_table(sym, theta0)
    consts = pendulum_constants(sym, theta0)
    print(f"θ0 = {theta0:.6g}, t_end = {args.t_end:g}; κ = {consts.kappa:.6g}, ε_pd = 4/κ = "
          f"{consts.eps_period_doubling:.6g}, λ = {consts.lam:.6g}, T0 = {consts.T0:.10g}, "
          f"C0 = ({consts.C0[0]:.8g}, {consts.C0[1]:.8g})\n")
    samples = ("Q", "Theta", "t", "phi")
    map_rows, cf_rows, slopes_map, slopes_cf = [], [], [], []
    for name, psi0 in PSI0.items():
        runs = [compare_with_ode(Body.paper(eps), theta0, psi0, args.t_end, table=table, constants=consts)
                for eps in EPS_MAP]
        for eps, c in zip(EPS_MAP, runs):
            map_rows.append([name, f"{eps:g}", f"{c.map.K:.3g}"] + [fmt(c.map_errors[q]) for q in QUANT]
                            + [f"{c.sample_errors[q]:.2e}" for q in samples])
        slopes_map.append([name] + [f"{loglog_slope(EPS_MAP, [r.map_errors[q] for r in runs]):.2f}" for q in QUANT]
                          + [f"{loglog_slope(EPS_MAP, [r.sample_errors[q] for r in runs]):.2f}" for q in samples])
        runs = [compare_with_ode(Body.paper(eps), theta0, psi0, args.t_end if eps >= 1e-4 else 3.0 * args.t_end,
                                 table=table, constants=consts) for eps in EPS_CF]
        for eps, c in zip(EPS_CF, runs):
            cf_rows.append([name, f"{eps:g}", f"{c.pendulum.K:.3g}"] + [fmt(c.pendulum_errors[q]) for q in QUANT])
        slopes_cf.append([name] + [f"{loglog_slope(EPS_CF, [r.pendulum_errors[q] for r in runs]):.2f}"
                                   for q in QUANT])
    cols = ["slow period", "Q_R extent", "Φ", "line slope"]
    print_table("Averaged map: relative errors against the direct ODE",
                ["ψ0", "ε", "K"] + cols + ["max ΔQ/extent", "max ΔΘ", "max Δt", "max Δφ"], map_rows)
    print_table("Averaged map: log-log slopes of |error| over ε ∈ {1e-2, 1e-3, 1e-4}",
                ["ψ0"] + cols + [f"sample {q}" for q in samples], slopes_map)
    print_table("Closed form (pendulum): relative errors against the direct ODE", ["ψ0", "ε", "K"] + cols, cf_rows)
    print_table("Closed form: log-log slopes over ε ∈ {1e-3, 1e-4, 1e-5}", ["ψ0"] + cols, slopes_cf)


if __name__ == "__main__":
    main()
