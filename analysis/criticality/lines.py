"""The critical Jellett lines and the regions I–IV of the (Q_R, Q_J) plane.

Paper §criticality (eqs. phidotCJQR th=0, th=pi, QJcrit_0, QJcrit_pi).

* The critical lines Q_J = Q_J,0^crit(Q_R) = ρ₀(1 − a) I3 Q_R and Q_J = Q_J,π^crit(Q_R) = −ρ_π(1 + a) I3 Q_R are the
  zeros of the numerator u = Q_J − ρ f I3 Q_R of V_φ (paper eq. phidotCJQR) at θ = 0 and θ = π.  Their signed
  distances u₀ = Q_J − Q_J,0^crit and u_π = Q_J − Q_J,π^crit are evaluated once, in double-double, by
  :func:`rocknroller.analysis.routh.reduction.u_ends`; everything here is built on them.
* Regions (paper §criticality): I: u₀ < 0 < u_π (Q_R > 0); II: u₀, u_π > 0; III: u_π < 0 < u₀ (Q_R < 0); IV: u₀, u_π < 0.

cos θ_z and the δ^½ bound are in :mod:`rocknroller.analysis.criticality.theta_z`, starts on a line in
:mod:`~rocknroller.analysis.criticality.starts`, the crossings of a run in :mod:`~rocknroller.analysis.criticality.reversals`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.routh.reduction import check_invariants, u_ends

__all__ = [
    "REGIONS", "ON_LINE_0", "ON_LINE_PI", "ON_BOTH", "LINES", "REGION_TOL", "QJ_crit_0", "QJ_crit_pi", "QJ_crit",
    "region", "region_fractions", "region_from_offsets", "side_code", "check_finite", "on_line", "strict_regions"
]

REGIONS = ("I", "II", "III", "IV")
#: Labels of :func:`region` for points on a critical line within the tolerance.
ON_LINE_0, ON_LINE_PI, ON_BOTH = "on QJ0crit", "on QJpicrit", "origin"
#: Names of the two critical lines, as accepted by :func:`QJ_crit` and :func:`critical_start`.
LINES = ("0", "pi")
#: Default relative tolerance of :func:`region` for "on a line": |u_e| <= tol * max(|Q_J|, |Q_J,e^crit|).
REGION_TOL = 1e-12

_REGION_OF_SIGNS = {(-1, 1): "I", (1, 1): "II", (1, -1): "III", (-1, -1): "IV"}
#: The same table indexed by side_code(u0, uπ) = 2 [u0 ≥ 0] + [uπ ≥ 0].
_REGION_BY_CODE = np.array([_REGION_OF_SIGNS[(2 * (c // 2) - 1, 2 * (c % 2) - 1)] for c in range(4)], dtype="<U11")


# ----------------------------------------------------------------------------- critical lines
def QJ_crit_0(QR: ArrayLike, body: Body) -> NDArray[np.float64]:
    """Critical Jellett quantity at θ = 0, Q_J,0^crit = ρ₀ (1 − a) I3 Q_R (paper eq. QJcrit_0).

    ρ₀ = [I3 + (I3/I1)(1 − a)²]^(−1/2).  Correctly rounded (from :func:`rocknroller.analysis.routh.reduction.u_ends`).

    Examples
    --------
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> print(f"{rr.QJ_crit_0(0.01, body):.12f}")
    0.003176133554
    """
    (QR,) = check_invariants(QR=QR)
    return -u_ends(QR, 0.0, body)[0]


def QJ_crit_pi(QR: ArrayLike, body: Body) -> NDArray[np.float64]:
    """Critical Jellett quantity at θ = π, Q_J,π^crit = −ρ_π (1 + a) I3 Q_R (paper eq. QJcrit_pi).

    ρ_π = [I3 + (I3/I1)(1 + a)²]^(−1/2).  Correctly rounded (from :func:`rocknroller.analysis.routh.reduction.u_ends`).

    Examples
    --------
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> print(f"{rr.QJ_crit_pi(0.01, body):.12f}")
    -0.003259832208
    """
    (QR,) = check_invariants(QR=QR)
    return -u_ends(QR, 0.0, body)[1]


def QJ_crit(line: str, QR: ArrayLike, body: Body) -> NDArray[np.float64]:
    """Q_J,0^crit (``line="0"``) or Q_J,π^crit (``line="pi"``).

    Examples
    --------
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> bool(rr.QJ_crit("pi", 0.01, body) == rr.QJ_crit_pi(0.01, body))
    True
    >>> bool(rr.QJ_crit("0", 0.01, body) == rr.QJ_crit_0(0.01, body))
    True
    """
    if line == "0":
        return QJ_crit_0(QR, body)
    if line == "pi":
        return QJ_crit_pi(QR, body)
    raise ValueError(f"line must be one of {LINES} (Q_J,0^crit or Q_J,pi^crit), got line={line!r}")


def check_finite(name: str, v: ArrayLike) -> NDArray[np.float64]:
    """``v`` as a float array, or a ValueError naming ``name`` if any entry is NaN or infinite.

    Examples
    --------
    >>> from rocknroller.analysis.criticality.lines import check_finite
    >>> check_finite("delta", [0.1, 0.2])
    array([0.1, 0.2])
    >>> check_finite("delta", [float("nan")])
    Traceback (most recent call last):
    ...
    ValueError: delta must be finite, got [nan]
    """
    arr = np.asarray(v, float)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got {v!r}")
    return arr


def region_from_offsets(u0: ArrayLike, upi: ArrayLike) -> NDArray[np.str_]:
    """Region I–IV from the signs of u0 = Q_J − Q_J,0^crit and uπ = Q_J − Q_J,π^crit (paper §criticality).

    A zero offset counts as above its line; :func:`region` reports points near a line separately.
    """
    return np.asarray(_REGION_BY_CODE[side_code(u0, upi)], dtype=_REGION_BY_CODE.dtype)  # an array also for scalars


def side_code(u0: ArrayLike, upi: ArrayLike) -> NDArray[np.int64]:
    """The sides of both critical lines as one integer 2 [u0 ≥ 0] + [uπ ≥ 0]: bit 1 is the side of
    Q_J,0^crit, bit 0 that of Q_J,π^crit (so the XOR of two codes names the lines crossed)."""
    return 2 * (np.asarray(u0) >= 0).astype(np.int64) + (np.asarray(upi) >= 0)


def on_line(u: NDArray, QJ: NDArray, tol: float) -> NDArray[np.bool_]:
    """|Q_J − Q_J,e^crit| = |u_e| ≤ tol · max(|Q_J|, |Q_J,e^crit|): on the critical line e within tol, from the
    offset u_e = Q_J − Q_J,e^crit and Q_J.

    Examples
    --------
    >>> import numpy as np
    >>> from rocknroller.analysis.criticality.lines import on_line
    >>> on_line(np.array([1e-15, 1e-3]), np.array([1.0, 1.0]), 1e-12)
    array([ True, False])
    """
    return np.abs(u) <= tol * np.maximum(np.abs(QJ), np.abs(QJ - u))


def region(QR: ArrayLike, QJ: ArrayLike, body: Body, tol: float = REGION_TOL) -> NDArray[np.str_] | str:
    """Critical region I–IV of (Q_R, Q_J) (paper §criticality), vectorised.

    A point with |Q_J − Q_J,e^crit| ≤ tol · max(|Q_J|, |Q_J,e^crit|) is reported as on that line:
    ``ON_LINE_0`` ("on QJ0crit"), ``ON_LINE_PI`` ("on QJpicrit"), or ``ON_BOTH`` ("origin", only Q_R = Q_J = 0
    for tol < 1).  The default tol = 1e-12 is about 4500 rounding units (2⁻⁵²): the side of a line is then
    decided by the sign of the double-double distance u_e, which is exact for the given doubles.

    Returns
    -------
    numpy array of str (a plain str for scalar input).

    Examples
    --------
    >>> import rocknroller as rr
    >>> body = rr.Body.paper()
    >>> print(rr.region(0.01, 0.0, body))
    I
    >>> print(rr.region([0.01, 0.01, 0.0], [0.01, -0.01, 0.0], body))
    ['II' 'IV' 'origin']
    """
    QR, QJ = check_invariants(QR=QR, QJ=QJ)
    tol = float(tol)
    if not 0.0 <= tol < 1.0:
        raise ValueError(f"tol must satisfy 0 <= tol < 1, got tol={tol!r}")
    u0, upi = u_ends(QR, QJ, body)
    on0, onpi = on_line(u0, QJ, tol), on_line(upi, QJ, tol)
    out = np.broadcast_to(region_from_offsets(u0, upi), np.broadcast(QR, QJ).shape).copy()
    out[on0] = ON_LINE_0
    out[onpi] = ON_LINE_PI
    out[on0 & onpi] = ON_BOTH
    return str(out) if out.ndim == 0 else out


def region_fractions(QR: ArrayLike, QJ: ArrayLike, body: Body, tol: float = REGION_TOL) -> dict[str, float]:
    """The fraction of the samples (Q_R, Q_J) (the θ-maxima of a run, for example ``run.maxima.QR``,
    ``run.maxima.QJ`` of a :class:`~rocknroller.numerics.ensembles.ensemble.RunSummary`) in each critical region I–IV and on
    each line, by :func:`region` (with its ``tol``).

    Returns
    -------
    dict
        ``{label: fraction}`` for every label of :func:`region`, the regions ``REGIONS`` first, then ``ON_LINE_0``,
        ``ON_LINE_PI``, ``ON_BOTH``; the fractions sum to 1.

    Raises
    ------
    ValueError
        No samples, Q_R and Q_J of different shapes, or a sample that is not finite.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> traj = rr.simulate(body, rr.EulerState(0.95 * math.pi, psi=math.pi / 4), 300.0)
    >>> fractions = rr.region_fractions(traj.maxima.QR, traj.maxima.QJ, body)
    >>> print(len(traj.maxima.QR), fractions)  # doctest: +NORMALIZE_WHITESPACE
    22 {'I': 0.5, 'II': 0.0, 'III': 0.5, 'IV': 0.0, 'on QJ0crit': 0.0, 'on QJpicrit': 0.0, 'origin': 0.0}
    """
    if np.shape(QR) != np.shape(QJ) or np.size(QR) == 0:
        raise ValueError(f"QR and QJ must be samples of one shape, at least one, got shapes {np.shape(QR)} and "
                         f"{np.shape(QJ)}")
    reg = np.asarray(region(QR, QJ, body, tol)).reshape(-1)
    return {lab: float(np.count_nonzero(reg == lab) / reg.size) for lab in REGIONS + (ON_LINE_0, ON_LINE_PI, ON_BOTH)}


def strict_regions(QR: NDArray, QJ: NDArray, body: Body, allowed: tuple[str, ...], what: str) -> NDArray:
    """The regions of (Q_R, Q_J) with no tolerance about the lines (:func:`region` with tol = 0), or a ValueError
    naming ``what`` and the first point outside the ``allowed`` regions.

    Examples
    --------
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.criticality.lines import strict_regions
    >>> body = rr.Body.paper()
    >>> QJ = float(rr.QJ_crit_pi(0.01, body)) + 1e-3
    >>> print(strict_regions(0.01, QJ, body, ("I", "II", "III", "IV"), "a quantity"))
    I
    """
    reg = np.asarray(region(QR, QJ, body, tol=0.0))
    bad = ~np.isin(reg, allowed)
    if np.any(bad):
        i = np.flatnonzero(bad.ravel())[0]
        raise ValueError(f"{what} exists only in Regions {'/'.join(allowed)}; (QR, QJ) = "
                         f"({np.ravel(QR * np.ones_like(QJ))[i]!r}, {np.ravel(QJ * np.ones_like(QR))[i]!r}) "
                         f"is in {reg.ravel()[i]}")
    return reg


