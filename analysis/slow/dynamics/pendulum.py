"""Closed forms of the slow motion near pure rocking: the standard map and its pendulum limit at large amplitude, the
linear beat at small amplitude.  It holds the constants of the pendulum for a release from rest at θ0
(:func:`pendulum_constants`, :class:`PendulumConstants`: T0, the kick C0 and the slopes ∂Δψ/∂Q, ∂Δφ/∂Q as quadratures
over the pure-rocking orbit; paper eqs. thetadotsq, phidotCJQR, psidotCJQR), the pendulum's slow period, extents, Φ
and ε_pd (:func:`pendulum_prediction`, :class:`PendulumPrediction`), the beat's slow period
(:func:`beat_prediction`, :class:`BeatPrediction`), and the parameter R² that tells their regimes apart
(:func:`regime_ratio`; :class:`ClosedFormRegimeWarning` when a form is used outside its own).

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

Regimes.  As θ0 → 0 the body is a linear oscillator with two rocking modes, about i and j, of frequencies
ν_k = √(g a/(I_k + (1 − a)²)) (:func:`rocknroller.analysis.routh.rocking.small_amplitude_frequency`); released from
rest at ψ0 their phases drift apart at Δν = |ν1 − ν2| ∝ ε, and Θ = 2ψ at the maxima (the axis of the rocking
ellipse) oscillates with the beat period 2π/Δν, for every ψ0 and independent of θ0 (:func:`beat_prediction`).  The
pendulum's period 4 K(m) T0/√|K| instead grows like 1/θ0 (κ ∝ θ0²).  Both are limits of the averaged two-mode
oscillator dS/dt = ∇H × S, S the Stokes vector of the two modes (S1 their energy difference, S3 ∝ the angular
momentum about the vertical), H = Δν S1 + (c/2) S3² with c S0 Δν = K/T0²; its slow frequency about the stable axis
is √(Δν² + K/T0²).  Hence R² = |K|/(T0 Δν)² (:func:`regime_ratio`): the pendulum holds for R² ≫ 1, its slow period
off the two-mode one's by at most √(1 + 1/R²) − 1 over all ψ0 (from R² = 2 up; more below), the beat for R² ≪ 1, by
at most 1/√(1 − R²) − 1 (the two-mode frequency about the axis ψ = 0 is Δν √(1 − R²)); the crossover is R² = 1,
θ0 ≈ 0.024π √(ε/0.01) for the paper body (R² ∝ θ0²/ε).  Against the direct ODE (ψ0 = 0.5, ε = 1e-2;
docs/averaging.md, "Closed forms") the pendulum is off by +0.7 % at 0.1π (R² = 19), +2.4 % at
0.05π, +50 % at 0.02π (R² = 0.69), ×3.2 at 0.01π, the beat by −11 % at 0.02π, −4.3 % at 0.01π, −1.1 % at 0.005π
(R² = 0.043), and their errors cross at R² = 1.9, 1.4 and 1.1 for ψ0 = 0.5, π/4 and 1.2 (at ε = 1e-2 and 1e-3
alike).  Each form warns (:class:`ClosedFormRegimeWarning`) where its bound exceeds ``REGIME_TOLERANCE``, naming
the crossover.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rocknroller.analysis.model.body import Body, float_or_nan
from rocknroller.analysis.model.diagnostics import azimuth_span, span
from rocknroller.analysis.model.equations import state_from_euler
from rocknroller.analysis.model.invariants import V_phi, V_psi
from rocknroller.analysis.routh.reduction import F
from rocknroller.analysis.routh.rocking import small_amplitude_frequency
from rocknroller.analysis.slow.dynamics.elliptic_functions import ellipj, ellipk
from rocknroller.analysis.slow.map.family import directional_derivative, rest_energy
from rocknroller.analysis.slow.map.limits import AveragingValidityWarning, eps_period_doubling, stable_rocking_psi
from rocknroller.analysis.slow.map.orbit import _QJ_of, _QR_of, eps_derivative_rhs

__all__ = ["PENDULUM_THETA0_RANGE", "REGIME_TOLERANCE", "ClosedFormRegimeWarning", "PendulumConstants",
           "pendulum_constants", "PendulumPrediction", "pendulum_prediction", "regime_ratio", "pendulum_regime_error", "BeatPrediction",
           "beat_prediction"]

_N_START = 32
_N_MAX = 4096
#: Accept a rule whose change is at the round-off floor if it is below this.
_RTOL_ACCEPT = 1e-7
#: Release angles for which the quadratures of :func:`pendulum_constants` converge (paper body, measured at 40
#: angles spaced geometrically from 3e-4π to 0.05π and 21 from 0.99π to 0.9999π).  At small θ0 the finite-part
#: slopes carry a relative round-off that grows like 1/θ0² (F0 = E − U(ϑ) cancels to O(θ0²)): below ≈ 0.001π it
#: exceeds ``_RTOL_ACCEPT`` and the rule fails (at 7 of the 10 angles there; 8e-1 at 1e-6 rad, and at 1e-108 rad
#: 8 minutes of doublings to 4096 nodes before failing); from 0.0028π up the last change was ≤ 1.5e-8, 7× below the
#: acceptance (4e-10 at 0.005π).  Towards the upright position the rule needs 256 nodes from 0.998π and its last
#: change reaches 1e-7 at 0.9998π; 0.999π (≤ 3e-8) is also the averaged map's limit (``THETA0_RANGE``).
PENDULUM_THETA0_RANGE = (0.005 * math.pi, 0.999 * math.pi)
#: Largest bound on a closed form's error from its regime (module docstring, "Regimes") accepted without a
#: ClosedFormRegimeWarning: the pendulum for R² ≥ 1/((1 + tol)² − 1) = 9.76, the beat for R² ≤ 1 − 1/(1 + tol)²
#: = 0.093 (the closed forms' own error is O(ε) besides: 0.4–0.7 % at ε = 1e-2).
REGIME_TOLERANCE = 0.05
#: Least R² from which √(1 + 1/R²) − 1 bounds the pendulum's regime error over all ψ0 (two-mode oscillator, ψ0 from
#: 0.02 to π/2: at R² = 2 the largest error is 0.2247, the bound's; at 1.2, 0.375 against 0.354).
_PENDULUM_BOUND_FROM = 2.0


class ClosedFormRegimeWarning(AveragingValidityWarning):
    """A closed form of the slow motion is used outside its regime (module docstring, "Regimes"): the pendulum at
    small amplitude or the linear beat at large, where its slow period may be off by more than
    ``REGIME_TOLERANCE``."""


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

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> c = rr.pendulum_constants(rr.Body.paper(), 0.95 * math.pi)
    >>> print(c.rel_change < 1e-10, c.C0.shape)
    True (2,)
    >>> print(f"eps at K = 4: {4 / c.kappa:.6f}")
    eps at K = 4: 0.009385
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
        θ0 outside ``PENDULUM_THETA0_RANGE`` = [0.005π, 0.999π], before any quadrature: below it the rule does not
        converge (the small-amplitude end is the linear beat, :func:`beat_prediction`), above it the rocking nears
        the upright equilibrium.
    RuntimeError
        The rule does not converge inside that range (possible for bodies other than the paper's).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> c = rr.pendulum_constants(rr.Body.paper(), 0.95 * math.pi)
    >>> print(f"T0 = {c.T0:.6f}, kappa = {c.kappa:.4f}, lambda = {c.lam:.6f}")
    T0 = 13.260653, kappa = 426.2263, lambda = 0.486224
    """
    body.require_gravity("the pendulum constants of the slow motion")
    theta0 = _check_theta0(theta0)
    sym = body.symmetric()
    E0 = rest_energy(sym, theta0)
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


def _check_theta0(theta0: float) -> float:
    """θ0 as a float, or a ValueError naming it unless it lies in ``PENDULUM_THETA0_RANGE``."""
    lo, hi = PENDULUM_THETA0_RANGE
    value = float_or_nan(theta0)
    if not lo <= value <= hi:  # also NaN
        raise ValueError(
            f"theta0 must lie in [{lo / math.pi:g}pi, {hi / math.pi:g}pi] = [{lo:.6g}, {hi:.6g}] for the pendulum "
            f"constants, got theta0={theta0!r}: below {lo / math.pi:g}pi their quadratures do not converge (round-off "
            f"grows like 1/theta0^2), and the slow motion there is near the linear beat (beat_prediction); above "
            f"{hi / math.pi:g}pi the rocking nears the upright equilibrium")
    return value


def regime_ratio(body: Body, theta0: float, constants: PendulumConstants | None = None) -> float:
    """R² = |ε κ|/(T0 Δν)², Δν = |ν1 − ν2|: the squared ratio of the pendulum's small-libration frequency √|K|/T0 to
    the beat frequency (module docstring, "Regimes"); R² = 1 is the crossover between their regimes.

    κ and T0 from ``constants`` (those of θ0, computed if not given); below ``PENDULUM_THETA0_RANGE``, where their
    quadratures do not converge, from its lower end with κ scaled by (θ0/θ0_min)² (κ ∝ θ0² as θ0 → 0: κ/θ0² changes
    by 7e-4 from 0.005π to 0.01π, T0 by 5e-5).  NaN for ε = 0 (no slow motion: neither form applies).
    """
    dnu = abs(small_amplitude_frequency(body, body.I1) - small_amplitude_frequency(body, body.I2))
    if body.epsilon == 0.0 or dnu == 0.0:
        return math.nan
    if constants is None:
        constants = pendulum_constants(body, max(float(theta0), PENDULUM_THETA0_RANGE[0]))
    scale = min(1.0, float(theta0) / constants.theta0) ** 2
    return abs(body.epsilon * constants.kappa) * scale / (constants.T0 * dnu) ** 2


def pendulum_regime_error(R2: float) -> float:
    """The bound √(1 + 1/R²) − 1 on the pendulum's slow-period error from its regime (module docstring, "Regimes"),
    at R² = ``regime_ratio`` (0 for ε = 0, R² NaN: pure rocking, where there is no libration to be off).

    Examples
    --------
    >>> from rocknroller.analysis.slow.dynamics.pendulum import pendulum_regime_error
    >>> print(f"{pendulum_regime_error(2.0):.4f} {pendulum_regime_error(9.76):.4f}")
    0.2247 0.0500
    """
    if math.isnan(R2):
        return 0.0
    return math.inf if R2 <= 0.0 else math.sqrt(1.0 + 1.0 / R2) - 1.0


def _regime_warning(form: str, R2: float, off: str, holds: str, theta0: float, body: Body) -> None:
    """ClosedFormRegimeWarning: ``form`` is used at R², where its slow period may be ``off``; it ``holds`` elsewhere."""
    import warnings

    dnu = abs(small_amplitude_frequency(body, body.I1) - small_amplitude_frequency(body, body.I2))
    closer = "the pendulum (pendulum_prediction)" if R2 > 1.0 else (
        f"the linear beat (beat_prediction: slow period 2 pi/|nu1 - nu2| = {2.0 * math.pi / dnu:.6g})")
    warnings.warn(
        f"the {form} closed form is used outside its regime: R^2 = |K|/(T0 |nu1 - nu2|)^2 = {R2:.3g} at "
        f"theta0={theta0:.6g} = {theta0 / math.pi:.4g}pi, eps={body.epsilon:.3g}, where its slow period may be off "
        f"{off}; it holds to {REGIME_TOLERANCE:.0%} for {holds}.  The crossover between the pendulum (large "
        f"amplitude) and the linear beat (small), R^2 = 1, is at theta0 ~ {theta0 / math.sqrt(R2) / math.pi:.3g}pi "
        f"for this body and eps; {closer} is the closer form here, and the averaged map (predict_slow_motion) holds "
        "on both sides", ClosedFormRegimeWarning, stacklevel=3)


@dataclass(frozen=True)
class PendulumPrediction:
    """Closed-form (pendulum) prediction of the slow motion released from rest at (θ0, ψ0).

    Extents and Φ are taken over the maxima n = 1, 2, ... with n T0 ≤ t_end, as for the ODE.  ``regime_ratio``: R²
    (:func:`regime_ratio`; the pendulum's regime is R² ≫ 1, NaN for ε = 0).
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
    regime_ratio: float = math.nan


def pendulum_prediction(body: Body, theta0: float, psi0: float, t_end: float = 1000.0, *,
                        constants: PendulumConstants | None = None) -> PendulumPrediction:
    """Closed-form slow period, extents, Φ and ε_pd from the pendulum limit of the standard map: the large-amplitude
    end of the slow motion near pure rocking, R² ≫ 1 (module docstring, "Regimes").

    Raises
    ------
    ValueError
        If θ0 is outside ``PENDULUM_THETA0_RANGE`` (without ``constants``), t_end is not a finite number > 0, ψ0 is
        not finite, or ψ0 is the unstable equilibrium (no libration: Θ0 = Θ* + π).  (ε ≥ 0 is guaranteed by Body.)

    Warns
    -----
    ClosedFormRegimeWarning
        R² < 9.76, where the slow period may be off by more than ``REGIME_TOLERANCE`` (by up to √(1 + 1/R²) − 1):
        towards the linear beat (:func:`beat_prediction`), naming the crossover R² = 1.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> p = rr.pendulum_prediction(rr.Body.paper(epsilon=1e-3), 0.95 * math.pi, math.pi / 4)
    >>> print(f"K = {p.K:.4f}, slow period = {p.slow_period:.3f}, Phi = {p.Phi:.4f}")
    K = 0.4262, slow period = 150.637, Phi = 1.5267
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
    R2 = regime_ratio(body, c.theta0, c)
    bound = pendulum_regime_error(R2)
    if bound > REGIME_TOLERANCE:
        off = (f"by up to {bound:.0%}" if R2 >= _PENDULUM_BOUND_FROM else
               f"by {bound:.0%} or more (several times as theta0 falls: its period grows like 1/theta0)")
        _regime_warning("pendulum", R2, off, f"R^2 >= {1.0 / ((1.0 + REGIME_TOLERANCE) ** 2 - 1.0):.3g}", c.theta0,
                        body)
    period = 4.0 * float(ellipk(m)) / rootK * c.T0
    n = np.arange(1, int(math.floor(t_end / c.T0)) + 1, dtype=float)
    sn, cn, dn = ellipj(rootK * n, m)
    sgn = 1.0 if A >= 0 else -1.0
    half = np.arcsin(np.clip(sgn * k * cn / dn, -1.0, 1.0))   # sin(φp/2) = k cd(√K n)
    phase = 2.0 * half                                          # φp = Θ − Θ*
    p = -sgn * 2.0 * k * (1.0 - m) * rootK * (sn / dn) / (dn * np.cos(half))
    QR, QJ = p / c.kappa * c.C0[0], p / c.kappa * c.C0[1]

    Phi = azimuth_span(c.lam * (phase - A)) if n.size else 0.0
    return PendulumPrediction(eps=eps, psi0=psi0, t_end=t_end, K=K, kappa=c.kappa,
                              eps_period_doubling=c.eps_period_doubling, slow_period=period,
                              QR_extent=span(QR), QJ_extent=span(QJ), Phi=Phi, line_slope=c.line_slope,
                              regime_ratio=R2)


@dataclass(frozen=True)
class BeatPrediction:
    """Closed-form (linear beat) slow period of a release from rest at θ0 (any ψ0): the small-amplitude end.

    Attributes
    ----------
    eps, theta0 : inputs.
    nu1, nu2 : the small-amplitude rocking frequencies about i and j, √(g a/(I_k + (1 − a)²)).
    slow_period : 2π/|ν1 − ν2| (inf for ε = 0: no beat).
    regime_ratio : R² (:func:`regime_ratio`; the beat's regime is R² ≪ 1, NaN for ε = 0).
    """

    eps: float
    theta0: float
    nu1: float
    nu2: float
    slow_period: float
    regime_ratio: float


def beat_prediction(body: Body, theta0: float) -> BeatPrediction:
    """The slow period of the linear anisotropic oscillator that the body is at small amplitude: Θ = 2ψ at the maxima
    oscillates with the beat period 2π/|ν1 − ν2| of its two rocking modes, whatever ψ0 (module docstring,
    "Regimes"); its regime is R² ≪ 1, θ0 well below θ0 ~ 0.024π √(ε/0.01) for the paper body.

    Raises
    ------
    ValueError
        θ0 outside (0, 0.999π] (the largest release angle of the averaged map's tables).

    Warns
    -----
    ClosedFormRegimeWarning
        R² > 0.093, where the slow period may be off by more than ``REGIME_TOLERANCE`` (by up to 1/√(1 − R²) − 1,
        without bound from the crossover R² = 1 up): towards the pendulum (:func:`pendulum_prediction`).
    """
    hi = PENDULUM_THETA0_RANGE[1]
    if not 0.0 < float_or_nan(theta0) <= hi:  # also NaN: not a number, or an int beyond the floats
        raise ValueError(f"theta0 must lie in (0, {hi / math.pi:g}pi] for the beat closed form, got theta0={theta0!r}")
    theta0 = float(theta0)
    nu1, nu2 = small_amplitude_frequency(body, body.I1), small_amplitude_frequency(body, body.I2)
    R2 = regime_ratio(body, theta0)
    if R2 > 0.0:  # NaN for ε = 0
        bound = 1.0 / math.sqrt(1.0 - R2) - 1.0 if R2 < 1.0 else math.inf
        if bound > REGIME_TOLERANCE:
            off = f"by up to {bound:.0%}" if R2 < 1.0 else "without bound (above R^2 = 1 its axis psi = 0 is unstable)"
            _regime_warning("linear beat", R2, off, f"R^2 <= {1.0 - 1.0 / (1.0 + REGIME_TOLERANCE) ** 2:.3g}", theta0,
                            body)
    period = 2.0 * math.pi / abs(nu1 - nu2) if nu1 != nu2 else math.inf
    return BeatPrediction(eps=body.epsilon, theta0=theta0, nu1=nu1, nu2=nu2, slow_period=period, regime_ratio=R2)
