"""Regenerates docs/slow_validation.md, "Random starts": the map on region tables vs the ODE over a stated domain.

Run:  python validation/random_starts.py [N] [SEED]     (default 40 starts, seed 12)
Domain: θ0 uniform in [0.3π, 0.97π], ψ0 uniform in [0, π), θ̇0 = 0, body-frame ω = (ω1, 0, ω3) with ω1, ω3 uniform
in [−0.4, 0.4] (the size of the paper's reversal rates: |ψ̇0| ≤ 0.378; ω2 = 0 makes the energy, and so the table,
independent of ε), and E < 2 g a (draws at or above the energy of the upright position pass through θ = π on
Q_J,π^crit, where the region tables stop: ``slow.region.check_below_top``; they are redrawn, and counted).  For each start: its table (chart by ``slow.region.region_axis``), then at ε = 1e-2, 1e-3, 1e-4
the largest maximum-by-maximum errors map − ODE over 1000 time units in Q (over the Q_R extent), Θ = 2ψ, t and
φ mod π, and their log-log slopes.  A start the map refuses (its orbit leaves the tables, or K = ε κ > 4 warns) is
listed with the reason.  Prints one row per start and the medians and minima of the slopes.
"""

from __future__ import annotations

import math
import sys
import warnings

import numpy as np

from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.map import region as sr
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map.family import first_maximum
from rocknroller.analysis.model.equations import EulerState
from rocknroller.papers.averaging_check import loglog_slope, ode_slow_summary, sample_errors

EPS = (1e-2, 1e-3, 1e-4)
THETA0 = (0.3 * math.pi, 0.97 * math.pi)
OMEGA = 0.4
T_END = 1000.0


def draw(n: int, seed: int) -> tuple[list[tuple[EulerState, float, float]], int]:
    """n starts of the domain, with their ω1 and ω3, and the number of draws above the upright energy redrawn."""
    from rocknroller.analysis.model.invariants import energy

    rng = np.random.default_rng(seed)
    body, out, above = Body.paper(0.0), [], 0
    while len(out) < n:
        th, psi = rng.uniform(*THETA0), rng.uniform(0.0, math.pi)
        w1, w3 = rng.uniform(-OMEGA, OMEGA, 2)
        start = EulerState.from_omega(th, 0.0, psi, (w1, 0.0, w3))
        y = start.to_body_state()
        if float(energy(body, y[0:3], y[3:6])) >= 2.0 * body.g * body.a:
            above += 1
            continue
        out.append((start, float(w1), float(w3)))
    return out, above


def main(n: int = 40, seed: int = 12) -> None:
    print("| # | θ0/π | ψ0 | ω1 | ω3 | E | chart | slope Q | slope Θ | slope t | slope φ | errors at ε = 1e-2 "
          "(Q, Θ, t, φ) | note |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    slopes: dict[str, list[float]] = {k: [] for k in ("Q", "Theta", "t", "phi")}
    refused = 0
    starts, above = draw(n, seed)
    for k, (start, w1, w3) in enumerate(starts):
        body0 = Body.paper(EPS[0])
        E = first_maximum(body0, start).E
        axis = sr.region_axis(body0, E)
        head = f"| {k} | {start.theta / math.pi:.3f} | {start.psi:.3f} | {w1:.3f} | {w3:.3f} | {E:.4f} | {axis} |"
        try:
            table = sr.load_or_build_region_table(body0, E, workers=2)
            errs: dict[str, list[float]] = {q: [] for q in slopes}
            notes = set()
            for eps in EPS:
                body = Body.paper(eps)
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always", av.AveragingValidityWarning)
                    pred = av.predict_slow_motion(body, start, t_end=T_END, table=table)
                notes |= {str(w.message)[:60] for w in caught}
                ode = ode_slow_summary(body, start, None, T_END)
                for q, e in sample_errors(pred.series, ode).items():
                    errs[q].append(e)
        except av.AveragingRangeError as exc:
            refused += 1
            print(head + " – | – | – | – | – | refused: " + str(exc)[:140] + " |", flush=True)
            continue
        s = {q: loglog_slope(EPS, e) for q, e in errs.items()}
        for q in slopes:
            slopes[q].append(s[q])
        first = ", ".join(f"{errs[q][0]:.1e}" for q in slopes)
        print(head + " | ".join(f" {s[q]:.2f}" for q in slopes) + f" | {first} | {'; '.join(sorted(notes))} |",
              flush=True)
    print()
    print(f"{n - refused} of {n} starts predicted ({refused} refused; {above} draws at or above the upright energy "
          f"redrawn); slopes over ε = 1e-2, 1e-3, 1e-4:")
    for q, v in slopes.items():
        if v:
            print(f"  {q}: median {np.median(v):.2f}, min {np.min(v):.2f}, below 0.9: {int(np.sum(np.array(v) < 0.9))}")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
