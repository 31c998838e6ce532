"""Paper §2.2 and §4.1: small-amplitude rocking frequencies about the two principal axes, and their ratio.

The exact linearisation of paper eq. (purerock) at θ = 0 is θ̈ + g a/(I_k + (1 − a)²) θ = 0; the paper's
eq. (smallamprock) uses g a/(I_k + 1).  The periods are measured on the direct ODE (amplitude 1e-3).
"""

from __future__ import annotations

import math
from pathlib import Path


from rocknroller.analysis.body import Body
from rocknroller.analysis.rocking import small_amplitude_frequency, small_amplitude_frequency_as_printed
from rocknroller.numerics.equations import EulerState
from rocknroller.numerics.integrate import simulate
from rocknroller.papers.output import Reproduction, write_csv

NAME = "table_small_amplitude"
AMPLITUDE = 1e-3
EPSILON = 1e-3


def measured_frequency(body: Body, psi0: float) -> float:
    """2π / period of rocking started at rest with amplitude 1e-3 and spin phase ψ0 (direct ODE); the
    rocking passes θ = 0, so a period spans two θ-maxima."""
    traj = simulate(body, EulerState(AMPLITUDE, 0.0, psi0), 80.0)
    return 2.0 * math.pi / (2.0 * traj.maxima_spacing)


def run(out: Path) -> Reproduction:
    body = Body.paper(EPSILON)
    rows = []
    for axis, moment, psi0 in (("i (I1)", body.I1, 0.0), ("j (I2)", body.I2, math.pi / 2)):
        rows.append((axis, measured_frequency(body, psi0), small_amplitude_frequency(body, moment),
                     small_amplitude_frequency_as_printed(body, moment)))
    path = write_csv(out / "table_small_amplitude.csv", {
        "axis": [r[0] for r in rows], "nu_ODE": [r[1] for r in rows], "nu_exact_linear": [r[2] for r in rows],
        "nu_paper": [r[3] for r in rows]},
        [f"small-amplitude rocking (amplitude {AMPLITUDE:g}) about each principal axis", f"body: {body.describe()}"])
    numbers = {
        "nu1_ODE": rows[0][1], "nu1_exact": rows[0][2], "nu1_paper": rows[0][3],
        "paper_rel_error": rows[0][3] / rows[0][1] - 1.0,
        "nu1/nu2_ODE": rows[0][1] / rows[1][1], "nu1/nu2_exact": rows[0][2] / rows[1][2],
        "nu1/nu2_paper": rows[0][3] / rows[1][3],
    }
    caption = (f"Small-amplitude rocking: ν1 = {rows[0][1]:.6f} (ODE) = √(ga/(I1+(1−a)²)) = {rows[0][2]:.6f}; the "
               f"paper's √(ga/(I1+1)) = {rows[0][3]:.6f} is {100 * abs(numbers['paper_rel_error']):.1f} % off. "
               f"Ratio ν1/ν2 = {numbers['nu1/nu2_ODE']:.8f} (ODE), {numbers['nu1/nu2_exact']:.8f} (exact), "
               f"{numbers['nu1/nu2_paper']:.8f} (paper).")
    return Reproduction(NAME, caption, [path], numbers)
