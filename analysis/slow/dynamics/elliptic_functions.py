"""The complete elliptic integral K(m) and the Jacobi elliptic functions sn, cn, dn, by the arithmetic-geometric mean
(Abramowitz & Stegun 17.6 and 16.4, the algorithm of Cephes' ``ellpj`` that scipy.special wraps), for the pendulum's
closed form (:func:`rocknroller.analysis.slow.dynamics.pendulum.pendulum_prediction`).

They are here, in numpy, rather than taken from scipy.special, whose import costs a first prediction 0.2 s of CPU
(the rest of scipy is not imported on that path).  Checked against mpmath at 30 digits and against scipy.special
(tests/analysis/slow/dynamics/test_elliptic_functions.py).

Error.  The AGM runs N ≤ ``_MAX_STEPS`` steps, each rounding a, b, c once; the amplitude φ_N = 2^N a_N u then carries
a relative error of about (N + 2) u_r (u_r the unit round-off), an absolute one of (N + 2) u_r |u| a_N, and the N
descending steps φ_{n−1} = (φ_n + asin(c_n sin φ_n / a_n)) / 2 halve it while adding a few roundings each.  So sn and
cn are within about (N + 4)(1 + |u|) u_r of the true values, and dn = cn / cos(φ_0 − φ_1) within that over dn's
least value √(1 − m); where cos(φ_0 − φ_1) < 0.1 (u near an odd multiple of K), dn = √(1 − m sn²) instead, within
about m (N + 4)(1 + |u|) u_r / dn.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["ellipk", "ellipj"]

#: Most AGM steps: c_n / a_n falls quadratically (below the round-off after 6 steps at m = 1 − 1e-15).
_MAX_STEPS = 16
#: Below this |cos(φ_0 − φ_1)|, dn is taken from sn (Cephes' switch): the quotient cn / cos(φ_0 − φ_1) is then 0/0-like.
_DN_SWITCH = 0.1


def _check_m(m: float) -> float:
    m = float(m)
    if not 0.0 <= m < 1.0:  # also NaN
        raise ValueError(f"the parameter m = k^2 must lie in [0, 1) (m = 1 is the separatrix: K is infinite), got m={m!r}")
    return m


def _agm(m: float) -> tuple[list[float], list[float]]:
    """The AGM's (a_n, c_n), n = 0..N, from a_0 = 1, b_0 = √(1 − m), c_0 = √m, until c_N ≤ a_N u_r."""
    a, b, c = [1.0], math.sqrt(1.0 - m), [math.sqrt(m)]
    while abs(c[-1]) > np.finfo(float).eps * a[-1]:
        if len(a) > _MAX_STEPS:  # pragma: no cover - quadratic convergence: 6 steps reach the round-off at 1 − 1e-15
            raise RuntimeError(f"the AGM did not converge in {_MAX_STEPS} steps at m={m!r}")
        ai = a[-1]
        c.append(0.5 * (ai - b))
        a.append(0.5 * (ai + b))
        b = math.sqrt(ai * b)
    return a, c


def ellipk(m: float) -> float:
    """The complete elliptic integral of the first kind K(m) = ∫₀^{π/2} dθ / √(1 − m sin²θ) = π / (2 AGM(1, √(1 − m))).

    Parameters
    ----------
    m : float
        The parameter k², in [0, 1).

    Examples
    --------
    >>> from rocknroller.analysis.slow.dynamics.elliptic_functions import ellipk
    >>> print(f"{ellipk(0.0):.15f} {ellipk(0.5):.15f}")
    1.570796326794897 1.854074677301372
    """
    a, _ = _agm(_check_m(m))
    return math.pi / (2.0 * a[-1])


def ellipj(u: ArrayLike, m: float) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The Jacobi elliptic functions sn(u | m), cn(u | m), dn(u | m), by the AGM's descending amplitudes.

    Parameters
    ----------
    u : array_like
        The arguments (finite).
    m : float
        The parameter k², in [0, 1).

    Returns
    -------
    sn, cn, dn : ndarray
        Shaped like ``u``.

    Examples
    --------
    >>> from rocknroller.analysis.slow.dynamics.elliptic_functions import ellipj, ellipk
    >>> sn, cn, dn = ellipj([0.0, ellipk(0.5)], 0.5)      # at u = K: sn = 1, cn = 0, dn = √(1 − m)
    >>> print(sn.round(15), abs(cn).round(15), dn.round(15))
    [0. 1.] [1. 0.] [1.         0.70710678]
    """
    u = np.asarray(u, dtype=float)
    if not np.all(np.isfinite(u)):
        raise ValueError("the arguments u must be finite")
    a, c = _agm(_check_m(m))
    n = len(a) - 1
    phi = (2.0 ** n) * a[n] * u
    previous = phi
    for i in range(n, 0, -1):
        previous = phi
        phi = 0.5 * (np.arcsin(c[i] * np.sin(phi) / a[i]) + phi)
    sn, cn = np.sin(phi), np.cos(phi)
    if not n:
        return sn, cn, np.ones_like(phi)
    # dn = cn / cos(φ_0 − φ_1), but where both vanish (u near K) from dn² = 1 − m sn², as Cephes (DLMF 22.20.5)
    factor = np.cos(phi - previous)
    with np.errstate(divide="ignore", invalid="ignore"):
        dn = np.where(np.abs(factor) < _DN_SWITCH, np.sqrt(1.0 - m * sn * sn), cn / factor)
    return sn, cn, dn
