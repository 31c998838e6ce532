"""The period doubling of rocking about the stable principal axis, from the exact one-step map.  It holds the
Jacobian of the exact step at the rocking fixed point (:func:`rocking_jacobian`) and of one step of the averaged map
(:func:`map_rocking_jacobian`), the threshold ε_pd of the exact step, to all orders in ε (:func:`period_doubling`,
:class:`PeriodDoubling`), and the averaged maps' own thresholds at order 1 or 2 (:func:`map_period_doubling`), all
at the energy of a release from rest (paper eq. energy).

Rocking in the vertical plane of a principal axis (Q_R = Q_J = 0, ψ = ψ_s at every maximum) is an exact motion of
the asymmetric body, a fixed point p* = (0, 0, Θ_s = 2ψ_s) of the one-step map (Q_R, Q_J, Θ) → (Q_R', Q_J', Θ') at
the energy of the release.  Its Jacobian J(ε) has one multiplier 1 and a pair λ, 1/λ; the first-order averaged map
gives, near p*, Chirikov's standard map with K = ε κ, whose pair reaches −1 at K = 4: ε_pd ≈ 4/κ
(:func:`rocknroller.analysis.slow.map.limits.eps_period_doubling`).  Here J(ε) is computed from the exact step
(:func:`rocknroller.analysis.slow.map.exact_step.exact_step`: direct ODE, no expansion in ε) by fourth-order central
differences at p*, and ε_pd is the root of det(J(ε) + 1) = 0 (Brent), to all orders in ε.  Its departure from the
first-order value is the O(ε²) correction: K_pd = ε_pd κ = 4 + c ε_pd + O(ε_pd²).  The averaged maps' own thresholds
(:func:`map_period_doubling`: 4/κ for order 1; order 2 adds its part of the correction) are found the same way
on one map step.

Checked against direct runs (``tests/analysis/slow/dynamics/test_period_doubling.py``): a deviation of 1e-4 from ψ_s stays
1e-4 over 3000 time units below ε_pd and grows above it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map.exact_step import exact_step, step_difference
from rocknroller.analysis.slow.map.family import _central_difference, rest_energy
from rocknroller.analysis.slow.map.limits import K_PERIOD_DOUBLING, eps_period_doubling, stable_rocking_psi
from rocknroller.analysis.slow.map.orbit import symmetric_data

if TYPE_CHECKING:
    from rocknroller.analysis.slow.map.chart import SecondOrderTable

__all__ = ["rocking_jacobian", "map_rocking_jacobian", "map_period_doubling", "PeriodDoubling", "period_doubling"]

#: Steps of the central differences at p*: in Q (well inside the layer of width ~2/|∇W(0)| ≳ 5e-3 where W turns,
#: so the O(h⁴) truncation is ~1e-12 relative; the exact steps' ~1e-13 round-off adds ~1e-7/|∂Θ'/∂Q| ~ 1e-10) and
#: in Θ.
_H_Q, _H_THETA = 1e-6, 1e-5


def rocking_jacobian(body: Body, theta0: float, eps: float, stable_psi: float) -> NDArray[np.float64]:
    """J = ∂(Q_R', Q_J', Θ')/∂(Q_R, Q_J, Θ) of the exact one-step map of the member I2 = (1 + ε) I1 of ``body``'s
    family at the rocking fixed point (0, 0, 2 ψ_s), at the energy of the release from rest at θ0 (paper eq.
    energy).  Fourth-order central differences of :func:`exact_step`, 12 steps."""
    sym = body.symmetric()
    E = rest_energy(sym, theta0)
    period = float(symmetric_data(sym, E, 0.0, 0.0)[0])
    x0 = np.array([0.0, 0.0, 2.0 * stable_psi])

    def P(x: NDArray[np.float64]) -> NDArray[np.float64]:
        return exact_step(sym, eps, E, float(x[0]), float(x[1]), 0.5 * float(x[2]), period)[:3]

    return _central_jacobian(P, x0)


def map_rocking_jacobian(table: Any, eps: float, stable_psi: float, second: "SecondOrderTable | None" = None) -> NDArray[np.float64]:
    """As :func:`rocking_jacobian`, for one step of the averaged map on a release table (order 2 with its
    ``second``-order table)."""
    from rocknroller.analysis.slow.map.compiled_map import iterate_slow_map

    def P(x: NDArray[np.float64]) -> NDArray[np.float64]:
        s = iterate_slow_map(table, eps, 0.5 * float(x[2]), 1e6, Q0=x[:2], n_steps=1, second=second)
        return np.array([s.QR[0], s.QJ[0], s.Theta[0]])

    return _central_jacobian(P, np.array([0.0, 0.0, 2.0 * stable_psi]))


def _central_jacobian(P: Any, x0: NDArray[np.float64]) -> NDArray[np.float64]:
    """Fourth-order central differences of the step P at x0 (steps ``_H_Q``, ``_H_Q``, ``_H_THETA``; Θ wrapped)."""
    J = np.zeros((3, 3))
    for j, h in enumerate((_H_Q, _H_Q, _H_THETA)):
        e = np.eye(3)[j]
        J[:, j] = _central_difference(lambda s: P(x0 + s * e), 0.0, h, step_difference)
    return J


def _root(excess: Any, e1: float, theta0: float, rtol: float) -> float:
    """The root of ``excess`` (det(J + 1)) in ε near 4/κ = e1: a bracket grown from ±1 % by 5 % a side, to 0.8 e1."""
    from scipy.optimize import brentq

    lo, hi = 0.99 * e1, 1.01 * e1
    f_lo, f_hi = excess(lo), excess(hi)
    while f_lo * f_hi > 0.0:
        if lo < 0.8 * e1:
            raise ValueError(f"no period doubling of stable rocking within [0.8, 1.25] x 4/kappa = {e1:.4g} at "
                             f"theta0={theta0!r}")
        lo, hi = 0.95 * lo, 1.05 * hi
        f_lo, f_hi = excess(lo), excess(hi)
    return float(brentq(excess, lo, hi, xtol=1e-300, rtol=rtol))


def map_period_doubling(body: Body, theta0: float, order: int = 2, *, rtol: float = 1e-10, workers: int = 1) -> float:
    """ε at which the averaged map of ``order`` has its rocking fixed point period-double (4/κ for order 1, to
    the differences' accuracy; order 2 adds the map's O(ε²) correction).  Needs the release tables of (body, θ0)
    (and for order 2 the second-order ones, built once by ``workers`` processes and cached; their cost: docs/performance.md).

    Raises
    ------
    ValueError
        ``order`` not 1 or 2, θ0 outside ``THETA0_RANGE``, or no root near 4/κ.
    """
    body.require_gravity("the period doubling of the rocking")
    from rocknroller.analysis.slow.map.tables_at_once import release_tables

    if order not in (1, 2) or isinstance(order, bool):
        raise ValueError(f"order must be 1 or 2, got order={order!r}")

    table, second = release_tables(body, theta0, order, workers=workers)
    kappa = float(table.kappa)
    stable_psi = stable_rocking_psi(kappa)
    return _root(lambda eps: float(np.linalg.det(map_rocking_jacobian(table, eps, stable_psi, second) + np.eye(3))),
                 eps_period_doubling(kappa), theta0, rtol)


@dataclass(frozen=True)
class PeriodDoubling:
    """The period doubling of stable rocking at one release angle.

    Attributes
    ----------
    theta0 : the release angle (its energy fixes the map).
    stable_psi : ψ_s of the stable axis (π/2 for κ > 0: the axis of moment I2).
    kappa : κ of the first-order map (the release table's).
    eps_first_order : 4/κ.
    eps_exact : the root of det(J(ε) + 1) = 0 of the exact one-step map.
    K_exact : ε_exact κ (4 to first order).
    correction : c in K_pd = 4 + c ε_pd: (K_exact − 4)/ε_exact.
    multipliers : the eigenvalues of J at ε_exact (one 1, a pair at −1): float, or complex when a pair is.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> pd = rr.period_doubling(rr.Body.paper(), 0.95 * math.pi)
    >>> print(f"K at the period doubling: {pd.K_exact:.4f}")
    K at the period doubling: 3.9994
    """

    theta0: float
    stable_psi: float
    kappa: float
    eps_first_order: float
    eps_exact: float
    K_exact: float
    correction: float
    multipliers: NDArray[np.inexact[Any]]  # float64, or complex128 with a complex pair (numpy.linalg.eigvals)


def period_doubling(body: Body, theta0: float, *, rtol: float = 1e-10) -> PeriodDoubling:
    """ε at which rocking about the stable axis period-doubles, released from rest at θ0, to all orders in ε
    (module docstring), beside the first-order 4/κ.

    Parameters
    ----------
    body : Body
        Any member of the family; its (a, I1, I3, g) are used.
    theta0 : float
        Release angle in ``THETA0_RANGE`` (κ comes from its averaging table, built and cached if needed).
    rtol : float
        Relative tolerance of the root in ε.

    Raises
    ------
    ValueError
        θ0 outside ``THETA0_RANGE``; or no sign change of det(J + 1) within [0.8, 1.25] × 4/κ, or a bracket
        beyond the largest ε the moments allow (I2 < I3), naming it.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> pd = rr.period_doubling(rr.Body.paper(), 0.95 * math.pi)
    >>> print(f"4/kappa = {pd.eps_first_order:.6f}, exact: {pd.eps_exact:.6f}")
    4/kappa = 0.009385, exact: 0.009383
    """
    body.require_gravity("the period doubling of the rocking")
    from rocknroller.analysis.slow.map.tables_at_once import release_tables

    table = release_tables(body, theta0, 1)[0]
    kappa = float(table.kappa)
    stable_psi = stable_rocking_psi(kappa)
    e1 = eps_period_doubling(kappa)
    eps_max = body.I3 / body.I1 - 1.0
    if 1.25 * e1 >= eps_max:
        raise ValueError(f"the period doubling at theta0={theta0!r} lies near eps = 4/kappa = {e1:.4g}, beyond the "
                         f"largest eps the moments allow (I2 < I3: eps < {eps_max:.4g})")

    eps = _root(lambda e: float(np.linalg.det(rocking_jacobian(body, theta0, e, stable_psi) + np.eye(3))), e1,
                theta0, rtol)
    K = eps * kappa
    return PeriodDoubling(theta0=float(theta0), stable_psi=stable_psi, kappa=kappa, eps_first_order=e1,
                          eps_exact=eps, K_exact=K, correction=(K - K_PERIOD_DOUBLING) / eps,
                          multipliers=np.linalg.eigvals(rocking_jacobian(body, theta0, eps, stable_psi)))
