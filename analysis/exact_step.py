"""The exact one-step map of the asymmetric body, maximum of θ → next maximum, at fixed energy; its ε-derivatives.

The averaged slow map (``rocknroller.analysis.averaging``) expands one step at fixed (E, Q_n, ψ_n) in
ε = (I2 − I1)/I1 about Routh's sphere.  Here the same step is computed without expansion: the state at a maximum
with the given (E, Q_R, Q_J, ψ) is solved for the body with I2 = (1 + ε) I1 (θ̇ = 0, φ = 0; Q_R and Q_J are
linear in (φ̇, ψ̇), E then fixes θ), and the direct ODE (``rocknroller.numerics.integrate.simulate``, heyoka,
tolerance the unit round-off) carries it to the next maximum.  Its ε-derivatives at ε = 0 follow by central
differences (:func:`eps_derivatives`): the first is an independent check of the variational equations of
``rocknroller.analysis.slow_orbit.first_order_step``, the second is the second-order response of the issue
"Second-order ε map".  A member with ε < 0 (I2 < I1) is the body with its principal axes i, j relabelled (j, −i):
moments ((1 + ε) I1, I1) and Euler angle ψ + π/2; Q_R and Q_J are invariant under that rotation about the
symmetry axis and are always computed with the family's I1.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rocknroller.analysis.body import Body
from rocknroller.analysis.invariants import jellett, routh
from rocknroller.analysis.quadrature import wrap_angle
from rocknroller.analysis.reduction import invariants_from_euler, state_from_turning_point, turning_points
from rocknroller.analysis.slow_orbit import (FIRST_ORDER_NAMES, _central_difference, _central_second_difference,
                                             symmetric_data)
from rocknroller.numerics.equations import EulerState

__all__ = ["STEP_NAMES", "family_member", "maximum_state", "exact_step", "step_difference", "EpsDerivatives",
           "eps_derivatives"]

#: What one step returns, in this order: Q_R, Q_J, Θ = 2ψ, t and φ at the next maximum (Θ and φ continued from the
#: start, so that differences between neighbouring steps are small): the components of the first-order responses.
STEP_NAMES = FIRST_ORDER_NAMES
#: The angle components of a step (Θ, φ), whose differences are wrapped.
_ANGLE_COMPONENTS = (2, 4)


def family_member(sym: Body, eps: float) -> tuple[Body, float]:
    """(body, ψ shift) of the member I2 = (1 + ε) I1 (I1, I3, a, g of ``sym``) of the family: for ε < 0 the same
    body with its axes relabelled, moments ((1 + ε) I1, I1), whose Euler angle ψ is the family's plus π/2.

    Raises
    ------
    ValueError
        If the member breaks I2 < I3 or the triangle inequality (naming ε and the moments).
    """
    if not math.isfinite(eps):
        raise ValueError(f"eps must be finite, got eps={eps!r}")
    if eps >= 0.0:
        return sym.with_epsilon(eps), 0.0
    return Body(sym.a, sym.I1 * (1.0 + eps), sym.I1, sym.I3, sym.g), 0.5 * math.pi


def maximum_state(sym: Body, eps: float, E: float, QR: float, QJ: float, psi: float) -> tuple[Body, float, EulerState]:
    """The family member's state at a maximum of θ with energy E, Routh's and Jellett's quantities (Q_R, Q_J)
    and spin angle ψ (θ̇ = 0, φ = 0): (body, ψ shift, state in the body's own Euler angles).

    At θ̇ = 0 the rates with the given (Q_R, Q_J) are Routh's sphere's, φ̇ = V_φ(θ), ψ̇ = V_ψ(θ) (paper eqs.
    phidotCJQR, psidotCJQR: Q_R and Q_J involve only I1, I3 and a, the family's), after which E(θ) = E (paper eq.
    energy, with the member's I2) is solved by Brent's method in a bracket grown about the symmetric body's θ_X.

    Raises
    ------
    ValueError
        If (E, Q_R, Q_J) admit no motion of the symmetric body (from ``turning_points``), or no maximum of the
        member is found near θ_X.
    """
    from scipy.optimize import brentq

    body, shift = family_member(sym, eps)
    theta_X = float(turning_points(E, QR, QJ, sym)[1])
    p = psi + shift

    def rates(th: float) -> tuple[float, float]:
        st = state_from_turning_point(sym, th, QR, QJ)
        return float(st.phi_dot), float(st.psi_dot)

    def excess(th: float) -> float:
        pd, sd = rates(th)
        return float(invariants_from_euler(body, th, 0.0, pd, sd, p)[0]) - E

    room = min(theta_X, math.pi - theta_X)
    d = 1e-3 * room
    while excess(theta_X - d) * excess(theta_X + d) > 0.0:
        d *= 2.0
        if d >= room:
            raise ValueError(f"no maximum of theta with E={E!r}, QR={QR!r}, QJ={QJ!r} for eps={eps!r} near the "
                             f"symmetric theta_X={theta_X!r}")
    th = brentq(excess, theta_X - d, theta_X + d, xtol=1e-300, rtol=8.9e-16, maxiter=200)
    pd, sd = rates(th)
    return body, shift, EulerState(th, 0.0, p, 0.0, pd, sd)


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
