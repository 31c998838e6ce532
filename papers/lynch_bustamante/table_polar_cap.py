"""Paper App. A.1: parameters of the bowling-ball rock'n'roller (polar cap with d = cos Θ removed)."""

from __future__ import annotations

import math
from pathlib import Path

from rocknroller.analysis.model.body import Body, polar_cap_offset_as_printed
from rocknroller.papers.output import Reproduction, write_csv

NAME = "table_polar_cap"
D_VALUES = (-0.5, 0.0, 0.2, 0.4, 0.6, 0.8, 0.9, 0.95)  # d = 1, the homogeneous ball (I1 = I3), is no loaded sphere
PAPER_D = 0.6  # Θ ≈ 53°, paper App. A.1


def run(out: Path) -> Reproduction:
    """Paper App. A.1: writes ``table_polar_cap.csv`` (for each d of ``D_VALUES``: Θ in degrees, a, the
    paper's printed a, I1, I3); numbers: d, a, I1, I3 and the printed a at the paper's d = 0.6."""
    bodies = [Body.from_polar_cap(d) for d in D_VALUES]
    printed_a = [polar_cap_offset_as_printed(d) for d in D_VALUES]
    path = write_csv(out / "table_polar_cap.csv", {
        "d": D_VALUES, "Theta_deg": [math.degrees(math.acos(d)) for d in D_VALUES],
        "a": [b.a for b in bodies], "a_as_printed": printed_a, "I1": [b.I1 for b in bodies],
        "I3": [b.I3 for b in bodies]},
        ["paper App. A.1: homogeneous unit ball, polar cap above height d = cos(Theta) removed; unit mass",
         "a = (pi/4)(1-d^2)^2/V (corrected sign); a_as_printed = the paper's formula, negative"])
    b = Body.from_polar_cap(PAPER_D)
    numbers = {"d": PAPER_D, "a": b.a, "I1": b.I1, "I3": b.I3,
               "a_as_printed": polar_cap_offset_as_printed(PAPER_D)}
    caption = (f"Bowling ball, d = {PAPER_D} (Θ ≈ {math.degrees(math.acos(PAPER_D)):.1f}°): a = {b.a:.4f}, "
               f"I1 = {b.I1:.4f}, I3 = {b.I3:.4f} (paper: 0.085, 0.362, 0.42). The printed formula for a has "
               "the wrong sign.")
    return Reproduction(NAME, caption, [path], numbers)
