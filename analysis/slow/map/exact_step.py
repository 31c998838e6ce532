"""The exact one-step map of the asymmetric body, maximum of θ → next maximum, at fixed energy; its ε-derivatives.
It holds the step of the family member I2 = (1 + ε) I1 by the direct ODE (:func:`exact_step`, with the wrapping of
its angle differences: :func:`step_difference`) and its first and second ε-derivatives at ε = 0 by extrapolated
central differences (:func:`eps_derivatives`, :class:`EpsDerivatives`); the step's Q_R and Q_J are those of
paper eq. JelletandRouth_Qtys.

:func:`exact_step_jacobian` is the step's derivative in x = (Q_R, Q_J, Θ = 2ψ) by the chain rule through the one
rock (:class:`rocknroller.analysis.slow.map.maps.ExactMap`'s Jacobian; that module's docstring gives the terms).

The averaged slow map (:mod:`rocknroller.analysis.slow.prediction`) expands one step at fixed (E, Q_n, ψ_n) in
ε = (I2 − I1)/I1 about Routh's sphere.  Here the same step is computed without expansion: the state at a maximum
with the given (E, Q_R, Q_J, ψ) is solved for the body with I2 = (1 + ε) I1
(:func:`rocknroller.analysis.slow.map.family.maximum_state`: θ̇ = 0, φ = 0; Q_R and Q_J are linear in (φ̇, ψ̇), E then
fixes θ), and the direct ODE (``rocknroller.numerics.integrate.simulate``, heyoka, tolerance the unit round-off)
carries it to the next maximum.  Its ε-derivatives at ε = 0 follow by central differences
(:func:`eps_derivatives`): the first is an independent check of the variational equations of
:func:`rocknroller.analysis.slow.map.orbit.first_order_step`, the second of the second-order ones
(:func:`rocknroller.analysis.slow.map.orbit.second_order_step`) from which the second-order kick k₂ is built
(:mod:`rocknroller.analysis.slow.map.second_order`).  A member with ε < 0 (I2 < I1) is the body with its principal
axes i, j relabelled (j, −i): moments ((1 + ε) I1, I1) and Euler angle ψ + π/2; Q_R and Q_J are invariant under
that rotation about the symmetry axis and are always computed with the family's I1.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.model.equations import body_frame_rhs, state_from_euler, turning_point_function
from rocknroller.analysis.model.invariants import energy, jellett, routh
from rocknroller.analysis.slow.map.family import (_central_difference, _central_second_difference,
                                                   directional_derivative, family_member, maximum_state)
from rocknroller.analysis.slow.map.orbit import FIRST_ORDER_NAMES, _psi_of, _QJ_of, _QR_of, symmetric_data

__all__ = ["STEP_NAMES", "exact_step", "exact_step_jacobian", "step_difference", "EpsDerivatives", "eps_derivatives"]

#: What one step returns, in this order: Q_R, Q_J, Θ = 2ψ, t and φ at the next maximum (Θ and φ continued from the
#: start, so that differences between neighbouring steps are small): the components of the first-order responses.
STEP_NAMES = FIRST_ORDER_NAMES
#: The angle components of a step (Θ, φ), whose differences are wrapped.
_ANGLE_COMPONENTS = (2, 4)


def exact_step(sym: Body, eps: float, E: float, QR: float, QJ: float, psi: float,
               period: float | None = None) -> NDArray[np.float64]:
    """One step of the family member I2 = (1 + ε) I1 from the maximum (E, Q_R, Q_J, ψ): the values of
    ``STEP_NAMES`` at the next maximum (Θ = 2ψ and φ continued from 2ψ and 0 by the run's unwrapped angles).

    ``period`` is the symmetric body's T_θ at (E, Q) (quadrature when not given); the next maximum is the first one
    of the run after half of it.
    """
    from rocknroller.numerics.integrate import simulate

    if period is None:
        period = float(symmetric_data(sym, E, QR, QJ)[0])
    body, shift, start = maximum_state(sym, eps, E, QR, QJ, psi)
    m = simulate(body, start, 1.5 * period, samples=False).maxima
    k = int(np.nonzero(m.t > 0.5 * period)[0][0])
    y = m.states[k]
    return np.array([float(routh(sym, y[0:3], y[3:6])), float(jellett(sym, y[0:3], y[3:6])),
                     2.0 * (float(m.psi[k]) - shift), float(m.t[k]), float(m.phi[k])])


def exact_step_jacobian(sym: Body, eps: float, E: float, x: NDArray[np.float64]) -> NDArray[np.float64]:
    """∂(Q_R', Q_J', Θ')/∂(Q_R, Q_J, Θ) of :func:`exact_step` from the maximum x = (Q_R, Q_J, Θ = 2ψ) (3,) of the
    member I2 = (1 + ε) I1 at the energy E: the start's dependence on x (six conditions), the variational equations
    of the (γ, ω) system to the next maximum (three runs), the event time's dependence and the outputs' gradients
    (:mod:`rocknroller.analysis.slow.map.maps`' docstring).

    Raises
    ------
    ValueError
        (E, Q) admits no motion.
    """
    from rocknroller.numerics.variational import tangent_to_maximum

    member = family_member(sym, eps)[0]
    T = float(symmetric_data(sym, E, float(x[0]), float(x[1]))[0])
    st = maximum_state(sym, eps, E, float(x[0]), float(x[1]), 0.5 * float(x[2]))[2]
    y0 = state_from_euler(st.theta, 0.0, st.psi, 0.0, st.phi_dot, st.psi_dot)
    conditions = [(_QR_of(sym), False), (_QJ_of(sym), False), (_psi_of, True),
                  (lambda y: energy(member, y[0:3], y[3:6]), False), (turning_point_function, False),
                  (lambda y: y[0] * y[0] + y[1] * y[1] + y[2] * y[2], False)]
    C = np.vstack([_gradient(f, y0, angle) for f, angle in conditions])
    P = np.zeros((6, 3))
    P[0, 0], P[1, 1], P[2, 2] = 1.0, 1.0, 0.5
    dy0 = np.asarray(np.linalg.solve(C, P), float)  # ∂(γ, ω)/∂x at the start: C⁻¹ P
    Y1, W = np.zeros(11), np.empty((6, 3))
    for j in range(3):
        _, Y1[:6], W[:, j] = tangent_to_maximum(member, y0[:6], dy0[:, j], 0.5 * T, 1.5 * T)
    f = np.zeros(11)
    f[:6] = np.array(body_frame_rhs(Y1, member.params)[:6], float)
    dY = np.zeros((11, 3))
    dY[:6] = W
    dh = _gradient(turning_point_function, Y1, False)
    dY[:6] -= np.outer(f[:6], dh @ W / (dh @ f[:6]))
    outputs = [(_QR_of(sym), False, 1.0), (_QJ_of(sym), False, 1.0), (_psi_of, True, 2.0)]
    return np.vstack([c * _gradient(g, Y1, angle) @ dY[:6] for g, angle, c in outputs])


def _gradient(fun: Any, y: NDArray[np.float64], angle: bool) -> NDArray[np.float64]:
    """∂fun/∂(γ, ω) at the body-frame state y (11,): fourth-order differences along the six unit vectors."""
    V = np.zeros((11, 6))
    V[:6, :6] = np.eye(6)
    return np.asarray(directional_derivative(fun, np.repeat(y[:, None], 6, axis=1), V, angle=angle), float)


def step_difference(d: NDArray[np.float64]) -> NDArray[np.float64]:
    """A difference of two steps (or of their first components) with its angle components (Θ, φ) wrapped to
    (−π, π]."""
    d = np.array(d, float)
    for i in _ANGLE_COMPONENTS:
        if i < d.size:
            d[i] = float(wrap_angle(d[i]))
    return d


@dataclass(frozen=True)
class EpsDerivatives:
    """First and second ε-derivatives at ε = 0 of one exact step at fixed (E, Q_R, Q_J, ψ).

    Attributes
    ----------
    d1, d2 : ndarray (5,)
        ∂/∂ε and ∂²/∂ε² of ``STEP_NAMES`` at the next maximum: fourth-order central differences with steps h and
        h/2, combined by Richardson's extrapolation (error O(h⁶)).
    d1_error, d2_error : ndarray (5,)
        The size of the Richardson correction, |D(h/2) − D(h)|/15: a bound on the error of the step-h/2 values,
        and (the extrapolation removing that term) a generous one on the extrapolated values.
    h : float
    """

    d1: NDArray[np.float64]
    d2: NDArray[np.float64]
    d1_error: NDArray[np.float64]
    d2_error: NDArray[np.float64]
    h: float


def eps_derivatives(sym: Body, E: float, QR: float, QJ: float, psi: float, h: float = 5e-4) -> EpsDerivatives:
    """∂/∂ε and ∂²/∂ε² of :func:`exact_step` at ε = 0, by central differences over ε ∈ {0, ±h/2, ±h, ±2h}
    (7 exact steps), extrapolated.

    Each exact step is accurate to ~1e-13 relative (heyoka at the unit round-off over one rock; the values are
    ≤ ~60), so round-off adds ~1e-13·60/h to the first derivative and ~1e-13·60/h² to the second (2e-5 at
    h = 5e-4).  Near Q = 0 the ε-series of one step has a radius of only ~1e-2 (the layer where W turns by 2π), so
    the truncation of the stencils is (h/1e-2)⁴ relative before extrapolation: h = 2e-3 leaves 1e-3 of the second
    derivative there (8e-4 at Q = 0.002 e, 0.95π, as its error estimate says), h = 5e-4 leaves 1e-5.

    Raises
    ------
    ValueError
        h outside (0, 0.05] (the family leaves the allowed moments beyond), or a start without motion.
    """
    if not (0.0 < h <= 0.05):
        raise ValueError(f"h must satisfy 0 < h <= 0.05, got h={h!r}")
    period = float(symmetric_data(sym, E, QR, QJ)[0])

    @functools.lru_cache(maxsize=None)  # ε = 0, ±h/2, ±h, ±2h: 7 steps shared by the four stencils (h/2 · 2 = h)
    def step(eps: float) -> NDArray[np.float64]:
        return exact_step(sym, eps, E, QR, QJ, psi, period)

    def stencils(s: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        return (_central_difference(step, 0.0, s, step_difference),
                _central_second_difference(step, 0.0, s, step_difference))

    (a1, a2), (b1, b2) = stencils(h), stencils(0.5 * h)
    c1, c2 = (b1 - a1) / 15.0, (b2 - a2) / 15.0
    return EpsDerivatives(d1=b1 + c1, d2=b2 + c2, d1_error=np.abs(c1), d2_error=np.abs(c2), h=float(h))
