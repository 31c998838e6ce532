"""Where the averaged slow map applies and how long one run may be; the stable rocking axis and its period doubling.
It holds the release angles of the release tables (``THETA0_RANGE``, :func:`check_map_theta0`) and of any release
from rest (:func:`check_release_theta0`), the most θ-maxima of one run (``MAX_MAXIMA``) and the t_end they allow
(:func:`t_end_limit`, :func:`check_t_end`), the standard map's period-doubling threshold K = ε κ = 4
(``K_PERIOD_DOUBLING``, :func:`eps_period_doubling`) and the ψ of the stable rocking (:func:`stable_rocking_psi`), and
the error and warning of the slow-motion prediction (:class:`AveragingRangeError`, :class:`AveragingValidityWarning`;
:mod:`rocknroller.analysis.slow.prediction`; docs/averaging.md, "Releases from rest: the range of θ0" and "Limits").

Pure checks on plain floats: a ValueError naming the parameter (``name``, e.g. ``--theta0`` for the CLI) and its
allowed range.
"""

from __future__ import annotations

import math

from rocknroller.analysis.model.body import as_float

__all__ = [
    "THETA0_RANGE", "MAX_MAXIMA", "K_PERIOD_DOUBLING", "eps_period_doubling", "stable_rocking_psi",
    "AveragingRangeError", "ChartWidthError", "AveragingValidityWarning", "check_map_theta0", "t_end_limit",
    "check_t_end", "check_release_theta0", "ANGLE_MAX", "check_angle"
]

#: Largest |angle| (ψ0, Θ, in radians) the slow motion takes: an angle is reduced mod 2π in double precision with an
#: absolute error of about |angle|·u (1.1e-10 rad at 1e6), and past about 1e15 its reduction loses every digit
#: (ψ0 = 1e15 gave an empty prediction, 1e14 another verdict, Θ = 1e17 came back unchanged).  Larger ones are refused.
ANGLE_MAX = 1e6


def check_angle(name: str, value: float) -> float:
    """``value`` if it is a finite angle within ±``ANGLE_MAX``, else a ValueError naming ``name`` and the range."""
    v = float(value)
    if not abs(v) <= ANGLE_MAX:
        raise ValueError(f"{name} must be a finite angle within [-{ANGLE_MAX:g}, {ANGLE_MAX:g}] rad (ANGLE_MAX): reduce "
                         f"it mod 2pi, whose rounding grows as |angle| u, got {name}={v!r}")
    return v

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
