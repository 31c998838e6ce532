"""Small-amplitude rocking about a principal axis (paper eqs. purerock, smallamprock; §4.1)."""

from __future__ import annotations

import math

from rocknroller.analysis.body import Body

__all__ = ["small_amplitude_frequency", "small_amplitude_frequency_as_printed"]


def small_amplitude_frequency(body: Body, moment: float) -> float:
    """ν = √(g a/(I + (1 − a)²)): the exact linearisation of paper eq. (purerock) at θ = 0 (f → 1 − a, s → 0).

    ``moment`` is I1 for rocking about i (ψ = 0) or I2 for rocking about j (ψ = π/2).
    """
    return math.sqrt(body.g * body.a / (moment + (1.0 - body.a) ** 2))


def small_amplitude_frequency_as_printed(body: Body, moment: float) -> float:
    """The paper's ν = √(g a/(I + 1)) (eq. smallamprock), which assumes a ≪ 1; kept to show the erratum."""
    return math.sqrt(body.g * body.a / (moment + 1.0))
