"""The family of bodies I2 = (1 + ε) I1 about Routh's sphere, and where a slow orbit starts on it.  It holds a member
of the family (:func:`family_member`; ε < 0 by relabelling the axes), the member's state at a maximum of θ with
given (E, Q_R, Q_J, ψ) (:func:`maximum_state`; paper eqs. phidotCJQR, psidotCJQR, energy), the energy of a release
from rest (:func:`rest_energy`; paper eq. energy), the first maximum of θ of any start, by the direct ODE
(:func:`first_maximum`), and the fourth-order central differences with which the family is differentiated (in ε,
and along a direction in state space: :func:`directional_derivative`).

The slow map is an expansion in ε along this family at fixed (E, Q_R, Q_J, ψ) at a maximum of θ.  The exact step
(:mod:`rocknroller.analysis.slow.map.exact_step`) and the second-order variational orbit
(:func:`rocknroller.analysis.slow.map.orbit.second_order_step`) start from :func:`maximum_state`; a start with velocity
enters the map at its :func:`first_maximum` (:func:`rocknroller.analysis.slow.prediction.predict_slow_motion`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.model.invariants import energy, jellett, routh
from rocknroller.analysis.routh.quadrature import precession
from rocknroller.analysis.routh.quadrature_mp import precession_mp
from rocknroller.analysis.routh.reduction import (NoMotionError, SteadyRollingError, effective_potential,
                                                  invariants_from_euler, require_open_tilt, state_from_turning_point)
from rocknroller.analysis.routh.rocking import small_amplitude_frequency
from rocknroller.analysis.routh.turning_points import turning_points

__all__ = ["rest_energy", "directional_derivative", "FirstMaximum", "first_maximum", "family_member", "maximum_state"]



def rest_energy(body: Body, theta0: float) -> float:
    """E of the body released from rest at θ0: U(θ0; 0, 0) = g a (1 − cos θ0) (paper eq. energy)."""
    theta0 = float(require_open_tilt(float(theta0)))
    return float(effective_potential(theta0, 0.0, 0.0, body.symmetric()))


def directional_derivative(fun: Callable[[NDArray[np.float64]], float | NDArray[np.float64]], y: ArrayLike,
                           v: ArrayLike, *, angle: bool = False, h: float = 1e-4) -> float | NDArray[np.float64]:
    """D fun(y)[v] by the fourth-order central difference along v/|v| (step h), times |v|.

    Exact to round-off for quadratic functions (Q_J, dγ3/dt); truncation ~h⁴ otherwise.
    ``angle=True`` wraps the differences to (−π, π] (for ψ and φ from ``atan2``).  y and v of shape (11, N)
    give the N derivatives (fun then maps (11, N) to N values).
    """
    y, v = np.asarray(y, float), np.asarray(v, float)
    norm = np.linalg.norm(v, axis=0)  # columns of (11, N) arrays are N separate points and directions
    e = v / np.where(norm == 0.0, 1.0, norm)
    out = norm * _central_difference(lambda s: fun(y + s * e), 0.0, h, wrap_angle if angle else np.asarray)
    return float(out) if np.ndim(out) == 0 else out


def _central_difference(fun: Callable[[Any], Any], x: float | NDArray[np.float64], h: float | NDArray[np.float64],
                        wrap: Callable[[Any], Any] = lambda d: d) -> Any:
    """f'(x) ≈ [8 (f(x + h) − f(x − h)) − (f(x + 2h) − f(x − 2h))]/(12 h), fourth order; ``wrap`` is applied
    to each difference (for angles).  Works on scalar or array values of f."""
    d1 = wrap(fun(x + h) - fun(x - h))
    d2 = wrap(fun(x + 2 * h) - fun(x - 2 * h))
    return (8.0 * d1 - d2) / (12.0 * h)


def _central_second_difference(fun: Callable[[float], Any], x: float, h: float,
                               wrap: Callable[[Any], Any] = lambda d: d) -> Any:
    """f''(x) ≈ [16 (d(h) + d(−h)) − (d(2h) + d(−2h))]/(12 h²), d(s) = f(x + s) − f(x), fourth order; ``wrap``
    is applied to each d (for angles).  Works on scalar or array values of f."""
    f0 = fun(x)
    d1 = wrap(fun(x + h) - f0) + wrap(fun(x - h) - f0)
    d2 = wrap(fun(x + 2 * h) - f0) + wrap(fun(x - 2 * h) - f0)
    return (16.0 * d1 - d2) / (12.0 * h * h)


def _second_directional(fun: Callable[[NDArray[np.float64]], float | NDArray[np.float64]], y: NDArray[np.float64],
                        v: NDArray[np.float64], *, angle: bool = False, h: float = 1e-3) -> float:
    """D²fun(y)[v, v] by :func:`_central_second_difference` along v/|v| (step h), times |v|²; exact to round-off for
    quadratic functions."""
    norm = float(np.linalg.norm(v))
    if norm == 0.0:
        return 0.0
    e = v / norm
    wrap = (lambda x: float(wrap_angle(x))) if angle else float
    return norm * norm * _central_second_difference(lambda s: fun(y + s * e), 0.0, h, wrap)


# ----------------------------------------------------------------------------- any start → its first maximum
@dataclass(frozen=True)
class FirstMaximum:
    """The state of a run at its first maximum of θ: where the slow map of a start with velocity begins.

    Attributes
    ----------
    t : float
        Time of the maximum (0 if the start is itself a maximum, as a release from rest is).
    E : float
        The body's energy (exact for the asymmetric body too; paper eq. energy).
    theta, QR, QJ, psi, phi : float
        θ_X, Routh's and Jellett's quantities, and the Euler angles ψ, φ there.
    """

    t: float
    E: float
    theta: float
    QR: float
    QJ: float
    psi: float
    phi: float


#: Longest stretch (in periods of the symmetric rocking at the start's energy) searched for the first maximum.
_FIRST_MAXIMUM_PERIODS = 4.0


def first_maximum(body: Body, initial: EulerState) -> FirstMaximum:
    """Carry ``initial`` to its first maximum of θ by a short direct integration of the asymmetric body.

    The direct ODE (heyoka, tolerance the unit round-off; ``rocknroller.numerics.integrate.simulate``) adds no
    error of the averaging's kind: the map then starts from the true maximum.  A start with θ̇ = 0 at which θ
    is about to decrease (a release from rest at 0 < θ0 < π) is itself the first maximum (t = 0).

    Raises
    ------
    ValueError
        A start that ``simulate`` refuses (naming the parameter), or one whose θ has no maximum within
        ``_FIRST_MAXIMUM_PERIODS`` times the symmetric body's period T_θ at its (E, Q) (steady rolling).
    """
    from rocknroller.numerics.events import start_turning_point
    from rocknroller.numerics.integrate import simulate

    y0 = initial.to_body_state()
    E = float(energy(body, y0[0:3], y0[3:6]))
    if not E > 0.0:
        raise ValueError(f"the start has no motion to average over: its energy is E={E!r} in double precision (at rest "
                         f"at the bottom, or theta0={initial.theta!r} and its rates too small to register)")
    QR0, QJ0 = float(routh(body, y0[0:3], y0[3:6])), float(jellett(body, y0[0:3], y0[3:6]))
    # θ̇ = 0 to rounding and θ about to fall: the start is a maximum (the direct ODE's own criterion, so that the
    # trajectory and the prediction start from the same sample)
    root = start_turning_point(body, y0)
    if root is not None and root.kind > 0:
        return FirstMaximum(t=0.0, E=E, theta=float(initial.theta), QR=QR0, QJ=QJ0, psi=float(initial.psi),
                            phi=float(initial.phi))
    # How far to look is set by the period of θ, whose quadrature costs ~5x the short run itself (measured:
    # 25 ms of a 30 ms prediction): look first over as many small-amplitude periods (closed form, the slower axis)
    # and compute the period only where that finds no maximum.
    look = _FIRST_MAXIMUM_PERIODS * 2.0 * math.pi / small_amplitude_frequency(body, max(body.I1, body.I2))
    run = simulate(body, initial, look, samples=False)
    if len(run.maxima) == 0:
        sym = body.symmetric()
        try:
            period = float(precession(E, QR0, QJ0, sym).T_theta)
        except (NoMotionError, SteadyRollingError) as exc:
            raise ValueError(f"the start has no oscillation of theta to average over: {exc}") from None
        except ValueError:  # oscillating, but too near steady rolling for the double quadrature: its mpmath reference
            period = float(precession_mp(E, QR0, QJ0, sym, dps=30).T_theta)
        if _FIRST_MAXIMUM_PERIODS * period > look:
            run = simulate(body, initial, _FIRST_MAXIMUM_PERIODS * period, samples=False)
        if len(run.maxima) == 0:
            raise ValueError(f"theta has no maximum within {_FIRST_MAXIMUM_PERIODS:g} rocking periods "
                             f"({_FIRST_MAXIMUM_PERIODS * period:.4g} time units) of this start: nothing to average")
    m = run.maxima
    return FirstMaximum(t=float(m.t[0]), E=E, theta=float(m.theta[0]), QR=float(m.QR[0]), QJ=float(m.QJ[0]),
                        psi=float(m.psi[0]), phi=float(m.phi[0]))


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


def maximum_state(sym: Body, eps: float, E: float, QR: float, QJ: float, psi: float, *,
                  theta_X: float | None = None) -> tuple[Body, float, EulerState]:
    """The family member's state at a maximum of θ with energy E, Routh's and Jellett's quantities (Q_R, Q_J)
    and spin angle ψ (θ̇ = 0, φ = 0): (body, ψ shift, state in the body's own Euler angles).

    At θ̇ = 0 the rates with the given (Q_R, Q_J) are Routh's sphere's, φ̇ = V_φ(θ), ψ̇ = V_ψ(θ) (paper eqs.
    phidotCJQR, psidotCJQR: Q_R and Q_J involve only I1, I3 and a, the family's), after which E(θ) = E (paper eq.
    energy, with the member's I2) is solved by Brent's method in a bracket grown about the symmetric body's θ_X
    (``theta_X`` if the caller has it, the root of its :func:`turning_points` with these (E, Q_R, Q_J); else solved
    here).

    Raises
    ------
    ValueError
        If (E, Q_R, Q_J) admit no motion of the symmetric body (from ``turning_points``), or no maximum of the
        member is found near θ_X.
    """
    from scipy.optimize import brentq

    body, shift = family_member(sym, eps)
    theta_X = float(turning_points(E, QR, QJ, sym)[1] if theta_X is None else theta_X)
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
