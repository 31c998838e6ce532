"""Closed form of the slow motion near pure rocking: the standard map and its pendulum limit.  It holds the
constants of the closed form for a release from rest at θ0 (:func:`pendulum_constants`, :class:`PendulumConstants`:
T0, the kick C0 and the slopes ∂Δψ/∂Q, ∂Δφ/∂Q as quadratures over the pure-rocking orbit; paper eqs. thetadotsq,
phidotCJQR, psidotCJQR) and the closed-form slow period, extents, Φ and ε_pd (:func:`pendulum_prediction`,
:class:`PendulumPrediction`).

As Q → 0 the first-order slow map of :mod:`rocknroller.analysis.slow.prediction` linearises to

    Q_{n+1} = Q_n + ε C0 sin Θ_n,   Θ_{n+1} = Θ_n + ∇W·Q_{n+1},   W = 2(Δψ − π),

so p = ∇W·Q obeys Chirikov's standard map p' = p + K sin Θ, Θ' = Θ + p' with K = ε κ,
κ = ∇W·C0 = 2 (∂Δψ/∂Q)·C0.  Its constants are one-dimensional quadratures over the pure-rocking
orbit θ̇² = F0(θ) = F(θ; E, 0, 0), written with a signed tilt ϑ ∈ [−θ0, θ0] that passes through
the vertical (ψ fixed, the body-frame orbit is smooth there):

* T0 = ∫ dϑ/√F0, the time between maxima (half the full rocking period);
* C0 = ∫ ∇Q·∂_ε f dϑ/√F0 at ψ = π/4 (the kick; ΔQ(0, Θ) = C0 sin Θ, harmonics c0 = c1 = 0 at Q = 0
  because rocking about either principal axis is an exact solution);
* ∂Δψ/∂Q and ∂Δφ/∂Q = FP ∫ ∂V/∂Q dϑ/√F0 (paper eqs. phidotCJQR, psidotCJQR), the Hadamard finite
  part at ϑ = 0 (∂V/∂Q ~ 1/ϑ²): the ±π jump at the passage is excluded, the regular remainder is
  the slope of the increments modulo π.

For K ≪ 1 the map is the pendulum d²Θ/dn² = K sin Θ.  Stable point Θ* = π for κ > 0 (ψ = π/2:
rocking about the body j axis, moment I2) and Θ* = 0 for κ < 0.  Released from rest at Θ0 = 2ψ0 the
phase librates with amplitude A = |Θ0 − Θ*|: slow period 4 K(m) T0/√|K|, m = sin²(A/2) (complete
elliptic integral), Q = (p/κ) C0 along the kick direction, and φ_n − φ_0 = λ (Θ_n − Θ_0) with
λ = (∂Δφ/∂Q)·C0/κ, which gives Φ = 2|λ||A|·(fraction covered within t_end) ≈ π − 2ψ0 when λ ≈ ½.
The stable rocking loses stability by period doubling at K = 4: ε_pd = 4/|κ|.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.special import ellipj, ellipk

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import azimuth_span, span
from rocknroller.analysis.model.equations import state_from_euler
from rocknroller.analysis.model.invariants import V_phi, V_psi
from rocknroller.analysis.routh.reduction import F
from rocknroller.analysis.slow.family import directional_derivative, rest_energy
from rocknroller.analysis.slow.limits import eps_period_doubling, stable_rocking_psi
from rocknroller.analysis.slow.orbit import _QJ_of, _QR_of, eps_derivative_rhs

__all__ = ["PendulumConstants", "pendulum_constants", "PendulumPrediction", "pendulum_prediction"]

_N_START = 32
_N_MAX = 4096
#: Accept a rule whose change is at the round-off floor if it is below this.
_RTOL_ACCEPT = 1e-7


@dataclass(frozen=True)
class PendulumConstants:
    """Constants of the closed form for (body, θ0).

    Attributes
    ----------
    theta0 : float
    T0 : float
        Time between maxima of pure rocking (half its period).
    C0 : ndarray (2,)
        Kick (Q_R, Q_J) per step per unit ε at Θ = π/2.
    dpsi_dQ, dphi_dQ : ndarray (2,)
        Slopes of Δψ and Δφ (per T0, modulo π) with respect to (Q_R, Q_J) at Q = 0.
    kappa : float
        κ = 2 (∂Δψ/∂Q)·C0; K = ε κ.
    lam : float
        λ = (∂Δφ/∂Q)·C0/κ: dφ/dΘ along the slow orbit.
    n_nodes : int
        Gauss–Legendre nodes used (converged by doubling).
    rel_change : float
        Largest relative change of the constants at the last doubling (their accuracy).
    """

    theta0: float
    T0: float
    C0: NDArray[np.float64]
    dpsi_dQ: NDArray[np.float64]
    dphi_dQ: NDArray[np.float64]
    kappa: float
    lam: float
    n_nodes: int
    rel_change: float

    @property
    def eps_period_doubling(self) -> float:
        """ε at which K = ε κ = 4 (period doubling of rocking about the stable axis)."""
        return eps_period_doubling(self.kappa)

    @property
    def stable_psi(self) -> float:
        """ψ (mod π) of the stable pure rocking: π/2 for κ > 0, 0 for κ < 0."""
        return stable_rocking_psi(self.kappa)

    @property
    def line_slope(self) -> float:
        """dQ_J/dQ_R of the line along which Q moves near pure rocking."""
        return float(self.C0[1] / self.C0[0])


def _integrands(sym: Body, theta0: float, E0: float, u: NDArray[np.float64]) -> NDArray[np.float64]:
    """Integrands (in u, ϑ = θ0 sin u, weight included) of T0, C0_R, C0_J, and h(ϑ) for the slopes."""
    vt = theta0 * np.sin(u)
    jac = theta0 * np.cos(u)
    th = np.abs(vt)
    sqF = np.sqrt(F(th, E0, 0.0, 0.0, sym))
    w = jac / sqF
    psi = 0.25 * math.pi
    kick = np.empty((2, u.size))
    QR_of, QJ_of = _QR_of(sym), _QJ_of(sym)
    for i in range(u.size):
        y = state_from_euler(vt[i], 0.0, psi, -sqF[i], 0.0, 0.0)
        f1 = eps_derivative_rhs(y, sym)
        kick[0, i] = directional_derivative(QR_of, y, f1)
        kick[1, i] = directional_derivative(QJ_of, y, f1)
    return np.vstack([w, kick * w])


def _slope_h(sym: Body, E0: float, vt: NDArray[np.float64]) -> NDArray[np.float64]:
    """h(ϑ) = ϑ² ∂V/∂Q(|ϑ|)/√F0(ϑ) for (ψ: Q_R, Q_J; φ: Q_R, Q_J), shape (4, n); even and smooth."""
    th = np.abs(vt)
    r = vt * vt / np.sqrt(F(th, E0, 0.0, 0.0, sym))
    return np.vstack([V_psi(th, QR=1.0, QJ=0.0, body=sym) * r, V_psi(th, QR=0.0, QJ=1.0, body=sym) * r,
                      V_phi(th, QR=1.0, QJ=0.0, body=sym) * r, V_phi(th, QR=0.0, QJ=1.0, body=sym) * r])


def _quadratures(sym: Body, theta0: float, E0: float, n: int) -> NDArray[np.float64]:
    x, wts = np.polynomial.legendre.leggauss(n)
    u = 0.5 * math.pi * x
    wts = 0.5 * math.pi * wts
    direct = _integrands(sym, theta0, E0, u) @ wts
    vt = theta0 * np.sin(u)
    # h(0) by Richardson extrapolation in ϑ² (h is even): an error Δ in h(0) would add Δ Σ w/ϑ² ∝ n
    d = 1e-4 * theta0
    h1, h2, h4 = (_slope_h(sym, E0, np.array([m * d])) for m in (1.0, 2.0, 4.0))
    h0 = (64.0 * h1 - 20.0 * h2 + h4) / 45.0
    h = _slope_h(sym, E0, vt)
    fp = ((h - h0) / (vt * vt) * (theta0 * np.cos(u))) @ wts - 2.0 * h0[:, 0] / theta0
    return np.concatenate([direct, fp])


def pendulum_constants(body: Body, theta0: float, *, rtol: float = 1e-10) -> PendulumConstants:
    """T0, C0, ∂Δψ/∂Q, ∂Δφ/∂Q, κ and λ for the body (its symmetric part) released at θ0.

    Gauss–Legendre in u (ϑ = θ0 sin u removes the inverse square roots at ±θ0); the node count
    is doubled from 32 until all constants change by less than ``rtol`` relative.  Round-off in
    F0 = θ̇² next to the turning point (E − U(ϑ) cancels) grows like n² and reaches ~1e-11 at
    n = 128, which sets the attainable ``rtol`` (the closed form itself is accurate to O(ε)).

    Raises
    ------
    ValueError
        θ0 outside (0, π).
    """
    sym = body.symmetric()
    E0 = rest_energy(sym, theta0)  # validates θ0
    theta0 = float(theta0)
    n = _N_START
    prev = _quadratures(sym, theta0, E0, n)
    last_change = math.inf
    while True:
        cur = _quadratures(sym, theta0, E0, 2 * n)
        change = float(np.max(np.abs(cur - prev) / np.abs(cur)))
        if change <= rtol:
            n *= 2
            break
        if change > last_change:  # round-off regime: the previous rule was the best
            cur, change = prev, last_change
            if change > _RTOL_ACCEPT:
                raise RuntimeError(f"pendulum constants reached only {change:.1e} relative accuracy")
            break
        n *= 2
        if n >= _N_MAX:
            raise RuntimeError(f"pendulum constants did not converge with {n} nodes")
        prev, last_change = cur, change
    T0, C0 = float(cur[0]), cur[1:3].copy()
    dpsi, dphi = cur[3:5].copy(), cur[5:7].copy()
    kappa = float(2.0 * dpsi @ C0)
    return PendulumConstants(theta0=theta0, T0=T0, C0=C0, dpsi_dQ=dpsi, dphi_dQ=dphi, kappa=kappa,
                             lam=float(dphi @ C0) / kappa, n_nodes=n, rel_change=change)


@dataclass(frozen=True)
class PendulumPrediction:
    """Closed-form (pendulum) prediction of the slow motion released from rest at (θ0, ψ0).

    Extents and Φ are taken over the maxima n = 1, 2, ... with n T0 ≤ t_end, as for the ODE.
    """

    eps: float
    psi0: float
    t_end: float
    K: float
    kappa: float
    eps_period_doubling: float
    slow_period: float
    QR_extent: float
    QJ_extent: float
    Phi: float
    line_slope: float


def pendulum_prediction(body: Body, theta0: float, psi0: float, t_end: float = 1000.0, *,
                        constants: PendulumConstants | None = None) -> PendulumPrediction:
    """Closed-form slow period, extents, Φ and ε_pd from the pendulum limit of the standard map.

    Raises
    ------
    ValueError
        If t_end is not a finite number > 0, ψ0 is not finite, or ψ0 is the unstable equilibrium
        (no libration: Θ0 = Θ* + π).  (ε ≥ 0 is guaranteed by Body.)
    """
    eps = body.epsilon
    t_end, psi0 = float(t_end), float(psi0)
    if not math.isfinite(t_end) or t_end <= 0.0:
        raise ValueError(f"t_end must be a finite number > 0, got t_end={t_end!r}")
    if not math.isfinite(psi0):
        raise ValueError(f"psi0 must be finite, got psi0={psi0!r}")
    c = constants if constants is not None else pendulum_constants(body, theta0)
    K = eps * c.kappa
    Theta_star = 2.0 * c.stable_psi
    A = float(math.remainder(2.0 * psi0 - Theta_star, 2.0 * math.pi))
    k = math.sin(abs(A) / 2.0)
    m = k * k
    if m >= 1.0:
        raise ValueError(f"psi0={psi0!r} starts on the unstable equilibrium (separatrix): no slow libration")
    rootK = math.sqrt(abs(K))
    if rootK == 0.0:
        return PendulumPrediction(eps=eps, psi0=psi0, t_end=t_end, K=K, kappa=c.kappa,
                                  eps_period_doubling=c.eps_period_doubling, slow_period=math.inf,
                                  QR_extent=0.0, QJ_extent=0.0, Phi=0.0, line_slope=c.line_slope)
    period = 4.0 * float(ellipk(m)) / rootK * c.T0
    n = np.arange(1, int(math.floor(t_end / c.T0)) + 1, dtype=float)
    sn, cn, dn, _ = ellipj(rootK * n, m)
    sgn = 1.0 if A >= 0 else -1.0
    half = np.arcsin(np.clip(sgn * k * cn / dn, -1.0, 1.0))   # sin(φp/2) = k cd(√K n)
    phase = 2.0 * half                                          # φp = Θ − Θ*
    p = -sgn * 2.0 * k * (1.0 - m) * rootK * (sn / dn) / (dn * np.cos(half))
    QR, QJ = p / c.kappa * c.C0[0], p / c.kappa * c.C0[1]

    Phi = azimuth_span(c.lam * (phase - A)) if n.size else 0.0
    return PendulumPrediction(eps=eps, psi0=psi0, t_end=t_end, K=K, kappa=c.kappa,
                              eps_period_doubling=c.eps_period_doubling, slow_period=period,
                              QR_extent=span(QR), QJ_extent=span(QJ), Phi=Phi, line_slope=c.line_slope)
