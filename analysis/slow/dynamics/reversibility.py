"""Reversibility and the invariant measure of the exact one-step map: is the rock'n'roller's chaos conservative?

The map P (:class:`rocknroller.analysis.slow.map.maps.ExactMap`, θ-maximum to θ-maximum in x = (Q_R, Q_J, Θ)) is
reversible, R P R = P⁻¹ with R(Q, Θ) = (−Q, Θ), and so is R S (Θ → −Θ); it does not keep volume pointwise.  A
continuous invariant density ρ on the section makes det DP(x) = ρ(x)/ρ(P x): log|det DP| a coboundary.  Hence:

* around a periodic orbit x₀ … x_{p−1}: Σ log|det DP(x_k)| = 0 (:func:`log_det_product`).  Orbits symmetric under a
  reversor G (G O = O) satisfy it whatever the dynamics (det DP(x) · det DP(G P x) = 1, :func:`reversor_defect`):
  they are the control; asymmetric ones are the test (:func:`find_cycle` finds orbits and classifies them);
* along an orbit: the mean of log|det DP|, the sum of the Lyapunov exponents (:func:`lyapunov_sum`, also by QR),
  forward and along the orbit of P⁻¹: → 0 like 1/n with a density; in mixed dynamics (Gonchenko–Gonchenko–Kazakov)
  negative forward (the attractor) and positive backward (the repeller);
* along long direct runs: the flow's own volume change (:mod:`rocknroller.analysis.slow.dynamics.flow_volume`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Mapping, Protocol, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.slow.map.maps import EVALUATION_ULPS, reverse

__all__ = ["EXACT_JACOBIAN_RTOL", "CYCLE_TOL", "SYMMETRY_TOL", "REVERSORS", "TangentMap", "reflected_reverse",
           "CycleError", "Cycle", "find_cycle", "DetProduct", "log_det_product", "reversor_defect", "LyapunovSum",
           "lyapunov_sum"]

_U = float(np.finfo(float).eps)
#: Relative accuracy η of ``ExactMap.jacobian`` (computed DF = (1 + E) DF, ‖E‖ ≤ η, so |δ log|det DF|| ≤ 3η).
#: The flow's part: heyoka at tolerance u per Taylor step, N ≤ 40 steps a rock (measured ≤ 34 at 0.9π and 0.95π,
#: ε ≤ 0.14), each local error carried by the rock's 6 × 6 flow Jacobian of condition A ≤ 150 (measured ≤ 130):
#: N A u = 1.3e-12.  The start's, the event's and the outputs' gradients (three factors) are fourth-order differences
#: of polynomials of the state at step h = 1e-4: exact but for round-off, (1 + 8 + 8 + 1)/12 u/h = 3.3e-12 each of
#: the terms' size (|γ| = 1, |ω| ~ 1: the gradients' size), 1.0e-11 together.  η = 1.13e-11; the reversibility
#: identity measures |δ log det| ≤ 2.7e-12 (16 points at 0.9π, ε = 0.03), within 3η = 3.4e-11.
EXACT_JACOBIAN_RTOL = 40 * 150 * _U + 3 * 1.5 * _U / 1e-4
#: Residual ‖P(x_k) − x_{k+1}‖∞ at which :func:`find_cycle` stops: each component is one evaluation of the map,
#: ``EVALUATION_ULPS`` ulp of 4π, against a stored point (one rounding more): twice that.
CYCLE_TOL = 2.0 * EVALUATION_ULPS * _U * 4.0 * math.pi
#: A cycle is symmetric under G when G maps its points onto its points within this (∞-norm): cycles solved to
#: ``CYCLE_TOL`` lie within ~1e-10 of their images when symmetric (measured ≤ 3e-11, periods 1–8, ε = 0.01–0.14), and
#: ≥ 1e-3 from their images under the other reversor when symmetric under one only: 1e-6 is far from both.
SYMMETRY_TOL = 1e-6
#: Newton iterations of :func:`find_cycle`, and halvings of a step that does not lower the residual.
_ITERATIONS, _HALVINGS = 30, 30
#: :func:`log_det_product` evaluates log|det| at the orbit moved by its location error δ magnified to 1e-6 (∞-norm):
#: the change is then ≫ the Jacobians' error, and the O(δ²) curvature ≪ it.
_LOCATION_PROBE = 1e-6


class TangentMap(Protocol):
    """A map with its tangent map and inverse (``ExactMap``, ``SlowMap``, or a toy in the tests)."""

    def __call__(self, x: ArrayLike) -> NDArray[np.float64]: ...
    def jacobian(self, x: ArrayLike) -> NDArray[np.float64]: ...
    def inverse(self, x: ArrayLike) -> NDArray[np.float64]: ...


def reflected_reverse(x: ArrayLike) -> NDArray[np.float64]:
    """R S (Q_R, Q_J, Θ) = (Q_R, Q_J, −Θ): time reversal after the body's reflection, the map's second reversor."""
    return np.array(x, float) * [1.0, 1.0, -1.0]


#: The rock'n'roller map's reversors (both linear with det ±1), by name.
REVERSORS: Mapping[str, Callable[[ArrayLike], NDArray[np.float64]]] = {"R": reverse, "RS": reflected_reverse}


def _wrap(d: NDArray[np.float64], angles: Sequence[int]) -> NDArray[np.float64]:
    d = np.array(d, float)
    for i in angles:
        d[..., i] = np.mod(d[..., i] + math.pi, 2.0 * math.pi) - math.pi
    return d


def _log_det(J: NDArray[np.float64]) -> float:
    return float(np.linalg.slogdet(J)[1])  # log|det J|


class CycleError(ValueError):
    """Newton's method did not close the cycle to the asked residual."""


@dataclass(frozen=True)
class Cycle:
    """A periodic orbit of a map (:func:`find_cycle`).

    Attributes
    ----------
    points : ndarray
        (p, d): the orbit's points.
    residual : float
        max_k ‖P(x_k) − x_{k+1}‖∞ (angles wrapped).
    multipliers : ndarray
        Eigenvalues of D(P^p) at the first point.
    distances : tuple
        (name, max_k min_j ‖G x_k − x_j‖∞) for each reversor G.
    symmetry : str or None
        The first reversor with distance ≤ ``SYMMETRY_TOL``, or None (asymmetric).
    iterations : int
        Newton iterations taken.
    """

    points: NDArray[np.float64]
    residual: float
    multipliers: NDArray[np.complex128]
    distances: tuple[tuple[str, float], ...]
    symmetry: str | None
    iterations: int


def _shooting(F: TangentMap, X: NDArray[np.float64], angles: Sequence[int],
              jacobians: bool = True) -> tuple[NDArray[np.float64], list[NDArray[np.float64]]]:
    """The residuals P(x_k) − x_{k+1 mod p}, angles wrapped, and DP(x_k) if asked."""
    r = _wrap(np.array([F(x) for x in X]) - np.roll(X, -1, axis=0), angles)
    return r, [np.asarray(F.jacobian(x), float) for x in X] if jacobians else []


def _cyclic(Js: list[NDArray[np.float64]]) -> NDArray[np.float64]:
    """The shooting equations' matrix: DP(x_k) on the block diagonal, −1 beside it (cyclically)."""
    p, d = len(Js), len(Js[0])
    A = np.zeros((p * d, p * d))
    for k, J in enumerate(Js):
        A[k * d:(k + 1) * d, k * d:(k + 1) * d] += J
        A[k * d:(k + 1) * d, (k + 1) % p * d:((k + 1) % p + 1) * d] -= np.eye(d)
    return A


def find_cycle(F: TangentMap, x0: ArrayLike, period: int, *, angles: Sequence[int] = (2,),
               scale: ArrayLike | None = None, reversors: Mapping[str, Callable[[ArrayLike], Any]] | None = None,
               tol: float = CYCLE_TOL) -> Cycle:
    """The periodic orbit of ``period`` near the orbit of x0, by multiple shooting: unknowns x₀ … x_{p−1}, equations
    P(x_k) = x_{k+1 mod p} (``angles`` wrapped to (−π, π]), Newton's minimum-norm step in the coordinates x/``scale``
    (families of symmetric orbits make the system singular along the family: the step does not move along it), halved
    until the residual falls.  Then the multipliers and the symmetry under each of ``reversors`` (default
    ``REVERSORS``).

    Raises
    ------
    CycleError
        The residual stops falling above ``tol``, or ``_ITERATIONS`` are not enough.

    Examples
    --------
    >>> import math, numpy as np
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.slow.dynamics.reversibility import find_cycle
    >>> P = rr.ExactMap(rr.Body.paper(0.0), 0.9 * math.pi, 0.03)
    >>> c = find_cycle(P, [0.0, 0.0, math.pi], 1)          # rocking about the stable axis
    >>> print(c.symmetry, c.residual <= 1e-12, np.round(np.sort(np.abs(c.multipliers)), 6))
    R True [1. 1. 1.]
    """
    X = np.array([np.asarray(x0, float)])
    for _ in range(period - 1):
        X = np.vstack([X, F(X[-1])])
    d = X.shape[1]
    D = np.tile(np.ones(d) if scale is None else np.asarray(scale, float), period)
    r, Js = _shooting(F, X, angles)
    res = float(np.max(np.abs(r)))
    for it in range(_ITERATIONS + 1):
        if res <= tol:
            break
        if it == _ITERATIONS:
            raise CycleError(f"no cycle of period {period} within {_ITERATIONS} iterations (residual {res:.3g})")
        step = (D * np.linalg.lstsq(_cyclic(Js) * D, -r.ravel(), rcond=None)[0]).reshape(period, d)
        for _ in range(_HALVINGS):
            try:
                if float(np.max(np.abs(_shooting(F, X + step, angles, False)[0]))) < res:
                    break
            except ValueError:  # the trial left the map's domain (no motion at that (E, Q)): shorter
                pass
            step = 0.5 * step
        else:
            raise CycleError(f"Newton's step no longer lowers the residual {res:.3g} (period {period}): no cycle near")
        X = X + step
        r, Js = _shooting(F, X, angles)
        res = float(np.max(np.abs(r)))
    M = np.eye(d)
    for J in Js:
        M = J @ M
    dist = tuple((name, max(float(np.min(np.max(np.abs(_wrap(X - G(x), angles)), axis=1))) for x in X))
                 for name, G in (REVERSORS if reversors is None else reversors).items())
    sym = next((name for name, s in dist if s <= SYMMETRY_TOL), None)
    return Cycle(X, res, np.linalg.eigvals(M).astype(complex), dist, sym, it)


@dataclass(frozen=True)
class DetProduct:
    """log Π |det DP(x_k)| around a periodic orbit, with its error bound (:func:`log_det_product`).

    Attributes
    ----------
    log_product : float
        Σ_k log|det DP(x_k)|.
    jacobian_error : float
        p · d · rtol (the Jacobians' error, |δ log|det|| ≤ d rtol each).
    location_error : float
        The change of the sum when the points move to the exact cycle (module constants).
    period : int
        p.
    """

    log_product: float
    jacobian_error: float
    location_error: float
    period: int

    @property
    def error(self) -> float:
        """The bound on |log_product − the exact cycle's value|: jacobian_error + location_error."""
        return self.jacobian_error + self.location_error


def log_det_product(F: TangentMap, points: ArrayLike, *, angles: Sequence[int] = (2,),
                    rtol: float = EXACT_JACOBIAN_RTOL) -> DetProduct:
    """Σ log|det DP| over the cycle ``points`` (p, d), with its error (:class:`DetProduct`).

    The location error: the exact cycle is x_k + δ_k, DP(x_k) δ_k − δ_{k+1} = −(P(x_k) − x_{k+1}) to first order
    (the minimum-norm solution, Newton's step); the sum's change is measured at x_k + s δ_k with s‖δ‖∞ = 1e-6,
    divided by s, plus the Jacobians' error of that difference, 2 p d rtol / s.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.slow.dynamics.reversibility import log_det_product
    >>> P = rr.ExactMap(rr.Body.paper(0.0), 0.9 * math.pi, 0.03)
    >>> d = log_det_product(P, [[0.0, 0.0, 0.0]])           # rocking about the unstable axis
    >>> print(abs(d.log_product) <= d.error, d.error < 1e-10)
    True True
    """
    X = np.atleast_2d(np.asarray(points, float))
    p, d = X.shape
    defect, Js = _shooting(F, X, angles)
    total = sum(_log_det(J) for J in Js)
    delta = np.linalg.lstsq(_cyclic(Js), -defect.ravel(), rcond=None)[0].reshape(p, d)
    size = float(np.max(np.abs(delta)))
    location = 0.0
    if size > 0.0:
        s = _LOCATION_PROBE / size
        moved = sum(_log_det(np.asarray(F.jacobian(x), float)) for x in X + s * delta)
        location = (abs(moved - total) + 2 * p * d * rtol) / s
    return DetProduct(float(total), p * d * rtol, location, p)


def reversor_defect(F: TangentMap, x: ArrayLike, reversor: Callable[[ArrayLike], Any] = reverse, *,
                    rtol: float = EXACT_JACOBIAN_RTOL) -> tuple[float, float]:
    """(log|det DP(x)| + log|det DP(G P x)|, its bound 2 d rtol): zero when G is a linear reversor with |det G| = 1
    (DP⁻¹(P x) = G DP(G P x) G), so a wrong involution shows as a defect beyond the bound.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.slow.dynamics.reversibility import reversor_defect
    >>> defect, bound = reversor_defect(rr.ExactMap(rr.Body.paper(0.0), 0.9 * math.pi, 0.03), [0.02, 0.0, 1.0])
    >>> print(abs(defect) <= bound)
    True
    """
    x = np.asarray(x, float)
    J1 = np.asarray(F.jacobian(x), float)
    J2 = np.asarray(F.jacobian(reversor(F(x))), float)
    return _log_det(J1) + _log_det(J2), 2 * x.size * rtol


@dataclass(frozen=True)
class LyapunovSum:
    """The sum of P's Lyapunov exponents over n steps (:func:`lyapunov_sum`).

    Attributes
    ----------
    value : (1/n) Σ log|det DP| over the points visited (forward: x₀ … x_{n−1}; backward: y₁ … y_n of the orbit
        y_{k+1} = P⁻¹(y_k), i.e. minus the sum of P⁻¹'s exponents there).
    qr_value : the same from the QR accumulation, Σ_i exponents (agrees with value to round-off).
    exponents : ndarray
        (d,): P's finite-time exponents from the QR accumulation, decreasing.
    error : d rtol, the Jacobians' error of value (the orbit's evaluation error moves it ≲ 0.1 × 5.6e-13 a step).
    n : int
        Steps.
    backward : bool
        Whether the orbit was that of P⁻¹.
    log_dets : ndarray
        log|det DP| at each point visited, in order.
    """

    value: float
    qr_value: float
    exponents: NDArray[np.float64]
    error: float
    n: int
    backward: bool
    log_dets: NDArray[np.float64]

    def mean(self, n: int) -> float:
        """The value after the first n steps (the same bound ``error``)."""
        return float(np.mean(self.log_dets[:n]))


def lyapunov_sum(F: TangentMap, x0: ArrayLike, n: int, *, backward: bool = False,
                 rtol: float = EXACT_JACOBIAN_RTOL) -> LyapunovSum:
    """The mean of log|det DP| along n steps of the orbit of P (or of P⁻¹ with ``backward``) from x0, directly and
    by QR of the tangent maps (sum of log|R_ii|), in P's orientation (:class:`LyapunovSum`).  With a continuous
    invariant density both directions tend to 0 like 1/n; in mixed dynamics forward → < 0, backward → > 0.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.slow.dynamics.reversibility import lyapunov_sum
    >>> s = lyapunov_sum(rr.ExactMap(rr.Body.paper(0.0), 0.9 * math.pi, 0.0), [0.01, 0.0, 1.0], 3)
    >>> print(abs(s.value) <= s.error, abs(s.qr_value - s.value) <= s.error)     # Routh's sphere: det DP = 1
    True True
    """
    x = np.asarray(x0, float)
    d = x.size
    Q, logs, dets = np.eye(d), np.zeros(d), np.empty(n)
    for k in range(n):
        if backward:
            x = F.inverse(x)
            J = np.asarray(F.jacobian(x), float)
            T = np.linalg.inv(J)
        else:
            J = T = np.asarray(F.jacobian(x), float)
            x = F(x)
        dets[k] = _log_det(J)
        Q, R = np.linalg.qr(T @ Q)
        logs += np.log(np.abs(np.diag(R)))
    exps = (-logs if backward else logs) / n
    return LyapunovSum(float(np.mean(dets)), float(np.sum(exps)), np.sort(exps)[::-1], d * rtol, n, backward, dets)
