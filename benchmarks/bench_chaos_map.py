"""Cost of the slow map's chaos indicators against the map alone (side by side, one process; ratios only).

Run:  python benchmarks/bench_chaos_map.py

Paper body, θ0 = 0.95π, 2·10⁴ time units (~1600 maxima; the chaotic orbit leaves the order-2 table not long after),
at a regular release (ε = 1e-2, ψ0 = π/4), a chaotic one (ψ0 = 0.1) and at ε = 1e-3 (ψ0 = π/4), first and second
order.  Reports, from the least CPU time of 15 interleaved rounds, the map's loop with the tangent vector
(``iterate_slow_map(..., tangent=True)``: the tangent map of every step in the compiled kernel) and with the
indicators computed from it (:func:`rocknroller.numerics.megno.chaos_indicators`), as ratios to the loop alone
(issue 23's target: at most 2×); and the default prediction (``predict_slow_motion``: order 2, 1000 time units, ~75
maxima), which now carries the indicators, against the same prediction with ``indicators=False`` (the cost before
them).  Measured (2 shared cores): tangent 1.42-1.65×, with the indicators 1.47-1.71×, the default prediction 1.42×.
"""

from __future__ import annotations

import math
import time
import warnings

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.map.second_order import load_or_build_second_order_table
from rocknroller.numerics.megno import chaos_indicators

THETA0, T_END = 0.95 * math.pi, 2e4
CASES = (("eps=1e-2 psi0=pi/4 (regular)", 1e-2, math.pi / 4), ("eps=1e-2 psi0=0.1 (chaotic)", 1e-2, 0.1),
         ("eps=1e-3 psi0=pi/4", 1e-3, math.pi / 4))


def best_of(fns, n=15):
    """The least CPU time of each of ``fns`` over ``n`` interleaved rounds (CPU time, interleaved: the machine's other
    load shifts neither the ratios nor one function against another)."""
    best = [math.inf] * len(fns)
    for _ in range(n):
        for i, fn in enumerate(fns):
            t0 = time.process_time()
            fn()
            best[i] = min(best[i], time.process_time() - t0)
    return best


def main() -> None:
    warnings.simplefilter("ignore")  # K > 4 at eps = 1e-2 warns: the timing is still meaningful
    body = Body.paper()
    table = av.load_or_build_table(body, THETA0)
    second = load_or_build_second_order_table(body, THETA0)
    print(f"{'case':32s} {'order':>5s} {'maxima':>7s} {'+tangent':>9s} {'+indicators':>12s}")
    for name, eps, psi0 in CASES:
        for order, sec in ((1, None), (2, second)):
            def plain():
                return av.iterate_slow_map(table, eps, psi0, T_END, second=sec)

            def tangent():
                return av.iterate_slow_map(table, eps, psi0, T_END, second=sec, tangent=True)

            def indicators():
                s = tangent()
                return chaos_indicators(s.t, s.log_growth)

            n = plain().t.size
            tangent()  # the tangent rows (built once per table)
            t0, t1, t2 = best_of([plain, tangent, indicators])
            print(f"{name:32s} {order:5d} {n:7d} {t1 / t0:8.2f}x {t2 / t0:11.2f}x")
    body = Body.paper(1e-3)
    av.predict_slow_motion(body, THETA0, math.pi / 4)
    t_pred, t_plain = best_of([lambda: av.predict_slow_motion(body, THETA0, math.pi / 4),
                               lambda: av.predict_slow_motion(body, THETA0, math.pi / 4, indicators=False)], n=100)
    print(f"predict_slow_motion (default: order 2, 1000 t.u.) with the indicators / without: {t_pred / t_plain:.2f}x")


if __name__ == "__main__":
    main()
