"""The mpmath reference of the precession quadratures: turning points and T_θ, Δφ, Δψ at any precision.

Independent of the double-precision rule of :mod:`rocknroller.analysis.routh.quadrature` (paper §2.5, eq.
Delta_phi): the same integrals by mpmath's tanh-sinh quadrature in the end variable, straight from the
definitions of P, u and ρ (no cancellation tricks), at ``dps`` decimal digits (default 40).
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import mpmath
import numpy as np

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.model.invariants import rho_inv_sq
from rocknroller.analysis.routh.quadrature import Precession
from rocknroller.analysis.routh.reduction import (NO_MOTION, OK, STEADY, D_coefficient, _u_direct, potential, reduced_N,
                                                  reduced_P, require_open_tilt)
from rocknroller.analysis.routh.turning_points import solve_turning_points

__all__ = ["turning_points_mp", "precession_mp"]


# ----------------------------------------------------------------------------- mpmath reference
def _mp_body(body: Body) -> SimpleNamespace:
    return SimpleNamespace(a=mpmath.mpf(body.a), I1=mpmath.mpf(body.I1), I3=mpmath.mpf(body.I3),
                           g=mpmath.mpf(body.g))


def _mp_theta(x, y):
    """θ = 2 atan2(√x, √y) from x = 1 − cos θ, y = 1 + cos θ (mpmath; reduction.theta_from_xy in double)."""
    return 2 * mpmath.atan2(mpmath.sqrt(x), mpmath.sqrt(y))


def _mp_terms(x, y, E, QR, QJ, mb):
    """P, u and 1/ρ at (x, y) in mpmath, straight from the definitions (no cancellation tricks)."""
    s2 = x * y
    f = (1 - x) - mb.a
    R = mpmath.sqrt(rho_inv_sq(mb, s2, f))
    u = _u_direct(f, R, QR, QJ, mb)
    P = reduced_P(s2, E - potential(x, mb), reduced_N(s2, f, R, u, QR, mb))
    return P, u, R


def _mp_root(z0: float, small_is_x: bool, inward_up: bool, E, QR, QJ, mb):
    """Root of P in the end variable z (x or y), bracketed around the double estimate z0.

    ``inward_up``: the allowed interval lies at larger z (θ_N in x, θ_X in y); else at smaller z.
    """
    sign = 1 if inward_up else -1

    def P_of(z):
        x, y = (z, 2 - z) if small_is_x else (2 - z, z)
        return sign * _mp_terms(x, y, E, QR, QJ, mb)[0]

    z0 = mpmath.mpf(z0)
    if z0 < 1e-100 and P_of(mpmath.mpf(0)) == 0:  # Q_J exactly critical here: the turning point is the end
        return mpmath.mpf(0)
    # P < 0 on the end side of the root and P > 0 inside the allowed interval (in x and in y alike)
    lo, hi = z0 * (1 - mpmath.mpf(1e-9)), z0 * (1 + mpmath.mpf(1e-9))
    for _ in range(400):
        if P_of(lo) < 0:
            break
        lo = lo / 10 if lo > 1e-300 else mpmath.mpf(0)
    for _ in range(400):
        if P_of(hi) > 0 or hi >= 1:
            break
        hi = min(hi * 10 if hi > 0 else mpmath.mpf(10) ** -300, mpmath.mpf(1))
    if not (P_of(lo) < 0 < P_of(hi)):
        raise ValueError(f"mpmath backend: could not bracket a turning point near {mpmath.nstr(z0, 17)} (in "
                         f"{'x = 1 - cos theta' if small_is_x else 'y = 1 + cos theta'})")
    z = mpmath.findroot(P_of, (lo, hi), solver="anderson")
    return z


def _same_tilt(x: float, y: float, x0: float, y0: float) -> bool:
    """Whether (x, y) is θ0 = (x0, y0) to 1e-6 relative in the end variable that is exact at θ0."""
    return abs(x / x0 - 1) < 1e-6 if x0 <= y0 else abs(y / y0 - 1) < 1e-6


def _check_dps(dps: Any) -> int:
    if not isinstance(dps, (int, np.integer)) or not 15 <= int(dps) <= 1000:
        raise ValueError(f"dps must be an integer in [15, 1000], got dps={dps!r}")
    return int(dps)


def _mp_turning_points(E: Any, QR: Any, QJ: Any, body: Body, mb: SimpleNamespace, theta0: float | None):
    """(E, (x_N, y_N), (x_X, y_X)) in mpmath at the working precision (see turning_points_mp)."""
    body.require_symmetric("the precession quadratures")
    QRm, QJm = mpmath.mpf(QR), mpmath.mpf(QJ)
    if theta0 is not None:
        theta0 = float(require_open_tilt(theta0))
        x0 = 2 * mpmath.sin(mpmath.mpf(theta0) / 2) ** 2
        y0 = 2 * mpmath.cos(mpmath.mpf(theta0) / 2) ** 2
        Em = -_mp_terms(x0, y0, 0, QRm, QJm, mb)[0] / (2 * x0 * y0)  # U(θ0): the E with P(θ0) = 0
    else:
        Em = mpmath.mpf(E)
    # double-precision estimates to bracket the roots
    tp = solve_turning_points(float(Em), float(QR), float(QJ), body)
    if int(tp.status) == NO_MOTION:
        raise ValueError(f"no motion: F(theta) < 0 on all of (0, pi) for E={E!r}, QR={QR!r}, QJ={QJ!r}")
    if int(tp.status) == STEADY:
        raise ValueError(f"steady circular rolling (double root) for E={E!r}, QR={QR!r}, QJ={QJ!r}; "
                         "not integrated")
    roots = []
    for (xr, yr), is_N in (((float(tp.x_N), float(tp.y_N)), True), ((float(tp.x_X), float(tp.y_X)), False)):
        small_is_x = xr <= yr
        if theta0 is not None and _same_tilt(xr, yr, float(x0), float(y0)):
            roots.append((x0, y0))
            continue
        z = _mp_root(xr if small_is_x else yr, small_is_x, small_is_x == is_N, Em, QRm, QJm, mb)
        roots.append((z, 2 - z) if small_is_x else (2 - z, z))
    return Em, roots[0], roots[1]


def turning_points_mp(E: Any, QR: Any, QJ: Any, body: Body, dps: int = 40) -> tuple[Any, Any]:
    """(θ_N, θ_X) with mpmath.findroot at ``dps`` digits (the reference for reduction.turning_points).

    Raises
    ------
    ValueError
        dps out of range, no motion, steady rolling, asymmetric body.
    """
    dps = _check_dps(dps)
    with mpmath.workdps(2 * dps + 20):
        _, (xN, yN), (xX, yX) = _mp_turning_points(E, QR, QJ, body, _mp_body(body), None)
        thetas = [_mp_theta(x, y) for x, y in ((xN, yN), (xX, yX))]
    with mpmath.workdps(dps):
        return +thetas[0], +thetas[1]


def precession_mp(E: Any, QR: Any, QJ: Any, body: Body, dps: int = 40, *, theta0: float | None = None) -> Precession:
    """Reference values of :class:`Precession` with mpmath at ``dps`` significant digits.

    Scalar.  The turning points are found with ``mpmath.findroot`` on P (reduction) at
    2·dps + 60 digits; the integrals over v (module docstring) are done by tanh-sinh
    (``mpmath.quad``) on [0, π/2] and [π/2, π] separately, each from its own end, with extra
    subdivision points at the scale √(x_N/H) of a near passage through θ = 0 (π); the poles of
    V_φ are NOT subtracted here, so this is an independent check of the double backend.

    Parameters
    ----------
    E, QR, QJ : float, str or mpf
        Converted exactly (floats) to mpf.  If ``theta0`` is given, E is ignored and computed as
        U(θ0) at working precision, and the root at θ0 is θ0 itself.
    dps : int
        Decimal digits of the result, 15 ≤ dps ≤ 1000.

    Raises
    ------
    ValueError
        dps out of range, no motion, steady rolling, asymmetric body, θ0 outside (0, π).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> E, QR, QJ = rr.invariants_from_euler(body, 0.95 * math.pi, 0.0, 0.15, 0.15)
    >>> ref = rr.precession_mp(E, QR, QJ, body, dps=30)
    >>> p = rr.precession(E, QR, QJ, body)
    >>> print(f"{float(ref.T_theta):.10f}", abs(float(ref.T_theta) / p.T_theta - 1) < 1e-13)
    13.1496523760 True
    """
    dps = _check_dps(dps)
    work = 2 * (dps + 15) + 30
    with mpmath.workdps(work):
        mb = _mp_body(body)
        QRm, QJm = mpmath.mpf(QR), mpmath.mpf(QJ)
        Em, (xN, yN), (xX, yX) = _mp_turning_points(E, QR, QJ, body, mb, theta0)
        H = xX - xN

        cache: dict = {}

        def core(t, second: bool):
            key = (t, second)
            if key not in cache:
                with mpmath.workdps(work):
                    cache[key] = core_work(t, second)
            return cache[key]

        def core_work(t, second: bool):
            sh2, ch2 = mpmath.sin(t / 2) ** 2, mpmath.cos(t / 2) ** 2
            S, C = (ch2, sh2) if second else (sh2, ch2)
            x, y = xN + H * S, yX + H * C
            P, u, R = _mp_terms(x, y, Em, QRm, QJm, mb)
            if P <= 0:  # node within round-off of a turning point (tanh-sinh weight < 10^-(dps+15))
                return mpmath.mpf(0), mpmath.mpf(0), mpmath.mpf(0)
            J = H * mpmath.sqrt(S * C) * mpmath.sqrt(D_coefficient(x, mb) / P)
            vphi = u / (mb.I1 * x * y)  # V_φ = u/(I1 s²) (paper eq. phidotCJQR)
            return J, vphi * J, (QRm / R - (1 - x) * vphi) * J  # V_ψ = ρ Q_R − c V_φ

        def integrate(k: int) -> Any:
            total = mpmath.mpf(0)
            for second, end_small in ((False, xN), (True, yX)):
                width = mpmath.sqrt(end_small / H) if end_small > 0 else mpmath.mpf(0)
                pts = [mpmath.mpf(0)]
                w = 2 * width
                while 0 < w < mpmath.pi / 4:
                    pts.append(w)
                    w *= 16
                pts.append(mpmath.pi / 2)
                with mpmath.workdps(dps + 15):
                    f = lambda t: core(+t, second)[k]  # noqa: E731
                    total += mpmath.quad(f, pts, method="tanh-sinh")
            return total

        T_half, phi_half, psi_half = integrate(0), integrate(1), integrate(2)
        T_theta = 2 * T_half
        dphi, dpsi = 2 * phi_half, 2 * psi_half
        with mpmath.workdps(dps):
            rnd = lambda a: +a  # noqa: E731
            return Precession(
                E=rnd(Em), QR=QRm, QJ=QJm,
                theta_N=rnd(_mp_theta(xN, yN)),
                theta_X=rnd(_mp_theta(xX, yX)),
                T_theta=rnd(T_theta), tau=rnd(2 * T_theta),
                delta_phi=rnd(dphi), delta_psi=rnd(dpsi), delta_phi_tau=rnd(2 * dphi), delta_psi_tau=rnd(2 * dpsi),
                visible_phi=rnd(wrap_angle(dphi)), visible_half_phi=rnd(wrap_angle(dphi, mpmath.pi)),
                status=OK, n_nodes=0,
            )
