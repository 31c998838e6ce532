"""What is measured on samples at the turning points, shared by the direct ODE and the averaged map.

Definitions (used identically for the trajectory and for the prediction):

* the slow period is the period of Θ = 2ψ sampled at the θ-maxima, measured from the times at
  which the samples cross their mean (linear interpolation between samples), not from extrema;
* the extents of Q_R and Q_J are max − min over the turning-point samples within t_end;
* the azimuth span Φ is the span of φ mod π at the maxima (:func:`azimuth_span`);
* the visible angle is φ mod 2π and the visible half-angle φ mod π, both in the symmetric range
  (:func:`wrap_angle`, numpy or mpmath).

Pure functions over numpy arrays (and mpmath numbers for :func:`wrap_angle`); they live with the model so that
the trajectory, the quadratures and the slow map all use the same ones.
"""

from __future__ import annotations

import math
from typing import Any

import mpmath
import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["unwrap_phase", "mean_crossings", "slow_period", "span", "azimuth_span", "wrap_angle"]

_TWO_PI = 2.0 * np.pi


def unwrap_phase(Theta: ArrayLike) -> NDArray[np.float64]:
    """Θ = 2ψ samples made continuous (each step taken in [−π, π]).

    Θ changes by W(Q) + O(ε) per rock, which is < π in the regime of the averaging
    (|W| < π is required for the sampled phase to be meaningful at all).
    """
    x = np.array(Theta, dtype=float)
    if x.ndim != 1:
        raise ValueError(f"Theta must be a 1-D array, got shape {x.shape}")
    if x.size > 1:  # subtract the multiple of 2π nearest to each step, accumulated
        x[1:] -= _TWO_PI * np.cumsum(np.round((x[1:] - x[:-1]) / _TWO_PI))
    return x


def mean_crossings(t: ArrayLike, x: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Times at which the samples ``x(t)`` cross their mean, by linear interpolation.

    Returns
    -------
    (times, directions)
        Crossing times in increasing order and their directions (+1 upward, −1 downward).
    """
    t, x = np.asarray(t, float), np.asarray(x, float)
    if t.shape != x.shape or t.ndim != 1:
        raise ValueError(f"t and x must be 1-D arrays of equal length, got shapes {t.shape} and {x.shape}")
    d = x - x.mean()
    # a sample exactly at the mean counts with the sign of the next sample
    s = np.sign(d)
    n = s.size
    nxt = np.minimum.accumulate(np.where(s != 0, np.arange(n), n)[::-1])[::-1]  # next nonzero sign, n if none
    s = np.where(nxt < n, s[np.minimum(nxt, n - 1)], 0.0)
    idx = np.flatnonzero(s[:-1] * s[1:] < 0)
    frac = d[idx] / (d[idx] - d[idx + 1])
    return t[idx] + frac * (t[idx + 1] - t[idx]), np.where(d[idx + 1] > d[idx], 1, -1).astype(np.int64)


def slow_period(t: ArrayLike, Theta: ArrayLike) -> float | None:
    """Slow period of Θ = 2ψ sampled at the θ-maxima (times ``t``), from crossings of the mean.

    Upward and downward crossings are used separately: each direction with at least two crossings
    gives (last − first)/(count − 1), and the estimates are averaged weighted by their counts − 1.
    With only one crossing of each direction the period is twice their separation.

    Parameters
    ----------
    t : array_like
        Sample times (increasing).
    Theta : array_like
        Θ = 2ψ at those times (any branch: it is unwrapped first).

    Returns
    -------
    float or None
        The period, or None if the samples cross their mean fewer than twice (t_end shorter than
        about half a slow period): the period is then not measurable.
    """
    t = np.asarray(t, float)
    if t.size < 3:
        return None
    times, dirs = mean_crossings(t, unwrap_phase(Theta))
    total, weight = 0.0, 0
    for sgn in (1, -1):
        tc = times[dirs == sgn]
        if tc.size >= 2:
            total += tc[-1] - tc[0]
            weight += tc.size - 1
    if weight:
        return float(total / weight)
    if times.size >= 2:
        return float(2.0 * (times[1] - times[0]))
    return None


def span(x: ArrayLike) -> float:
    """max − min of the samples (0.0 for none)."""
    x = np.asarray(x, float)
    return float(x.max() - x.min()) if x.size else 0.0


def azimuth_span(phi: ArrayLike) -> float:
    """Azimuth span Φ = φ_max − φ_min of the visible half-angle φ mod π (paper §7.2).

    Measured on the circle of circumference π — π minus the largest gap between the sorted
    samples of φ mod π — so that it does not depend on where the cut of ``mod π`` falls.
    Returns 0.0 for fewer than two samples.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> print(f"{rr.azimuth_span([0.1, 0.3, math.pi + 0.2]):.12f}")
    0.200000000000
    >>> print(f"{rr.azimuth_span([3.1, 0.05]):.12f}")
    0.091592653590
    """
    v = np.sort(np.mod(np.asarray(phi, float), math.pi))
    if v.size < 2:
        return 0.0
    gaps = np.diff(np.concatenate([v, [v[0] + math.pi]]))
    return float(math.pi - gaps.max())


def wrap_angle(angle: Any, period: Any = None) -> Any:
    """angle mod period in the symmetric range (−period/2, period/2] (default period 2π).

    numpy arrays, or an mpmath number (then at the working precision, period 2π of that precision).
    """
    if isinstance(angle, mpmath.mpf):
        period = 2 * mpmath.pi if period is None else mpmath.mpf(period)
        r = mpmath.fmod(period / 2 - angle, period)
        return period / 2 - (r + period if r < 0 else r)
    period = 2 * np.pi if period is None else period
    a = np.asarray(angle, float)
    return period / 2 - np.remainder(period / 2 - a, period)
