"""Steady circular rolling of Routh's sphere (paper §2.2, eq. om2om3), and a start's distance to it.

Steady rolling is the double root of F (E = min_θ U): :func:`boundary_distance` measures how far (E, Q_R, Q_J) lie
from it, δ = (E − min U)/E, 1 for pure rocking (Q = 0) and 0 at steady rolling.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.routh.reduction import require_open_tilt
from rocknroller.analysis.routh.turning_points import min_potential

__all__ = ["steady_rolling_omega3", "boundary_distance"]


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


def boundary_distance(body: Body, E: ArrayLike, QR: ArrayLike, QJ: ArrayLike) -> NDArray[np.float64]:
    """δ = (E − min_θ U(θ; Q_R, Q_J))/E: 0 at steady rolling, 1 at Q = 0, < 0 where no motion is possible."""
    E = np.asarray(E, float)
    return (E - min_potential(QR, QJ, body.symmetric())) / E
