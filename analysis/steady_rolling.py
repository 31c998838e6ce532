"""Steady circular rolling of Routh's sphere (paper §2.2, eq. om2om3)."""

from __future__ import annotations

import math

from rocknroller.analysis.body import Body
from rocknroller.analysis.reduction import require_open_tilt

__all__ = ["steady_rolling_omega3"]


def steady_rolling_omega3(body: Body, theta0: float, omega2: float) -> float:
    """ω3' for steady rolling at constant tilt θ0 with ω2' = s φ̇ (paper eq. om2om3, with m = 1).

    ω3' = [(I1 cot θ0 + h0 f0 csc θ0) ω2'² − g a sin θ0] / [(I3 + h0) ω2'],
    f0 = cos θ0 − a, h0 = 1 − a cos θ0.

    Raises
    ------
    ValueError
        For θ0 outside (0, π) or ω2' = 0 (no steady rolling without precession).
    """
    body.require_symmetric("steady rolling (paper eq. om2om3)")
    require_open_tilt(theta0)
    if omega2 == 0.0 or not math.isfinite(omega2):
        raise ValueError(f"omega2 = sin(theta0)*phi_dot must be finite and non-zero, got omega2={omega2!r}")
    s, c = math.sin(theta0), math.cos(theta0)
    f0, h0 = c - body.a, 1.0 - body.a * c
    return ((body.I1 * c / s + h0 * f0 / s) * omega2**2 - body.g * body.a * s) / ((body.I3 + h0) * omega2)
