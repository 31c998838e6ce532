"""Euler-angle kinematics shared by the analysis and the direct ODE.

Conventions (paper §2 and §4): θ is the tilt of the body axis k from the upward
vertical, φ the azimuth, ψ the spin; s = sin θ, c = cos θ, σ = sin ψ, χ = cos ψ.
The rotation matrix Υ (paper eq. before (Gam)) has as rows the space axes X, Y, Z
in body components; its last row is the upward vertical γ = (sσ, sχ, c).
All functions are vectorised over numpy arrays (broadcasting on the angles).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "vertical_in_body",
    "space_axes_in_body",
    "omega_from_rates",
    "rates_from_omega",
    "primed_from_body",
    "angles_from_frame",
]


def vertical_in_body(theta: ArrayLike, psi: ArrayLike) -> NDArray[np.float64]:
    """Upward vertical γ = (sσ, sχ, c) in body components, shape (3, ...)."""
    theta, psi = np.asarray(theta, float), np.asarray(psi, float)
    s = np.sin(theta)
    return np.array([s * np.sin(psi), s * np.cos(psi), np.cos(theta)])


def space_axes_in_body(theta: ArrayLike, phi: ArrayLike, psi: ArrayLike) -> NDArray[np.float64]:
    """Rows of Υ: the space axes X, Y, Z in body components, shape (3, 3, ...).

    Paper §4.2 (the matrix Υ with v = Υᵀ V).
    """
    theta, phi, psi = (np.asarray(x, float) for x in (theta, phi, psi))
    s, c = np.sin(theta), np.cos(theta)
    sp, cp = np.sin(phi), np.cos(phi)
    sg, ch = np.sin(psi), np.cos(psi)
    ex = np.array([cp * ch - c * sp * sg, -cp * sg - c * sp * ch, s * sp])
    ey = np.array([sp * ch + c * cp * sg, -sp * sg + c * cp * ch, -s * cp])
    ez = np.array([s * sg, s * ch, c * np.ones_like(phi)])
    return np.array([ex, ey, ez])


def omega_from_rates(theta: ArrayLike, psi: ArrayLike, theta_dot: ArrayLike, phi_dot: ArrayLike,
                     psi_dot: ArrayLike) -> NDArray[np.float64]:
    """Body-frame angular velocity ω = Σ(θ, ψ) θ̇ (paper eq. thetaomega), shape (3, ...)."""
    theta, psi = np.asarray(theta, float), np.asarray(psi, float)
    s, c = np.sin(theta), np.cos(theta)
    sg, ch = np.sin(psi), np.cos(psi)
    return np.array([
        ch * theta_dot + s * sg * phi_dot,
        -sg * theta_dot + s * ch * phi_dot,
        c * phi_dot + psi_dot,
    ])


def rates_from_omega(theta: ArrayLike, psi: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """Euler rates (θ̇, φ̇, ψ̇) = Σ⁻¹ ω; singular at sin θ = 0 (paper eq. anglesdot)."""
    theta, psi = np.asarray(theta, float), np.asarray(psi, float)
    w1, w2, w3 = np.asarray(omega, float)
    s, c = np.sin(theta), np.cos(theta)
    sg, ch = np.sin(psi), np.cos(psi)
    phi_dot = (sg * w1 + ch * w2) / s
    return np.array([ch * w1 - sg * w2, phi_dot, w3 - c * phi_dot])


def primed_from_body(psi: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """Intermediate-frame components (ω1', ω2', ω3') = (θ̇, s φ̇, c φ̇ + ψ̇) from body ω (paper eq. angledot)."""
    psi = np.asarray(psi, float)
    w1, w2, w3 = np.asarray(omega, float)
    sg, ch = np.sin(psi), np.cos(psi)
    return np.array([ch * w1 - sg * w2, sg * w1 + ch * w2, w3 * np.ones_like(psi)])


def angles_from_frame(gamma: ArrayLike, ex: ArrayLike) -> NDArray[np.float64]:
    """Euler angles (θ, φ, ψ) in (−π, π] from γ and the space X axis, both in body components.

    θ = atan2(|γ₁₂|, γ₃); ψ = atan2(γ₁, γ₂); φ = atan2(X·k, −Y·k) with Y = γ × X.
    φ and ψ are undefined at θ = 0 exactly (only φ + ψ is); elsewhere this is exact.
    """
    g1, g2, g3 = np.asarray(gamma, float)
    x1, x2, x3 = np.asarray(ex, float)
    ey3 = g1 * x2 - g2 * x1
    return np.array([np.arctan2(np.hypot(g1, g2), g3), np.arctan2(x3, -ey3), np.arctan2(g1, g2)])
