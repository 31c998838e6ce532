"""Energy, Jellett's and Routh's quantities, the angular momentum about the contact point and Borisov and Mamaev's
quantity M² − 2K r², and the angular rates of Routh's sphere.

Paper eqs. (energy), (jellett), (routh), (measure), (phidotCJQR), (psidotCJQR); the paper's conclusion for
M² − 2K r² (docs/theory/further_integral.md).
For the asymmetric body the paper's definitions (eq. JelletandRouth_Qtys) are
kept: Q_J = I1 s ω2' + I3 f ω3' and Q_R = ω3'/ρ.  In body components
s ω2' = γ1 ω1 + γ2 ω2 and ω3' = ω3, so every function here is smooth at θ = 0.
All functions are vectorised: body-frame vectors have shape (3, ...).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body

__all__ = ["rho", "rho_inv", "rho_inv_sq", "energy", "jellett", "routh", "invariants", "contact_momentum",
           "borisov_mamaev", "V_phi", "V_psi"]


def rho_inv_sq(body: Any, s2: Any, f: Any) -> Any:
    """ρ⁻² = I3 + s² + (I3/I1) f² from s² = sin²θ and f = cos θ − a (paper eq. measure).

    Generic arithmetic: numpy arrays, mpmath numbers or sympy expressions; ``body`` needs only the
    attributes I1 and I3 (a Body, or the same numbers in another arithmetic).
    """
    return body.I3 + s2 + (body.I3 / body.I1) * f * f


def rho_inv(body: Body, s2: ArrayLike, f: ArrayLike) -> NDArray[np.float64]:
    """1/ρ = [I3 + s² + (I3/I1) f²]^(1/2) from s² = sin²θ and f = cos θ − a (paper eq. measure)."""
    return np.sqrt(rho_inv_sq(body, np.asarray(s2, float), np.asarray(f, float)))


def rho(theta: ArrayLike, body: Body) -> NDArray[np.float64]:
    """Measure ρ(θ) = [I3 + s² + (I3/I1) f²]^(−1/2), f = cos θ − a (paper eq. measure)."""
    theta = np.asarray(theta, float)
    return 1.0 / rho_inv(body, np.sin(theta) ** 2, np.cos(theta) - body.a)


def energy(body: Body, gamma: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """Total energy E = T + V, V = g a (1 − c), with v = ω × r and r = γ − a e3 (paper eq. energy)."""
    g1, g2, g3 = np.asarray(gamma, float)
    w1, w2, w3 = np.asarray(omega, float)
    r3 = g3 - body.a
    v1, v2, v3 = w2 * r3 - w3 * g2, w3 * g1 - w1 * r3, w1 * g2 - w2 * g1
    T = 0.5 * (v1 * v1 + v2 * v2 + v3 * v3) + 0.5 * (body.I1 * w1 * w1 + body.I2 * w2 * w2 + body.I3 * w3 * w3)
    return T + body.g * body.a * (1.0 - g3)


def jellett(body: Body, gamma: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """Jellett's quantity Q_J = I1 s ω2' + I3 f ω3' (paper eqs. jellett, JelletandRouth_Qtys)."""
    g1, g2, g3 = np.asarray(gamma, float)
    w1, w2, w3 = np.asarray(omega, float)
    return body.I1 * (g1 * w1 + g2 * w2) + body.I3 * (g3 - body.a) * w3


def routh(body: Body, gamma: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """Routh's quantity Q_R = ω3'/ρ (paper eqs. routh, measure)."""
    g1, g2, g3 = np.asarray(gamma, float)
    w3 = np.asarray(omega, float)[2]
    return w3 * rho_inv(body, g1 * g1 + g2 * g2, g3 - body.a)


def contact_momentum(body: Body, gamma: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """Angular momentum about the contact point, M = I ω + r × (ω × r) = K(γ) ω, r = γ − a e3, in body components.

    K(γ) = diag(I) + (r·r) 1 − r rᵀ is the mass matrix of the direct equations
    (:func:`rocknroller.analysis.model.equations.body_frame_rhs`); shape (3, ...) like ``omega``.
    """
    g1, g2, g3 = np.asarray(gamma, float)
    w = np.asarray(omega, float)
    r = np.array([g1, g2, g3 - body.a])
    rr, rw = np.sum(r * r, axis=0), np.sum(r * w, axis=0)
    inertia = np.array([body.I1, body.I2, body.I3]).reshape((3,) + (1,) * (w.ndim - 1))
    return inertia * w + rr * w - rw * r


def borisov_mamaev(body: Body, gamma: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """Borisov and Mamaev's quantity B = M² − 2K r², with K = E the energy (paper, Conclusions).

    M is :func:`contact_momentum`, r = γ − a e3.  Along the motion (unit mass, ``body_frame_rhs``)

        d(M²)/dt = 2T d(r²)/dt + 2 g a M·(e3 × γ),

    so without gravity (g = 0, T = E constant) B is a first integral for any moments I1, I2, I3, and with gravity it is
    not (tests/analysis/model/test_borisov_mamaev.py proves the identity with sympy and checks both cases against
    the direct ODE; docs/theory/further_integral.md).  The paper does not define K; for m = 1 the identity fixes it as the
    kinetic energy, which equals E at g = 0.
    """
    g1, g2, g3 = np.asarray(gamma, float)
    M = contact_momentum(body, gamma, omega)
    r2 = g1 * g1 + g2 * g2 + (g3 - body.a) ** 2
    return np.sum(M * M, axis=0) - 2.0 * energy(body, gamma, omega) * r2


def invariants(body: Body, gamma: ArrayLike, omega: ArrayLike) -> tuple[NDArray, NDArray, NDArray]:
    """(E, Q_R, Q_J) of body-frame states."""
    return energy(body, gamma, omega), routh(body, gamma, omega), jellett(body, gamma, omega)


def V_phi(theta: ArrayLike, *, QR: ArrayLike, QJ: ArrayLike, body: Body) -> NDArray[np.float64]:
    """φ̇ = V_φ(θ; Q_R, Q_J) = [Q_J − ρ f I3 Q_R]/(I1 s²) (paper eq. phidotCJQR; the paper writes V_φ(θ; Q_J, Q_R)).

    Q_R, Q_J and the body are keyword-only: the package orders Q_R before Q_J everywhere, and a swap here would
    give wrong numbers silently.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> E, QR, QJ = rr.invariants_from_euler(body, 0.95 * math.pi, 0.0, 0.15, 0.15)
    >>> print(f"{rr.V_phi(0.95 * math.pi, QR=QR, QJ=QJ, body=body):.12f}")
    0.150000000000
    """
    theta = np.asarray(theta, float)
    s, c = np.sin(theta), np.cos(theta)
    return (QJ - rho(theta, body) * (c - body.a) * body.I3 * QR) / (body.I1 * s * s)


def V_psi(theta: ArrayLike, *, QR: ArrayLike, QJ: ArrayLike, body: Body) -> NDArray[np.float64]:
    """ψ̇ = V_ψ(θ; Q_R, Q_J) = −[c Q_J − ρ(c f I3 + I1 s²) Q_R]/(I1 s²) (paper eq. psidotCJQR); keyword-only
    like :func:`V_phi`.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> E, QR, QJ = rr.invariants_from_euler(body, 0.95 * math.pi, 0.0, 0.15, 0.15)
    >>> print(f"{rr.V_psi(0.95 * math.pi, QR=QR, QJ=QJ, body=body):.12f}")
    0.150000000000
    """
    theta = np.asarray(theta, float)
    s, c = np.sin(theta), np.cos(theta)
    return -(c * QJ - rho(theta, body) * (c * (c - body.a) * body.I3 + body.I1 * s * s) * QR) / (body.I1 * s * s)
