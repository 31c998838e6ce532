"""Small-amplitude rocking about a principal axis (paper eqs. purerock, smallamprock; §4.1).

The exact linear frequency √(g a/(I + (1 − a)²)), the paper's printed approximation √(g a/(I + 1)), and the
frequency measured on the direct ODE that decides between them.
"""

from __future__ import annotations

import math

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState

__all__ = ["small_amplitude_frequency", "small_amplitude_frequency_as_printed", "measured_frequency"]


def small_amplitude_frequency(body: Body, moment: float) -> float:
    """ν = √(g a/(I + (1 − a)²)): the exact linearisation of paper eq. (purerock) at θ = 0 (f → 1 − a, s → 0).

    ``moment`` is I1 for rocking about i (ψ = 0) or I2 for rocking about j (ψ = π/2).
    """
    return math.sqrt(body.g * body.a / (moment + (1.0 - body.a) ** 2))


def small_amplitude_frequency_as_printed(body: Body, moment: float) -> float:
    """The paper's ν = √(g a/(I + 1)) (eq. smallamprock), which assumes a ≪ 1; kept to show the erratum."""
    return math.sqrt(body.g * body.a / (moment + 1.0))


def measured_frequency(body: Body, psi0: float, amplitude: float = 1e-3) -> float:
    """2π / period of rocking started at rest with the given amplitude and spin phase ψ0, measured on the direct
    ODE (80 time units); the rocking passes θ = 0, so a period spans two θ-maxima."""
    from rocknroller.numerics.integrate import simulate

    traj = simulate(body, EulerState(amplitude, 0.0, psi0), 80.0)
    spacing = traj.maxima_spacing
    if spacing is None:
        raise ValueError(f"no rocking period measured: fewer than two theta-maxima in 80 time units "
                         f"(amplitude={amplitude!r}, psi0={psi0!r})")
    return 2.0 * math.pi / (2.0 * spacing)
