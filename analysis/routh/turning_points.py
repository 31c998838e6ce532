"""The turning points θ_N < θ_X of Routh's sphere: the simple roots of F(θ) = 0 about the minimum of U.

Paper §2.4 (eq. thetadotsq): θ oscillates where E > U(θ; Q_R, Q_J).  U is unimodal in w = log tan²(θ/2), so its
minimum is found by golden section and each root by bisection in w, all vectorised; the roots are returned in the
end variables x = 1 − cos θ, y = 1 + cos θ with their full relative precision (:class:`TurningPoints`, never
raising) or as angles (:func:`turning_points`, raising ``NoMotionError`` or ``SteadyRollingError``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.routh.reduction import (NO_MOTION, OK, STATUS_TEXT, STEADY, NoMotionError, SteadyRollingError,
                                                  _P_xy, _U_xy, _xy_from_w, check_invariants, theta_from_xy, u_ends,
                                                  where_defined)

if TYPE_CHECKING:
    import pandas

__all__ = ["TurningPoints", "min_potential", "solve_turning_points", "turning_points"]


#: Search range of w = log tan²(θ/2): θ ≳ 2 e^{-150} and π − θ ≳ 2 e^{-150}.
_W_MAX = 300.0


_GOLDEN_ITER = 90


_BISECT_ITER = 72


#: A double root is declared when E − min U ≤ _STEADY_RTOL · min U (U ≥ 0 is a sum of positive terms).
_STEADY_RTOL = 64 * np.finfo(float).eps


@dataclass(frozen=True)
class TurningPoints:
    """Turning points of θ̇² = F(θ), vectorised, never raising.

    ``x_* = 1 − cos θ_*`` and ``y_* = 1 + cos θ_*`` carry the full relative precision at the ends;
    ``status`` is OK, NO_MOTION or STEADY (see STATUS_TEXT); the root fields are masked arrays,
    masked at the non-OK entries (:func:`where_defined`).  ``u0``, ``upi``
    are the numerators of V_φ at θ = 0 and π.
    """

    E: NDArray[np.float64]
    QR: NDArray[np.float64]
    QJ: NDArray[np.float64]
    x_N: NDArray[np.float64]
    y_N: NDArray[np.float64]
    x_X: NDArray[np.float64]
    y_X: NDArray[np.float64]
    U_min: NDArray[np.float64]
    theta_min: NDArray[np.float64]
    u0: NDArray[np.float64]
    upi: NDArray[np.float64]
    status: NDArray[np.int64]

    @property
    def theta_N(self) -> NDArray[np.float64]:
        return theta_from_xy(self.x_N, self.y_N)

    @property
    def theta_X(self) -> NDArray[np.float64]:
        return theta_from_xy(self.x_X, self.y_X)

    def to_dataframe(self) -> "pandas.DataFrame":
        """One row per point: E, Q_R, Q_J, θ_N, θ_X, min U, its θ and the status (missing where a turning
        point does not exist; needs pandas)."""
        from rocknroller.analysis.model.frames import dataframe

        return dataframe({"E": self.E, "QR": self.QR, "QJ": self.QJ, "theta_N": self.theta_N,
                          "theta_X": self.theta_X, "U_min": self.U_min, "theta_min": self.theta_min,
                          "status": self.status, "status_text": np.vectorize(STATUS_TEXT.get, otypes=[str])(
                              np.asarray(self.status))})


def _minimize_U(QR, QJ, body: Body):
    """Golden-section search of U over w = log tan²(θ/2) ∈ [−_W_MAX, _W_MAX] (U is unimodal)."""
    shape = np.broadcast(QR, QJ).shape
    lo, hi = np.full(shape, -_W_MAX), np.full(shape, _W_MAX)
    r = (np.sqrt(5.0) - 1.0) / 2.0
    w1, w2 = hi - r * (hi - lo), lo + r * (hi - lo)
    U1, U2 = _U_xy(*_xy_from_w(w1), QR, QJ, body), _U_xy(*_xy_from_w(w2), QR, QJ, body)
    for _ in range(_GOLDEN_ITER):
        left = U1 <= U2  # minimum in [lo, w2]
        hi = np.where(left, w2, hi)
        lo = np.where(left, lo, w1)
        new_w1 = np.where(left, hi - r * (hi - lo), w2)
        new_w2 = np.where(left, w1, lo + r * (hi - lo))
        w_eval = np.where(left, new_w1, new_w2)
        U_eval = _U_xy(*_xy_from_w(w_eval), QR, QJ, body)
        U1, U2 = np.where(left, U_eval, U2), np.where(left, U1, U_eval)
        w1, w2 = new_w1, new_w2
    w = 0.5 * (lo + hi)
    return w, _U_xy(*_xy_from_w(w), QR, QJ, body)


def min_potential(QR: ArrayLike, QJ: ArrayLike, body: Body) -> NDArray[np.float64]:
    """min over θ of U(θ; Q_R, Q_J), vectorised (the golden-section search of :func:`solve_turning_points`):
    the least energy with which θ can oscillate at these invariants (steady rolling, paper §2.3)."""
    body.require_symmetric("the effective potential U")
    QR, QJ = np.broadcast_arrays(*check_invariants(QR=QR, QJ=QJ))
    return _minimize_U(QR, QJ, body)[1]


def _bisect_root(lo, hi, E, QR, QJ, body: Body, rising: bool):
    """Root of P in w between lo and hi (P(lo) < 0 < P(hi) if rising), then one regula-falsi step
    in the exact small variable (x if the root has x ≤ 1, else y)."""
    for _ in range(_BISECT_ITER):
        mid = 0.5 * (lo + hi)
        Pm = _P_xy(*_xy_from_w(mid), E, QR, QJ, body)
        pos = Pm > 0.0
        if rising:
            hi, lo = np.where(pos, mid, hi), np.where(pos, lo, mid)
        else:
            lo, hi = np.where(pos, mid, lo), np.where(pos, hi, mid)
    xl, yl = _xy_from_w(lo)
    xh, yh = _xy_from_w(hi)
    Pl, Ph = _P_xy(xl, yl, E, QR, QJ, body), _P_xy(xh, yh, E, QR, QJ, body)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(Pl != Ph, Pl / (Pl - Ph), 0.5)
    t = np.clip(np.nan_to_num(t, nan=0.5), 0.0, 1.0)
    use_x = xl + xh <= 2.0
    x = np.where(use_x, xl + t * (xh - xl), 2.0 - (yl + t * (yh - yl)))
    y = np.where(use_x, 2.0 - x, yl + t * (yh - yl))
    return x, y


def solve_turning_points(E: ArrayLike, QR: ArrayLike, QJ: ArrayLike, body: Body) -> TurningPoints:
    """Turning points θ_N ≤ θ_X of θ̇² = F(θ), vectorised; never raises for physical reasons.

    U(θ) (module docstring) is unimodal on (0, π), so the allowed set {E ≥ U} is one interval.
    Its minimum is found by golden section in w = log tan²(θ/2), the two roots of P by bisection
    in w and a final regula-falsi step in the exact end variable x or y.  Reaches θ_N and π − θ_X down to
    2 e^(−150) ≈ 1.4e-65, the end of the search range (|w| ≤ 300); a root closer to the pole (|Q_J − Q_J,e^crit|
    below ~1e-65 √E) is reported at that end, within 1.5e-65 rad of the truth, which the precession
    quadratures do not feel (their pole terms are exact for every θ_N).

    Returns
    -------
    TurningPoints
        ``status`` = NO_MOTION where E < min U − tol, STEADY (double root, steady circular
        rolling, paper §2.3 "Pure Rolling") where |E − min U| ≤ tol with
        tol = 64 ε min U; root fields are masked there.

    Raises
    ------
    ValueError
        Asymmetric body, or E, Q_R, Q_J outside :func:`check_invariants`' ranges.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> E, QR, QJ = rr.invariants_from_euler(body, 0.95 * math.pi, 0.0, 0.15, 0.15)
    >>> tp = rr.solve_turning_points([E, 0.0], [QR, QR], [QJ, QJ], body)
    >>> print(tp.status)
    [0 1]
    >>> print(f"{tp.theta_X[0] / math.pi:.10f} pi", tp.theta_X.mask[1])
    0.9500000000 pi True
    """
    body.require_symmetric("the turning points of theta_dot^2 = F(theta)")
    E, QR, QJ = np.broadcast_arrays(*check_invariants(E=E, QR=QR, QJ=QJ))
    w_min, U_min = _minimize_U(QR, QJ, body)
    u0, upi = u_ends(QR, QJ, body)
    tol = _STEADY_RTOL * np.abs(U_min)
    status = np.where(E < U_min - tol, NO_MOTION, np.where(E <= U_min + tol, STEADY, OK)).astype(np.int64)
    ok = status == OK
    # a root may sit beyond the search range only if u0 (u_pi) is ~0: then it is at the end itself
    lo = np.full(E.shape, -_W_MAX)
    hi = np.full(E.shape, _W_MAX)
    xN, yN = _bisect_root(lo, np.where(ok, w_min, 0.0), E, QR, QJ, body, rising=True)
    xX, yX = _bisect_root(np.where(ok, w_min, 0.0), hi, E, QR, QJ, body, rising=False)
    return TurningPoints(
        E=E, QR=QR, QJ=QJ,
        x_N=where_defined(xN, ok), y_N=where_defined(yN, ok),
        x_X=where_defined(xX, ok), y_X=where_defined(yX, ok),
        U_min=U_min, theta_min=theta_from_xy(*_xy_from_w(w_min)), u0=u0, upi=upi, status=status,
    )


def turning_points(E: ArrayLike, QR: ArrayLike, QJ: ArrayLike,
                   body: Body) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(θ_N, θ_X), the roots of F in (0, π) (paper §2.5), vectorised.

    Robust near both ends (θ_N down to 1e-10 and far below, θ_X up to π − 1e-8 and beyond).
    See :func:`solve_turning_points` for the non-raising form with the exact end variables.

    Raises
    ------
    NoMotionError (a ValueError)
        If for some point F < 0 on all of (0, π) (E below the minimum of U).
    SteadyRollingError (a ValueError)
        If some point is a double root θ_N = θ_X (steady circular rolling): it is reported, never
        integrated; the exception's ``theta`` attribute holds the steady tilt (masked elsewhere).
    ValueError
        Asymmetric body or non-finite input.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> E, QR, QJ = rr.invariants_from_euler(body, 0.95 * math.pi, 0.0, 0.15, 0.15)
    >>> theta_N, theta_X = rr.turning_points(E, QR, QJ, body)
    >>> print(f"{theta_N / math.pi:.10f} pi, {theta_X / math.pi:.10f} pi")
    0.0001717329 pi, 0.9500000000 pi
    """
    tp = solve_turning_points(E, QR, QJ, body)
    if np.any(tp.status == NO_MOTION):
        i = np.flatnonzero(tp.status == NO_MOTION)[0]
        raise NoMotionError(
            f"no motion: F(theta) < 0 on all of (0, pi) for E={float(tp.E.flat[i])!r}, QR={float(tp.QR.flat[i])!r}, "
            f"QJ={float(tp.QJ.flat[i])!r}; E must be >= min U = {float(tp.U_min.flat[i])!r}")
    if np.any(tp.status == STEADY):
        i = np.flatnonzero(tp.status == STEADY)[0]
        raise SteadyRollingError(
            f"double root: E={float(tp.E.flat[i])!r} equals min U to round-off for QR={float(tp.QR.flat[i])!r}, "
            f"QJ={float(tp.QJ.flat[i])!r}; this is steady circular rolling at theta={float(tp.theta_min.flat[i])!r}, "
            "not a rocking motion", where_defined(tp.theta_min, tp.status == STEADY))
    return tp.theta_N, tp.theta_X
