"""The rock'n'roller's state and the right-hand sides of its equations of motion, in four formulations.

:class:`EulerState` is an initial state in Euler angles and rates (or body-frame ω), with its conversion to the
body-frame state y of form (i); ``RATE_MAX`` bounds its rates.

(i)   :func:`body_frame_rhs` — the production form, singularity-free, in the body frame.
      State y = (γ, ω, e_X, X, Y) (11 components, layout in :data:`STATE_LAYOUT`): γ the upward
      vertical and e_X the space X axis, both in body components; ω the body-frame angular
      velocity; (X, Y) the contact point.  With r = γ − a e3 (contact point → mass centre),

          K(γ) ω̇ = P(γ, ω),  K = diag(I) + (r·r) 1 − r rᵀ,
          P = −ω × Iω − r × (ω × γ̇ + ω × (ω × r)) + g a e3 × γ,
          γ̇ = γ × ω,  ė_X = e_X × ω,  Ẋ = ω·e_Y,  Ẏ = −ω·e_X  (e_Y = γ × e_X).

      (Newton–Euler about the mass centre with the rolling constraint v = ω × r and the reaction
      eliminated; the contact point moves with the geometric centre, v_C = ω × Z.)
      It uses only + − × ÷, so the same function builds heyoka expressions and evaluates numpy arrays.
(ii)  :func:`euler_angle_rhs` — the paper's system Σ θ̇ = ω, K ω̇ = P_ω (paper eq. thetaomega).
(iii) :func:`euler_lagrange_rhs` — the paper's M θ̈ + P_θ = 0 (paper eq. ELtheta, App. A.3).
(iv)  :func:`intermediate_frame_rhs` — the symmetric intermediate-frame system (paper App. A.2), I1 = I2.

Forms (ii)-(iv) are transcribed from the paper as printed and serve as independent checks of (i).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body, require_finite
from rocknroller.analysis.model.kinematics import (angles_from_frame, omega_from_rates, primed_from_body,
                                                   rates_from_omega, space_axes_in_body)

__all__ = [
    "cross",
    "dot",
    "RATE_MAX",
    "STATE_LAYOUT",
    "STATE_SIZE",
    "EulerState",
    "FIG5_THETA0",
    "FIG5_OMEGA0",
    "fig5_start",
    "body_frame_rhs",
    "turning_point_function",
    "state_from_euler",
    "euler_from_state",
    "euler_angle_rhs",
    "euler_lagrange_rhs",
    "intermediate_frame_rhs",
    "euler_angle_state_from_body",
    "lagrange_state_from_euler_angle",
    "intermediate_state_from_euler_angle",
    "omega_dot_from_lagrange",
    "omega_dot_from_intermediate",
    "omega_dot_by_form",
    "formulation_differences",
]

#: Slices of the 11-component body-frame state of form (i).
STATE_LAYOUT = {"gamma": slice(0, 3), "omega": slice(3, 6), "ex": slice(6, 9), "X": 9, "Y": 10}
STATE_SIZE = 11


def cross(u: Sequence[Any], v: Sequence[Any]) -> tuple[Any, Any, Any]:
    """u × v of two 3-vectors of any ring's elements (floats, sympy polynomials): only + − ×.

    Examples
    --------
    >>> from rocknroller.analysis.model.equations import cross
    >>> cross((1, 0, 0), (0, 1, 0))
    (0, 0, 1)
    """
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def dot(u: Sequence[Any], v: Sequence[Any]) -> Any:
    """u · v of two 3-vectors of any ring's elements.

    Examples
    --------
    >>> from rocknroller.analysis.model.equations import dot
    >>> dot((1, 2, 3), (4, 5, 6))
    32
    """
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def _solve_sym3(K: Sequence[Sequence[Any]], P: Sequence[Any]) -> tuple[Any, Any, Any]:
    """Solve the symmetric 3×3 system K x = P by the adjugate (only + − × ÷)."""
    (k11, k12, k13), (_, k22, k23), (_, _, k33) = K
    c11 = k22 * k33 - k23 * k23
    c12 = k13 * k23 - k12 * k33
    c13 = k12 * k23 - k13 * k22
    c22 = k11 * k33 - k13 * k13
    c23 = k12 * k13 - k11 * k23
    c33 = k11 * k22 - k12 * k12
    det = k11 * c11 + k12 * c12 + k13 * c13
    p1, p2, p3 = P
    return (
        (c11 * p1 + c12 * p2 + c13 * p3) / det,
        (c12 * p1 + c22 * p2 + c23 * p3) / det,
        (c13 * p1 + c23 * p2 + c33 * p3) / det,
    )


#: A state or parameter vector as form (i) takes it, component by component: a numpy array (components along the
#: first axis, any common shape after it) or a sequence (of floats, or of heyoka expressions and parameters).
_Components = Sequence[Any] | NDArray[Any]


def turning_point_function(y: _Components) -> Any:
    """d(γ3)/dt = γ1 ω2 − γ2 ω1 = −sin θ · θ̇; zero exactly at the turning points of θ.

    Rising through zero: a maximum of θ; falling: a minimum.
    """
    return y[0] * y[4] - y[1] * y[3]


def body_frame_rhs(y: _Components, p: _Components) -> list[Any]:
    """Form (i): time derivative of the 11-component body-frame state.

    Parameters
    ----------
    y : sequence
        (γ1, γ2, γ3, ω1, ω2, ω3, X1, X2, X3, X, Y): vertical, angular velocity and space X axis in
        body components, contact point in space.  Numpy arrays (any common shape) or heyoka expressions.
    p : sequence
        (a, I1, I2, I3, g) for a mass centre on the third axis (:class:`~rocknroller.analysis.model.body.Body`), or
        (c1, c2, c3, I1, I2, I3, g) for a mass centre anywhere
        (:class:`~rocknroller.analysis.model.loaded_sphere.LoadedSphere`, paper fig. 1); floats or heyoka
        parameters.  With c the offset of the mass centre from the geometric centre, r = γ + c runs from the contact
        point to the mass centre and gravity's torque about the contact point is g γ × c; the on-axis form is
        c = (0, 0, −a), with its own arithmetic (g a e3 × γ), unchanged.

    Returns
    -------
    list
        The 11 derivatives, of the same kind as the input.

    Examples
    --------
    >>> import numpy as np
    >>> from rocknroller.analysis.model.equations import body_frame_rhs
    >>> y = np.array([0.3, 0.0, -0.9539392014169456, 0.1, -0.2, 0.5, 1.0, 0.0, 0.0, 0.0, 0.0])
    >>> on_axis = body_frame_rhs(y, (0.05, 0.35, 0.36, 0.4, 9.87))
    >>> general = body_frame_rhs(y, (0.0, 0.0, -0.05, 0.35, 0.36, 0.4, 9.87))
    >>> print(bool(np.allclose(on_axis, general, rtol=1e-14, atol=1e-14)))
    True
    """
    g1, g2, g3 = y[0], y[1], y[2]
    if len(p) == 7:
        c1, c2, c3, I1, I2, I3, grav = p
        r = (g1 + c1, g2 + c2, g3 + c3)
        P0, rest = _rolling_terms(y, (I1, I2, I3), r)
        P = (P0[0] + grav * (g2 * c3 - g3 * c2), P0[1] + grav * (g3 * c1 - g1 * c3),
             P0[2] + grav * (g1 * c2 - g2 * c1))
    else:
        a, I1, I2, I3, grav = p
        r = (g1, g2, g3 - a)
        P0, rest = _rolling_terms(y, (I1, I2, I3), r)
        ga = grav * a
        P = (P0[0] - ga * g2, P0[1] + ga * g1, P0[2])
    rr = dot(r, r)
    K = (
        (I1 + rr - r[0] * r[0], -r[0] * r[1], -r[0] * r[2]),
        (None, I2 + rr - r[1] * r[1], -r[1] * r[2]),
        (None, None, I3 + rr - r[2] * r[2]),
    )
    wdot = _solve_sym3(K, P)
    gdot, exdot, Xdot, Ydot = rest
    return [*gdot, *wdot, *exdot, Xdot, Ydot]


def _rolling_terms(y: _Components, inertia: tuple[Any, Any, Any], r: tuple[Any, Any, Any]
                   ) -> tuple[tuple[Any, Any, Any], tuple[Any, Any, Any, Any]]:
    """Form (i)'s torque about the contact point without gravity, −ω × Iω − r × (ω × γ̇ + ω × (ω × r)), and the
    kinematics (γ̇, ė_X, Ẋ, Ẏ), for :func:`body_frame_rhs`."""
    g1, g2, g3, w1, w2, w3, x1, x2, x3 = y[:9]
    I1, I2, I3 = inertia
    gam = (g1, g2, g3)
    om = (w1, w2, w3)
    gdot = cross(gam, om)
    Iw = (I1 * w1, I2 * w2, I3 * w3)
    wxr = cross(om, r)
    w_gdot, w_wxr = cross(om, gdot), cross(om, wxr)
    inner = (w_gdot[0] + w_wxr[0], w_gdot[1] + w_wxr[1], w_gdot[2] + w_wxr[2])
    t1 = cross(om, Iw)
    t2 = cross(r, inner)
    ex = (x1, x2, x3)
    exdot = cross(ex, om)
    ey = cross(gam, ex)
    return (-t1[0] - t2[0], -t1[1] - t2[1], -t1[2] - t2[2]), (gdot, exdot, dot(om, ey), -dot(om, ex))


#: Largest absolute rate of an initial state (θ̇, φ̇, ψ̇ or a component of ω): the body-frame ω, its square in the
#: energy and φ̇ = ω/sin²θ-type conversions stay in double range.  (simulate() refuses far smaller energies.)
RATE_MAX = 1e150


@dataclass(frozen=True)
class EulerState:
    """An initial state in Euler angles and Euler rates (paper eq. angledot).

    Parameters
    ----------
    theta : float
        Tilt, ``0 <= theta <= pi``.
    phi, psi : float
        Azimuth and spin angles (any finite value).
    theta_dot, phi_dot, psi_dot : float
        Euler rates.
    X, Y : float
        Initial contact point (default 0).
    omega : (ω1, ω2, ω3), optional
        The body-frame angular velocity the rates were computed from (set by :meth:`from_omega`).
        When present, :meth:`to_body_state` uses it as given rather than rebuilding it from the rates,
        which near θ = π (or 0) would cost digits: φ̇ and ψ̇ are then large and nearly opposite.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> start = rr.EulerState.from_omega(0.95 * math.pi, 0.0, 0.0, (0.0, 1e-3, -1e-3))
    >>> print(f"theta = {start.theta / math.pi:.2f} pi, theta_dot = {start.theta_dot:.1e}")
    theta = 0.95 pi, theta_dot = 0.0e+00
    >>> rest = rr.EulerState(theta=0.95 * math.pi, psi=math.pi / 4)
    >>> print(rest.theta_dot, rest.phi_dot, rest.psi_dot)
    0.0 0.0 0.0
    """

    theta: float
    phi: float = 0.0
    psi: float = 0.0
    theta_dot: float = 0.0
    phi_dot: float = 0.0
    psi_dot: float = 0.0
    X: float = 0.0
    Y: float = 0.0
    omega: tuple[float, float, float] | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        for name in ("theta", "phi", "psi", "theta_dot", "phi_dot", "psi_dot", "X", "Y"):
            object.__setattr__(self, name, require_finite(name, getattr(self, name)))
        if not 0.0 <= self.theta <= math.pi:
            raise ValueError(f"theta0 must satisfy 0 <= theta0 <= pi, got theta0={self.theta!r}")
        for name in ("theta_dot", "phi_dot", "psi_dot"):
            if abs(getattr(self, name)) > RATE_MAX:
                raise ValueError(f"{name} must satisfy |{name}| <= {RATE_MAX:g} (the body-frame angular velocity and "
                                 f"the energy must stay in double range), got {name}={getattr(self, name)!r}")
        if self.omega is not None:
            om = np.asarray(self.omega, float)
            if om.shape != (3,) or not np.all(np.isfinite(om)) or np.any(np.abs(om) > RATE_MAX):
                raise ValueError(f"omega must be three finite numbers (w1, w2, w3) with |w| <= {RATE_MAX:g}, "
                                 f"got {self.omega!r}")
            object.__setattr__(self, "omega", tuple(float(w) for w in om))

    @classmethod
    def from_omega(cls, theta: float, phi: float, psi: float, omega: ArrayLike,
                   X: float = 0.0, Y: float = 0.0) -> "EulerState":
        """State from the body-frame angular velocity ω = (ω1, ω2, ω3); needs 0 < θ < π."""
        om = np.asarray(omega, float)
        if om.shape != (3,) or not np.all(np.isfinite(om)) or np.any(np.abs(om) > RATE_MAX):
            raise ValueError(f"omega must be three finite numbers (w1, w2, w3) with |w| <= {RATE_MAX:g}, "
                             f"got omega={om.tolist()!r}")
        if not 0.0 < float(theta) < math.pi:
            raise ValueError(
                "theta0 must satisfy 0 < theta0 < pi when the body-frame omega is given "
                f"(the Euler rates are singular at theta = 0, pi), got theta0={theta!r}"
            )
        with np.errstate(over="ignore"):
            td, pd, sd = (float(r) for r in rates_from_omega(theta, psi, om))
        if not all(math.isfinite(r) and abs(r) <= RATE_MAX for r in (td, pd, sd)):
            raise ValueError(f"theta0={theta!r} is too close to the vertical for omega={om.tolist()!r}: the Euler "
                             f"rates (phi_dot ~ omega/sin(theta)^2) exceed {RATE_MAX:g}")
        return cls(theta, phi, psi, td, pd, sd, X, Y, omega=(float(om[0]), float(om[1]), float(om[2])))

    def to_body_state(self) -> NDArray[np.float64]:
        """The 11-component body-frame state of form (i) (with ``omega`` as given, if present)."""
        y = state_from_euler(self.theta, self.phi, self.psi, self.theta_dot, self.phi_dot, self.psi_dot,
                             self.X, self.Y)
        if self.omega is not None:
            y[3:6] = self.omega
        return y


#: The start of the paper's fig. 5 (§7.1): θ0 = 0.95π, φ0 = ψ0 = 0, body-frame ω = (0, 0.001, −0.001); also the
#: default start of ``rocknroller simulate`` (:func:`fig5_start`).
FIG5_THETA0 = 0.95 * math.pi
FIG5_OMEGA0 = (0.0, 0.001, -0.001)


def fig5_start() -> EulerState:
    """The figure-5 start (paper §7.1): θ0 = ``FIG5_THETA0``, φ0 = ψ0 = 0, ω = ``FIG5_OMEGA0``."""
    return EulerState.from_omega(FIG5_THETA0, 0.0, 0.0, FIG5_OMEGA0)


def state_from_euler(theta: ArrayLike, phi: ArrayLike, psi: ArrayLike, theta_dot: ArrayLike,
                     phi_dot: ArrayLike, psi_dot: ArrayLike, X: ArrayLike = 0.0,
                     Y: ArrayLike = 0.0) -> NDArray[np.float64]:
    """Body-frame state (γ, ω, e_X, X, Y) from Euler angles and rates; shape (11, ...)."""
    axes = space_axes_in_body(theta, phi, psi)
    omega = omega_from_rates(theta, psi, theta_dot, phi_dot, psi_dot)
    shape = np.broadcast(np.asarray(theta), np.asarray(phi), np.asarray(psi)).shape
    XY = np.broadcast_to(np.array([X, Y], dtype=float).reshape((2,) + (1,) * len(shape)), (2,) + shape)
    return np.concatenate([np.broadcast_to(axes[2], (3,) + shape), np.broadcast_to(omega, (3,) + shape),
                           np.broadcast_to(axes[0], (3,) + shape), XY])


def euler_from_state(y: ArrayLike) -> NDArray[np.float64]:
    """(θ, φ, ψ, θ̇, φ̇, ψ̇) from body-frame states y of shape (11, ...); angles in (−π, π]."""
    y = np.asarray(y, float)
    theta, phi, psi = angles_from_frame(y[0:3], y[6:9])
    return np.concatenate([[theta, phi, psi], rates_from_omega(theta, psi, y[3:6])])


# ---------------------------------------------------------------- form (ii): paper eq. (thetaomega)
def _sigma_matrix(theta: float, psi: float) -> NDArray[np.float64]:
    """The paper's Σ(θ, ψ) of eq. (thetaomega), ω = Σ θ̇, transcribed here rather than taken from
    rocknroller.analysis.model.kinematics so that forms (ii) and (iii) stay independent transcriptions of the paper,
    checked against form (i) and the kinematics by tests/analysis/model/test_equations.py."""
    s, c, sg, ch = math.sin(theta), math.cos(theta), math.sin(psi), math.cos(psi)
    return np.array([[ch, s * sg, 0.0], [-sg, s * ch, 0.0], [0.0, c, 1.0]])


def euler_angle_rhs(x: ArrayLike, body: Body) -> NDArray[np.float64]:
    """Form (ii), the paper's Σ θ̇ = ω, K ω̇ = P_ω, state x = (θ, φ, ψ, ω1, ω2, ω3) (paper eq. thetaomega)."""
    theta, _, psi, w1, w2, w3 = (float(v) for v in np.asarray(x, float))
    a, I1, I2, I3, g = body.params
    s, c, sg, ch = math.sin(theta), math.cos(theta), math.sin(psi), math.cos(psi)
    f = c - a
    K = np.array([
        [I1 + f * f + s * s * ch * ch, -s * s * sg * ch, -f * s * sg],
        [-s * s * sg * ch, I2 + f * f + s * s * sg * sg, -f * s * ch],
        [-f * s * sg, -f * s * ch, I3 + s * s],
    ])
    G = g + w1 * w1 + w2 * w2
    P = np.array([
        -G * a * s * ch + (I2 - I3 - a * f) * w2 * w3,
        G * a * s * sg + (I3 - I1 + a * f) * w1 * w3,
        (I1 - I2) * w1 * w2 + a * s * (-ch * w1 + sg * w2) * w3,
    ])
    rates = np.linalg.solve(_sigma_matrix(theta, psi), [w1, w2, w3])
    return np.concatenate([rates, np.linalg.solve(K, P)])


# ---------------------------------------------------------------- form (iii): paper App. A.3
def euler_lagrange_rhs(x: ArrayLike, body: Body) -> NDArray[np.float64]:
    """Form (iii), the paper's M θ̈ + P_θ = 0, state x = (θ, φ, ψ, θ̇, φ̇, ψ̇) (paper eq. ELtheta)."""
    theta, _, psi, td, pd, sd = (float(v) for v in np.asarray(x, float))
    a, I1, I2, I3, g = body.params
    s, c, sg, ch = math.sin(theta), math.cos(theta), math.sin(psi), math.cos(psi)
    h = 1.0 - a * c
    dI = I1 - I2
    M = np.array([
        [I1 * ch * ch + I2 * sg * sg + a * a * s * s + h * h, dI * s * sg * ch, 0.0],
        [dI * s * sg * ch, (I1 * sg * sg + I2 * ch * ch + a * a) * s * s + I3 * c * c, I3 * c + a * s * s],
        [0.0, I3 * c + a * s * s, I3 + s * s],
    ])
    S = I1 * sg * sg + I2 * ch * ch
    c2 = ch * ch - sg * sg
    P_theta = (a * s * td * td + (-(S - I3) * s * c + h * a * s) * pd * pd + (-dI * 2 * sg * ch) * td * sd
               + (dI * s * c2 + I3 * s + h * s) * pd * sd + g * a * s)
    P_phi = (dI * c * sg * ch * td * td + ((S - I3) * 2 * s * c + (2 * a * c - 1) * a * s) * td * pd
             + (dI * s * c2 - I3 * s + a * s * c) * td * sd + dI * 2 * s * s * sg * ch * pd * sd)
    P_psi = (dI * sg * ch * td * td - dI * s * s * sg * ch * pd * pd
             + (-(dI * c2 + I3) * s + (2 * a * c - 1) * s) * td * pd + s * c * td * sd)
    acc = np.linalg.solve(M, -np.array([P_theta, P_phi, P_psi]))
    return np.concatenate([[td, pd, sd], acc])


# ---------------------------------------------------------------- form (iv): paper App. A.2
def intermediate_frame_rhs(x: ArrayLike, body: Body) -> NDArray[np.float64]:
    """Form (iv), the symmetric system in the intermediate frame, state x = (θ, φ, ψ, ω1', ω2', ω3').

    Paper eqs. (omegasdot), (anglesdot) and (PPP), App. A.2; requires I1 = I2.
    """
    body.require_symmetric("the intermediate-frame system (paper App. A.2)")
    theta, _, _, u1, u2, u3 = (float(v) for v in np.asarray(x, float))
    a, I1, _, I3, g = body.params
    s, c = math.sin(theta), math.cos(theta)
    f, h = c - a, 1.0 - a * c
    O1, O2, O3 = u1, u2, c * u2 / s
    G10 = -(a * s * u1 * u1 - h * (f * u2 - s * u3) * u2 / s) - g * a * s
    G20 = -(-f * u1 * (s * u2 + c * u3) + h * f * u1 * u2 / s)
    G30 = -(s * u1 * (s * u2 + c * u3) - h * u1 * u2)
    P1 = -(I3 * O2 * u3 - I1 * O3 * u2) + G10
    P2 = -(I1 * O3 * u1 - I3 * O1 * u3) + G20
    P3 = G30
    S1 = P1 / (I1 + s * s + f * f)
    Delta = I1 * I3 + I1 * s * s + I3 * f * f
    S2 = ((I3 + s * s) * P2 + f * s * P3) / Delta
    S3 = (f * s * P2 + (I1 + f * f) * P3) / Delta
    return np.array([u1, u2 / s, u3 - c * u2 / s, S1, S2, S3])


# ---------------------------------------------------------------- conversions between the forms
def euler_angle_state_from_body(y: ArrayLike) -> NDArray[np.float64]:
    """Form (i) state → form (ii) state (θ, φ, ψ, ω1, ω2, ω3)."""
    y = np.asarray(y, float)
    return np.concatenate([angles_from_frame(y[0:3], y[6:9]), y[3:6]])


def lagrange_state_from_euler_angle(x: ArrayLike) -> NDArray[np.float64]:
    """Form (ii) state → form (iii) state (θ, φ, ψ, θ̇, φ̇, ψ̇), θ̇ = Σ⁻¹ ω."""
    x = np.asarray(x, float)
    return np.concatenate([x[:3], rates_from_omega(x[0], x[2], x[3:6])])


def intermediate_state_from_euler_angle(x: ArrayLike) -> NDArray[np.float64]:
    """Form (ii) state → form (iv) state (θ, φ, ψ, ω1', ω2', ω3')."""
    x = np.asarray(x, float)
    return np.concatenate([x[:3], primed_from_body(x[2], x[3:6])])


def omega_dot_from_lagrange(x: ArrayLike, xdot: ArrayLike) -> NDArray[np.float64]:
    """Body-frame ω̇ = Σ θ̈ + Σ̇ θ̇ from a form-(iii) state x = (θ, φ, ψ, θ̇, φ̇, ψ̇) and its derivative."""
    theta, _, psi, td, pd, sd = (float(v) for v in np.asarray(x, float))
    s, c, sg, ch = math.sin(theta), math.cos(theta), math.sin(psi), math.cos(psi)
    sigma_dot = np.array([[-sg * sd, c * sg * td + s * ch * sd, 0.0],
                          [-ch * sd, c * ch * td - s * sg * sd, 0.0],
                          [0.0, -s * td, 0.0]])
    return _sigma_matrix(theta, psi) @ np.asarray(xdot, float)[3:] + sigma_dot @ np.array([td, pd, sd])


def omega_dot_from_intermediate(x: ArrayLike, xdot: ArrayLike) -> NDArray[np.float64]:
    """Body-frame ω̇ from a form-(iv) state x = (θ, φ, ψ, ω1', ω2', ω3') and its derivative (ω = R(ψ) ω')."""
    _, _, psi, u1, u2, _ = (float(v) for v in np.asarray(x, float))
    d = np.asarray(xdot, float)
    sg, ch, sd = math.sin(psi), math.cos(psi), d[2]
    return np.array([ch * d[3] + sg * d[4] + sd * (-sg * u1 + ch * u2),
                     -sg * d[3] + ch * d[4] + sd * (-ch * u1 - sg * u2), d[5]])


def omega_dot_by_form(y: ArrayLike, body: Body) -> dict[str, NDArray[np.float64]]:
    """Body-frame ω̇ of the form-(i) state ``y`` computed by the paper's forms: "ii" (Σθ̇ = ω, Kω̇ = P_ω),
    "iii" (Euler–Lagrange, App. A.3) and, for I1 = I2, "iv" (intermediate frame, App. A.2)."""
    x2 = euler_angle_state_from_body(y)
    x3 = lagrange_state_from_euler_angle(x2)
    out = {"ii": euler_angle_rhs(x2, body)[3:], "iii": omega_dot_from_lagrange(x3, euler_lagrange_rhs(x3, body))}
    if body.is_symmetric:
        x4 = intermediate_state_from_euler_angle(x2)
        out["iv"] = omega_dot_from_intermediate(x4, intermediate_frame_rhs(x4, body))
    return out


def formulation_differences(Y: ArrayLike, body: Body) -> dict[str, float]:
    """Largest |ω̇_form − ω̇_(i)|∞ / (1 + |ω̇_(i)|∞) over the states ``Y`` (shape (11, n)) for each form of
    :func:`omega_dot_by_form`: how far the paper's formulations are from form (i)."""
    Y = np.asarray(Y, float)
    D = np.array(body_frame_rhs(Y, body.params))
    worst: dict[str, float] = {}
    for y, d in zip(Y.T, D.T):
        scale = 1.0 + np.max(np.abs(d[3:6]))
        for form, wdot in omega_dot_by_form(y, body).items():
            worst[form] = max(worst.get(form, 0.0), float(np.max(np.abs(wdot - d[3:6]))) / scale)
    return worst
