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

from rocknroller.analysis.model.body import Body, LoadedSphere

__all__ = ["rho", "rho_inv", "rho_inv_sq", "energy", "jellett", "routh", "invariants", "contact_momentum",
           "momentum_squared", "momentum_vertical", "momentum_along_offset_line", "routh_on_axis", "borisov_mamaev",
           "V_phi", "V_psi"]


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


def _contact_to_mass_centre(body: Body | LoadedSphere, gamma: Any) -> tuple[Any, Any, Any]:
    """r = γ + c, from the contact point to the mass centre in body components: (γ1, γ2, γ3 − a) for a
    :class:`Body` (its own arithmetic), (γ1 + c1, γ2 + c2, γ3 + c3) for a :class:`LoadedSphere`."""
    g1, g2, g3 = gamma
    if isinstance(body, LoadedSphere):
        c1, c2, c3 = body.offset
        return g1 + c1, g2 + c2, g3 + c3
    return g1, g2, g3 - body.a


def _require_on_axis(body: Body | LoadedSphere, what: str) -> Body:
    """``body`` itself, or a ValueError naming ``what`` unless it is a :class:`Body` (the mass centre on the third
    principal axis)."""
    if not isinstance(body, Body):
        raise ValueError(f"{what} is defined for a mass centre on the third principal axis below the geometric centre "
                         f"(rr.Body); this {body.kind} has c = {body.offset!r}. The family's integrals are in "
                         f"rocknroller.analysis.hierarchy (E, M·r, M·M, M·γ)")
    return body


def energy(body: Body | LoadedSphere, gamma: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """Total energy E = T + V, with v = ω × r and r = γ + c (paper eq. energy).

    V = g a (1 − c) for a :class:`Body` (c = (0, 0, −a)); V = g (|c| + c·γ) for a :class:`LoadedSphere`, the height
    of the mass centre above its lowest, 0 ≤ V ≤ 2 g |c| (the same V for an on-axis offset).

    Examples
    --------
    >>> import numpy as np
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.model.invariants import energy
    >>> gamma, omega = np.array([0.6, 0.0, -0.8]), np.array([0.1, 0.2, -0.3])
    >>> body = rr.Body.paper(1e-3)
    >>> print(f"{energy(body, gamma, omega):.12f} {energy(body.as_loaded_sphere(), gamma, omega):.12f}")
    0.941219500000 0.941219500000
    """
    gamma = np.asarray(gamma, float)
    g1, g2, g3 = gamma
    w1, w2, w3 = np.asarray(omega, float)
    r1, r2, r3 = _contact_to_mass_centre(body, gamma)
    v1, v2, v3 = w2 * r3 - w3 * r2, w3 * r1 - w1 * r3, w1 * r2 - w2 * r1
    T = 0.5 * (v1 * v1 + v2 * v2 + v3 * v3) + 0.5 * (body.I1 * w1 * w1 + body.I2 * w2 * w2 + body.I3 * w3 * w3)
    if isinstance(body, LoadedSphere):
        c1, c2, c3 = body.offset
        return T + body.g * (body.offset_norm + (c1 * g1 + c2 * g2 + c3 * g3))
    return T + body.g * body.a * (1.0 - g3)


def jellett(body: Body | LoadedSphere, gamma: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """Jellett's quantity Q_J = I1 s ω2' + I3 f ω3' (paper eqs. jellett, JelletandRouth_Qtys); for a mass centre on the
    third axis only (a LoadedSphere gives a ValueError: its Jellett quantity is M·r, analysis.hierarchy)."""
    body = _require_on_axis(body, "Q_J (paper eq. (16))")
    g1, g2, g3 = np.asarray(gamma, float)
    w1, w2, w3 = np.asarray(omega, float)
    return body.I1 * (g1 * w1 + g2 * w2) + body.I3 * (g3 - body.a) * w3


def routh(body: Body | LoadedSphere, gamma: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """Routh's quantity Q_R = ω3'/ρ (paper eqs. routh, measure); for a mass centre on the third axis only."""
    body = _require_on_axis(body, "Q_R (paper eq. (17))")
    g1, g2, g3 = np.asarray(gamma, float)
    w3 = np.asarray(omega, float)[2]
    return w3 * rho_inv(body, g1 * g1 + g2 * g2, g3 - body.a)


def contact_momentum(body: Body | LoadedSphere, gamma: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """Angular momentum about the contact point, M = I ω + r × (ω × r) = K(γ) ω, r = γ + c, in body components.

    K(γ) = diag(I) + (r·r) 1 − r rᵀ is the mass matrix of the direct equations
    (:func:`rocknroller.analysis.model.equations.body_frame_rhs`); shape (3, ...) like ``omega``.
    """
    w = np.asarray(omega, float)
    r = np.array(_contact_to_mass_centre(body, np.asarray(gamma, float)))
    rr, rw = np.sum(r * r, axis=0), np.sum(r * w, axis=0)
    inertia = np.array([body.I1, body.I2, body.I3]).reshape((3,) + (1,) * (w.ndim - 1))
    return inertia * w + rr * w - rw * r


def momentum_squared(body: Body | LoadedSphere, gamma: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """M·M, M the angular momentum about the contact point (:func:`contact_momentum`): Chaplygin's integral of the
    ball (c = 0), where M is constant in space (the reaction passes through the centre, which is the mass centre)."""
    M = contact_momentum(body, gamma, omega)
    return np.sum(M * M, axis=0)


def momentum_vertical(body: Body | LoadedSphere, gamma: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """M·γ, M about the contact point: Chaplygin's area integral of the ball (c = 0), and for every member the
    component of M along the vertical (paper eq. jellett's Q_J is M·r for Routh's sphere, not M·γ)."""
    M = contact_momentum(body, gamma, omega)
    return np.sum(M * np.asarray(gamma, float), axis=0)


def momentum_along_offset_line(body: Body | LoadedSphere, gamma: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """M·r = Iω·r, r = γ + c: Jellett's quantity of the family, the paper's Q_J = I1 s ω2' + I3 f ω3' where I1 = I2
    and c = (0, 0, −a) (paper eq. jellett), defined for every member (r × (ω × r) is normal to r).

    Examples
    --------
    >>> import numpy as np
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.model.invariants import jellett, momentum_along_offset_line
    >>> body = rr.Body.paper()
    >>> gamma, omega = np.array([0.6, 0.0, -0.8]), np.array([0.1, 0.2, -0.3])
    >>> print(f"{jellett(body, gamma, omega):.15f} {momentum_along_offset_line(body, gamma, omega):.15f}")
    0.123000000000000 0.123000000000000
    """
    w1, w2, w3 = np.asarray(omega, float)
    r1, r2, r3 = _contact_to_mass_centre(body, np.asarray(gamma, float))
    return body.I1 * w1 * r1 + body.I2 * w2 * r2 + body.I3 * w3 * r3


def routh_on_axis(body: Body | LoadedSphere, gamma: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """Routh's quantity ω3/ρ, ρ⁻² = I3 + s² + (I3/I1) f² with f = γ3 + c3 (paper eqs. routh, measure), for any member
    whose mass centre lies on the third axis (c1 = c2 = 0; f = cos θ − a for a Body): a ValueError otherwise."""
    if isinstance(body, LoadedSphere) and (body.offset[0] != 0.0 or body.offset[1] != 0.0):
        raise ValueError(f"Routh's Q_R needs the mass centre on the third axis (c1 = c2 = 0); this {body.kind} has "
                         f"c = {body.offset!r}")
    g1, g2, g3 = np.asarray(gamma, float)
    r3 = _contact_to_mass_centre(body, (g1, g2, g3))[2]
    return np.asarray(omega, float)[2] * np.sqrt(rho_inv_sq(body, g1 * g1 + g2 * g2, r3))


def borisov_mamaev(body: Body | LoadedSphere, gamma: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """Borisov and Mamaev's quantity B = M² − 2K r², with K = E the energy (paper, Conclusions).

    M is :func:`contact_momentum`, r = γ + c.  Along the motion (unit mass, ``body_frame_rhs``)

        d(M²)/dt = 2T d(r²)/dt + 2 g M·(γ × c),

    so without gravity (g = 0, T = E constant) B is a first integral for any moments I1, I2, I3 and any offset c, and
    with gravity it is not (tests/analysis/model/test_borisov_mamaev.py proves the identity with sympy and checks both
    cases against the direct ODE; docs/theory/further_integral.md).  The paper does not define K; for m = 1 the
    identity fixes it as the kinetic energy, which equals E at g = 0.
    """
    r1, r2, r3 = _contact_to_mass_centre(body, np.asarray(gamma, float))
    return momentum_squared(body, gamma, omega) - 2.0 * energy(body, gamma, omega) * (r1 * r1 + r2 * r2 + r3 * r3)


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
