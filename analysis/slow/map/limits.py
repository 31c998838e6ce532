"""Where the averaged slow map applies and how long one run may be; the stable rocking axis and its period doubling.
It holds the release angles of the release tables (``THETA0_RANGE``, :func:`check_map_theta0`) and of any release
from rest (:func:`check_release_theta0`), the most θ-maxima of one run (``MAX_MAXIMA``) and the t_end they allow
(:func:`t_end_limit`, :func:`check_t_end`), the standard map's period-doubling threshold K = ε κ = 4
(``K_PERIOD_DOUBLING``, :func:`eps_period_doubling`) and the ψ of the stable rocking (:func:`stable_rocking_psi`), the
maxima x = (Q_R, Q_J, Θ) the maps take, one or an array of them (:func:`check_points`), and the error and warning of
the slow-motion prediction (:class:`AveragingRangeError`, :class:`AveragingValidityWarning`;
:mod:`rocknroller.analysis.slow.prediction`; docs/averaging.md, "Releases from rest: the range of θ0" and "Limits").

Pure checks on plain floats (and on arrays of points, row by row): a ValueError naming the parameter (``name``, e.g.
``--theta0`` for the CLI) and its allowed range, and for an array the rows that break it (:func:`rows_text`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import as_float
from rocknroller.analysis.model.equations import EulerState

__all__ = [
    "THETA0_RANGE", "MAX_MAXIMA", "K_PERIOD_DOUBLING", "eps_period_doubling", "stable_rocking_psi",
    "AveragingRangeError", "ChartWidthError", "AveragingValidityWarning", "check_map_theta0", "t_end_limit",
    "check_t_end", "check_release_theta0", "default_order", "ANGLE_MAX", "check_angle", "check_points", "rows_text"
]

#: Largest |angle| (ψ0, Θ, in radians) the slow motion takes: an angle is reduced mod 2π in double precision with an
#: absolute error of about |angle|·u (1.1e-10 rad at 1e6), and past about 1e15 its reduction loses every digit
#: (ψ0 = 1e15 gave an empty prediction, 1e14 another verdict, Θ = 1e17 came back unchanged).  Larger ones are refused.
ANGLE_MAX = 1e6


def check_angle(name: str, value: float) -> float:
    """``value`` if it is a finite angle within ±``ANGLE_MAX``, else a ValueError naming ``name`` and the range."""
    v = float(value)
    if not abs(v) <= ANGLE_MAX:
        raise ValueError(_angle_message(name, v))
    return v


def _angle_message(name: str, v: float) -> str:
    return (f"{name} must be a finite angle within [-{ANGLE_MAX:g}, {ANGLE_MAX:g}] rad (ANGLE_MAX): reduce it mod 2pi, "
            f"whose rounding grows as |angle| u, got {name}={v!r}")


#: Most row indices an error message lists (:func:`rows_text`).
ROWS_LISTED = 10


def rows_text(mask: NDArray[np.bool_]) -> str:
    """The rows of an array of points where ``mask`` (its leading shape) is True, for a message: their indices into
    the leading axes (integers for a stack (N, 3), tuples beyond; the first ``ROWS_LISTED``) and their count."""
    where = np.argwhere(mask)
    rows = [int(i[0]) if mask.ndim == 1 else tuple(int(j) for j in i) for i in where[:ROWS_LISTED]]
    more = ", ..." if len(where) > ROWS_LISTED else ""
    return f"rows {str(rows)[:-1]}{more}] ({len(where)} of {mask.size})"


def check_points(x: ArrayLike) -> NDArray[np.float64]:
    """x as a new float array (..., 3): one maximum (Q_R, Q_J, Θ) of shape (3,), or an array of them along its last
    axis; else a ValueError.  Each row must be three finite numbers with |Θ| ≤ ``ANGLE_MAX`` (:func:`check_angle`);
    an array's message names the rows that are not (:func:`rows_text`), one point's is the one it always was.  A
    complex x is refused, not cast with a ComplexWarning (its imaginary part silently dropped), and so is a string.

    Examples
    --------
    >>> check_points([[0.0, 0.0, 1.0], [1e-3, 0.0, 2.0]]).shape
    (2, 3)
    >>> check_points([[0.0, 0.0, 1.0], [0.0, float("nan"), 2.0]])
    Traceback (most recent call last):
    ...
    ValueError: x must be three finite numbers (Q_R, Q_J, Theta) in every row, and rows [1] (1 of 2) of x (shape (2, 3)) are not
    """
    try:
        shape: object = np.shape(x)
        real = not isinstance(x, str) and not np.iscomplexobj(x)
        a = np.array(x, dtype=float) if real else np.array(np.nan)
    except (TypeError, ValueError):  # a ragged sequence, or elements that are not numbers
        shape, a = "none: not an array of numbers", np.array(np.nan)
    if a.ndim == 0 or a.shape[-1] != 3:
        got = f"x={x!r} (shape {shape})" if a.ndim <= 1 else f"an array of shape {a.shape}"
        raise ValueError(f"x must be three finite numbers (Q_R, Q_J, Theta), or an array (..., 3) of them, got {got}")
    if a.ndim == 1:
        if not np.all(np.isfinite(a)):
            raise ValueError(f"x must be three finite numbers (Q_R, Q_J, Theta), got x={x!r} (shape {shape})")
        check_angle("Theta", a[2])
        return a
    bad = ~np.all(np.isfinite(a), axis=-1)
    if bad.any():
        raise ValueError(f"x must be three finite numbers (Q_R, Q_J, Theta) in every row, and {rows_text(bad)} of x "
                         f"(shape {a.shape}) are not")
    far = ~(np.abs(a[..., 2]) <= ANGLE_MAX)
    if far.any():
        raise ValueError(f"{_angle_message('Theta', float(a[..., 2][far][0]))}, the first of {rows_text(far)} of x "
                         f"(shape {a.shape}) beyond it")
    return a


#: Release angles (θ0_min, θ0_max) for which the tables are built and the map is validated against the direct ODE
#: (docs/averaging.md, "Releases from rest: the range of θ0").  Below ≈ 0.732π (paper body) the table rectangle, 2.5
#: times the libration amplitude at K = 4, reaches Q at which the energy of the release admits no motion: the tables
#: cannot be built; 0.75π keeps a margin.  Towards the upright equilibrium θ = π the tables lose accuracy (interpolation
#: error 2e-13 at 0.999π, 2e-7 at 0.9999π, O(1) at 0.99999π, where the map is wrong).
THETA0_RANGE = (0.75 * math.pi, 0.999 * math.pi)
#: Largest number of θ-maxima one run of the slow map may produce.  A run costs ~0.4 kB and ~4 µs per maximum
#: (its series, 5 × 8 bytes, and the critical-region diagnostics; measured: 10⁶ maxima, 0.42 GB peak, 4.3 s);
#: 10⁶ maxima (t_end up to 5·10⁵ T_θ(0), 6.6·10⁶ time units at θ0 = 0.95π) is far beyond the first-order
#: averaging's horizon, yet bounded for a laptop.
MAX_MAXIMA = 10**6

#: Chirikov's standard map I' = I + K sin Θ, Θ' = Θ + I' (the slow map near pure rocking, K = ε κ): the
#: Jacobian at its stable fixed point has trace 2 − K, which reaches −2 (period doubling) at K = 4.
K_PERIOD_DOUBLING = 4.0


def eps_period_doubling(kappa: float) -> float:
    """ε at which K = ε κ reaches K_PERIOD_DOUBLING (rocking about the stable axis period-doubles)."""
    return K_PERIOD_DOUBLING / abs(kappa)


def stable_rocking_psi(kappa: float) -> float:
    """ψ (mod π) of the stable pure rocking: π/2 for κ > 0 (the axis of moment I2), 0 for κ < 0."""
    return 0.5 * math.pi if kappa > 0 else 0.0


class AveragingRangeError(ValueError):
    """The slow orbit leaves the region where the averaging tables were built."""


class ChartWidthError(AveragingRangeError):
    """The slow orbit of a release leaves its release tables across the kick direction (|v| > V), where the region
    tables of its energy still hold it."""


class AveragingValidityWarning(UserWarning):
    """The prediction is outside the regime where the first-order theory is expected to hold."""


def check_map_theta0(theta0: float, name: str = "theta0") -> float:
    """θ0 as a float, or a ValueError naming ``name`` unless it lies in ``THETA0_RANGE`` (the releases for
    which the averaging tables are built and the map is validated; other amplitudes are not covered yet)."""
    theta0, (lo, hi) = as_float(name, theta0), THETA0_RANGE
    if not lo <= theta0 <= hi:  # also NaN
        raise ValueError(
            f"{name} must lie in [{lo / math.pi:g}pi, {hi / math.pi:g}pi] = [{lo:.6g}, {hi:.6g}] for the averaged "
            f"slow map, got {name}={theta0!r} = {theta0 / math.pi:.6g}pi: below {lo / math.pi:g}pi the averaging "
            "tables reach states that the energy of the release does not allow (they cannot be built; "
            "predict_slow_motion and rocknroller slow use the region tables there), above "
            f"{hi / math.pi:g}pi they lose accuracy near the upright equilibrium")
    return theta0


def check_release_theta0(theta0: float, name: str = "theta0") -> float:
    """θ0 of a release from rest as a float, or a ValueError naming ``name`` unless 0 < θ0 ≤ ``THETA0_RANGE[1]``
    (from ``THETA0_RANGE[0]`` up the release tables serve it, below the region tables of its energy)."""
    theta0, (lo, hi) = as_float(name, theta0), THETA0_RANGE
    if not 0.0 < theta0 <= hi:  # also NaN
        raise ValueError(f"{name} must lie in (0, {hi / math.pi:g}pi] for a release from rest, got {name}={theta0!r}: "
                         f"from {lo / math.pi:g}pi up on the release tables, below on the region tables of its energy; "
                         f"{name} = 0 is the body at rest at the bottom (no motion), and above {hi / math.pi:g}pi the "
                         "tables lose accuracy near the upright equilibrium")
    return theta0


def t_end_limit(T0: float) -> float:
    """Largest t_end for T0 = T_θ(0), the time between maxima of pure rocking: the maxima within t_end number
    at most t_end/(T0/2) (T_θ ≥ 0.73 T0 on the tables), which must not exceed ``MAX_MAXIMA``."""
    return 0.5 * MAX_MAXIMA * T0


def check_t_end(t_end: float, T0: float, name: str = "t_end") -> float:
    """t_end as a float, or a ValueError naming ``name`` unless 0 < t_end ≤ :func:`t_end_limit` (T0)."""
    t_end, tmax = as_float(name, t_end), t_end_limit(T0)
    if not (math.isfinite(t_end) and 0.0 < t_end <= tmax):
        raise ValueError(
            f"{name} must be a finite number in (0, {tmax:.6g}], got {name}={t_end!r}: a run of the slow map "
            f"produces up to t_end/(T_theta/2) maxima of theta (T_theta = {T0:.6g}), at most {MAX_MAXIMA:.0e}")
    return t_end


def default_order(start: float | EulerState) -> int:
    """The order of the map in ε when none is given, for a release angle θ0 or an initial state: the one default of
    every entry that takes an order (``predict_slow_motion``, ``SlowMap``, ``slow_portrait``, ``periodic_orbit``,
    ``continue_orbit``, ``periodic_start``, ``map_ensemble``, ``bifurcation_diagram``) and of the commands
    (``slow``, ``portrait``, ``bifurcation``); the atlas's default is 2 where the tables over energy cover its rows,
    else 1 (:func:`rocknroller.analysis.slow.atlas.atlas_order`), and it names its order.

    2 for a release from rest in ``THETA0_RANGE``: the second-order release tables bring the map 10–1000× closer to the
    direct ODE at ε ≤ 3e-3 (at the command's default release, 0.95π, ψ0 = π/4, ε = 1e-3, 1000 time units: slow period
    within 3.5e-6 of the ODE, order 1 2.2e-4; docs/slow_validation.md, "Releases from rest, second order"), for a build
    once per (body, θ0), then cached, and little more than the run time of order 1.  1 for any other start (an initial
    state, or a release below ``THETA0_RANGE``): its second-order tables are per energy, several times dearer, so
    order 2 is asked for explicitly there.  The costs: docs/performance.md.

    Examples
    --------
    >>> import math
    >>> from rocknroller.analysis.slow.map.limits import default_order
    >>> default_order(0.95 * math.pi), default_order(0.6 * math.pi)
    (2, 1)
    """
    # compared as given (int or float; Python compares them exactly, so 10**400 or NaN is simply out of range)
    in_range = (isinstance(start, (int, float)) and not isinstance(start, bool)
                and THETA0_RANGE[0] <= start <= THETA0_RANGE[1])
    return 2 if in_range else 1
