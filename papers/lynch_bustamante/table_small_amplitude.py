"""Paper §2.2 and §4.1: small-amplitude rocking frequencies about the two principal axes, and their ratio.

The exact linearisation of paper eq. (purerock) at θ = 0 is θ̈ + g a/(I_k + (1 − a)²) θ = 0; the paper's
eq. (smallamprock) uses g a/(I_k + 1).  The periods are measured on the direct ODE (amplitude 1e-3).
"""

from __future__ import annotations

import math
from pathlib import Path

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.routh.rocking import (measured_frequency, small_amplitude_frequency,
                                               small_amplitude_frequency_as_printed)
from rocknroller.papers.output import Reproduction, write_csv

NAME = "table_small_amplitude"
AMPLITUDE = 1e-3
EPSILON = 1e-3


def run(out: Path) -> Reproduction:
    """Paper §2.2 and §4.1: writes ``table_small_amplitude.csv`` (about the axes i and j, ε = 1e-3: ν from the
    direct ODE at amplitude 1e-3, the exact linearisation √(ga/(I_k + (1 − a)²)) and the paper's √(ga/(I_k + 1)));
    numbers: ν1 by each, the paper's relative error, and ν1/ν2 by each."""
    body = Body.paper(EPSILON)
    rows = []
    for axis, moment, psi0 in (("i (I1)", body.I1, 0.0), ("j (I2)", body.I2, math.pi / 2)):
        rows.append((axis, measured_frequency(body, psi0, AMPLITUDE), small_amplitude_frequency(body, moment),
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
