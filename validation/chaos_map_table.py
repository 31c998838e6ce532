"""Regenerates docs/slow_howto.md, "Order and chaos": the slow map's verdict, MEGNO and Lyapunov exponent over their
span, and its predictability horizon with its method, at the releases of issue 23's table.

Run:  python validation/chaos_map_table.py      (~3 s once the tables of 0.95π are cached)

Paper body released from rest at θ0 = 0.95π, t_end = 3000 time units, the map of order 1 and 2
(``predict_slow_motion``; the indicators from the tangent vector carried through the compiled map over their span,
max(t_end, 1000 rocks), the horizon from ``SlowPrediction.horizon_estimate()``).  The last column is the direct ODE's kind from issue 23's table (two direct runs with
ψ0 1e-10 apart, their distance in (Q_R, Q_J) after ~200 rocks).  Prints a Markdown table; the horizon as
``rocknroller slow`` prints it (:func:`horizon_cell`): to two significant digits, "≥" before one extrapolated past the
direct probe (a lower bound), "infinite" where no growth is resolved (``unresolved``) or it lies past the longest run
(``beyond``).
"""

from __future__ import annotations

import math
import warnings

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow import prediction as av
from rocknroller.cli.slow_chaos import EXTRAPOLATED, two_digits

THETA0, T_END = 0.95 * math.pi, 3000.0
#: (ε, ψ0 as text, ψ0, the direct ODE's kind in issue 23's table)
RELEASES = ((1e-2, "0.1", 0.1, "chaotic"), (1e-2, "0.3", 0.3, "chaotic"), (1e-2, "π/8", math.pi / 8, "regular"),
            (1e-2, "0.5", 0.5, "regular"), (1e-2, "π/4", math.pi / 4, "regular"), (1e-2, "1.2", 1.2, "regular"),
            (3e-3, "0.001", 0.001, "chaotic"), (3e-3, "0.05", 0.05, "weakly chaotic (layer)"),
            (1e-3, "0.001", 0.001, "weakly chaotic (layer)"), (1e-3, "0.01", 0.01, "regular"),
            (1e-3, "0.05", 0.05, "regular"), (1e-3, "π/4", math.pi / 4, "not in the table"))


HEADER = "| ε | ψ0 | order | map | MEGNO | λ per unit time | λ per rock | span | horizon | method | direct ODE |"
RULE = "|---|---|---|---|---|---|---|---|---|---|---|"


def horizon_cell(t: float, method: str) -> str:
    """The horizon as ``rocknroller slow`` prints it: two significant digits (what the probe resolves), "≥" before an
    extrapolated one (a lower bound), "infinite" for none."""
    if not math.isfinite(t):
        return "infinite"
    return f"{'≥ ' if method in EXTRAPOLATED else ''}{two_digits(t)}"


def main() -> None:
    warnings.simplefilter("ignore", av.AveragingValidityWarning)  # K = 4.26 > 4 at ε = 1e-2: the releases
    print(HEADER)
    print(RULE)
    for eps, text, psi0, ode in RELEASES:
        for order in (1, 2):
            p = av.predict_slow_motion(Body.paper(eps), THETA0, psi0, T_END, order=order)
            c = p.chaos
            h = p.horizon_estimate()
            print(f"| {eps:g} | {text} | {order} | {c.verdict} | {c.megno:.3g} | {c.lyapunov:.3g} | "
                  f"{c.lyapunov_per_rock:.3g} | {c.span:.4g} | {horizon_cell(h.t, h.method)} | {h.method} | {ode} |")


if __name__ == "__main__":
    main()
