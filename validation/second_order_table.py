"""Regenerates docs/slow_validation.md, "Releases from rest, second order": order 2 against order 1 and the ODE.

Run:  python validation/second_order_table.py  [--theta0 0.95pi] [--t-end 1000]

Paper body released from rest at θ0, ψ0 ∈ {π/8, π/4, 3π/8, 3.9π/8}, ε ∈ {1e-2, 3e-3, 1e-3, 3e-4} (the issue
"Second-order ε map").  Prints Markdown: per ψ0 and order, the largest maximum-by-maximum differences map − ODE in
Q (over the Q_R extent), Θ, t and φ mod π at each ε and their log-log slopes over ε; the relative errors of the slow
period, the Q_R extent and Φ at ε = 1e-2; and the cost of one prediction of each order from cached tables (the
second-order tables are built once, ~60 s on 2 cores).
"""

from __future__ import annotations

import time

from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map.second_order import load_or_build_second_order_table
from rocknroller.papers.averaging_check import loglog_slope, ode_slow_summary, relative_errors, sample_errors

from averaging_table import PSI0, theta0_and_t_end  # the script beside this one (run from validation/ or by path)

EPS = (1e-2, 3e-3, 1e-3, 3e-4)
SAMPLES = ("Q", "Theta", "t", "phi")
QUANT = ("slow_period", "QR_extent", "Phi")


def main() -> None:
    args, theta0 = theta0_and_t_end(__doc__)
    table = av.load_or_build_table(Body.paper(0.0), theta0)
    second = load_or_build_second_order_table(Body.paper(0.0), theta0, workers=2)
    print(f"\n### Maximum-by-maximum map − ODE, θ0 = {args.theta0}, {args.t_end:g} time units\n")
    print("| ψ0 | order | " + " | ".join(SAMPLES) + " | slopes Q, Θ, t, φ |")
    print("|---" * (3 + len(SAMPLES)) + "|")
    at_1e2, cost = {}, {1: [], 2: []}
    for label, psi0 in PSI0.items():
        errs: dict[int, dict[str, list[float]]] = {1: {s: [] for s in SAMPLES}, 2: {s: [] for s in SAMPLES}}
        for eps in EPS:
            body = Body.paper(eps)
            ref = ode_slow_summary(body, theta0, psi0, args.t_end)
            for order in (1, 2):
                t0 = time.perf_counter()
                pred = av.predict_slow_motion(body, theta0, psi0, args.t_end, order=order, table=table, second=second)
                cost[order].append(time.perf_counter() - t0)
                for s, v in sample_errors(pred.series, ref).items():
                    errs[order][s].append(v)
                if eps == EPS[0]:
                    at_1e2[(label, order)] = relative_errors(pred, ref)
        for order in (1, 2):
            row = [" / ".join(f"{v:.1e}" for v in errs[order][s]) for s in SAMPLES]
            slopes = ", ".join(f"{loglog_slope(EPS, errs[order][s]):.2f}" for s in SAMPLES)
            print(f"| {label} | {order} | " + " | ".join(row) + f" | {slopes} |")
    print("\n(each cell: ε = " + " / ".join(f"{e:g}" for e in EPS) + ")")
    print(f"\n### Relative errors at ε = {EPS[0]:g} (map/ODE − 1)\n")
    print("| ψ0 | order | " + " | ".join(QUANT) + " |")
    print("|---" * (2 + len(QUANT)) + "|")
    for (label, order), rel in at_1e2.items():
        print(f"| {label} | {order} | " + " | ".join(f"{rel[q]:+.1e}" for q in QUANT) + " |")
    for order in (1, 2):
        c = sorted(cost[order])
        print(f"\ncost of one prediction, order {order}: median {1e3 * c[len(c) // 2]:.2f} ms (tables given)")


if __name__ == "__main__":
    main()
