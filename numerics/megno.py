"""Chaos indicators of an orbit sampled at its θ-maxima: MEGNO and the finite-time maximal Lyapunov exponent.

One formula for both the direct motion (a tangent vector integrated along the ODE, sampled at the θ-maxima) and the
averaged slow map (a tangent vector propagated step by step), so the two are compared in the same units: the samples
are the times t_k of the maxima and ℓ_k = ln(‖w(t_k)‖/‖w(0)‖), the logarithmic growth of a tangent vector w (kept
as a logarithm: a propagator renormalises w and adds up the logarithms, so nothing overflows).

MEGNO (Cincotta & Simó 2000, *Astron. Astrophys. Suppl.* 147, 205; the discrete form of Cincotta, Giordano & Simó
2003, *Physica D* 182, 151) with the samples' own times as weights:

    Y(t_n) = (2/t_n) Σ_{k=1..n} t_k (ℓ_k − ℓ_{k−1}),      ⟨Y⟩(t_n) = (1/t_n) Σ_{k=1..n} Y(t_k) (t_k − t_{k−1}),

the Riemann–Stieltjes sums of Y(t) = (2/t) ∫₀ᵗ s d ln‖w‖ and its time mean; for equally spaced maxima
(t_k = k T) they are the map's Y_n = (2/n) Σ k ln(δ_k/δ_{k−1}) and ⟨Y⟩_n.  Limits: ⟨Y⟩ → 2 on a regular (quasi-
periodic) orbit, where ‖w‖ grows linearly; → 0 on a stable periodic orbit; ≈ λ t/2 on a chaotic one (REBOUND's
``sim.megno()``, the same definition).

The finite-time Lyapunov exponent is the least-squares slope of ℓ against t over the later half of the samples
(the first half is the transient in which w turns towards the most unstable direction), per unit time and, divided
by the mean time between maxima, per rock.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["ChaosIndicators", "MEGNO_CHAOTIC", "MEGNO_CLIP", "MIN_SAMPLES", "megno_series", "lyapunov_slope",
           "chaos_indicators"]

#: ⟨Y⟩ above which an orbit is called chaotic over the time sampled.  A regular orbit's ⟨Y⟩ is 2 + O(ln t / t)
#: (≤ 2.2 from a few dozen maxima on), a stable periodic one's tends to 0; a chaotic one's passes 3 once λ t ≳ 6,
#: i.e. once a nearby start has separated by e⁶ ≈ 400 times its initial distance.  The verdict is a finite-time one:
#: an orbit in a thin chaotic layer with λ t < 6 over the time sampled is called regular, and is, to that time.
MEGNO_CHAOTIC = 3.0
#: Top of the colour scales of MEGNO (the atlas's layer, the portrait's orbits): a regular orbit's MEGNO is ≈ 2 (0 on
#: a stable periodic one), a chaotic one's grows as λt/2 without bound (above ``MEGNO_CHAOTIC``: chaotic); larger
#: values get the top colour (the colour bar's arrow), so that the scale is the same on every figure.
MEGNO_CLIP = 5.0
#: Fewest samples (θ-maxima after the start) from which the indicators are computed.
MIN_SAMPLES = 8


@dataclass(frozen=True)
class ChaosIndicators:
    """MEGNO and the finite-time maximal Lyapunov exponent of one orbit, from its samples at the θ-maxima.

    Attributes
    ----------
    t : times of the samples (the θ-maxima after the start).
    log_growth : ℓ_k = ln(‖w(t_k)‖/‖w(0)‖) of the tangent vector.
    megno : ⟨Y⟩ at the last sample.
    lyapunov : finite-time maximal Lyapunov exponent per unit time (:func:`lyapunov_slope`), ≥ 0.
    lyapunov_per_rock : the same per rock (per θ-maximum: per unit time × mean time between maxima).
    regular : ``megno <= MEGNO_CHAOTIC``.
    mean_megno : ⟨Y⟩ at every sample.
    """

    t: NDArray[np.float64] = field(repr=False)
    log_growth: NDArray[np.float64] = field(repr=False)
    megno: float
    lyapunov: float
    lyapunov_per_rock: float
    regular: bool
    mean_megno: NDArray[np.float64] = field(repr=False)

    @property
    def lyapunov_time(self) -> float:
        """1/λ (inf where λ = 0)."""
        return math.inf if self.lyapunov <= 0.0 else 1.0 / self.lyapunov


def _samples(t: ArrayLike, log_growth: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    t = np.asarray(t, dtype=float)
    ell = np.asarray(log_growth, dtype=float)
    if t.ndim != 1 or ell.shape != t.shape:
        raise ValueError(f"t and log_growth must be 1-d arrays of one length, got shapes {t.shape} and {ell.shape}")
    if len(t) < MIN_SAMPLES:
        raise ValueError(f"the indicators need at least MIN_SAMPLES = {MIN_SAMPLES} samples (θ-maxima), got {len(t)}: "
                         "integrate or iterate longer")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(ell))):
        raise ValueError("t and log_growth must be finite")
    if not (t[0] > 0.0 and np.all(np.diff(t) > 0.0)):
        raise ValueError("t must be positive and strictly increasing (the times of the maxima after the start at t = 0)")
    return t, ell


def megno_series(t: ArrayLike, log_growth: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Y and ⟨Y⟩ at every sample (module docstring), from the start at t = 0 where ℓ = 0.

    Parameters
    ----------
    t : times of the samples, 0 < t_1 < t_2 < ...
    log_growth : ℓ_k = ln(‖w(t_k)‖/‖w(0)‖).

    Returns
    -------
    Y, mean_Y : arrays like ``t``.
    """
    t, ell = _samples(t, log_growth)
    dl = np.diff(ell, prepend=0.0)
    Y = 2.0 * np.cumsum(t * dl) / t
    dt = np.diff(t, prepend=0.0)
    return Y, np.cumsum(Y * dt) / t


def lyapunov_slope(t: ArrayLike, log_growth: ArrayLike) -> float:
    """Least-squares slope of ℓ against t over the later half of the samples, floored at 0 (per unit time)."""
    t, ell = _samples(t, log_growth)
    half = len(t) // 2
    slope = float(np.polyfit(t[half:], ell[half:], 1)[0])
    return max(slope, 0.0)


def chaos_indicators(t: ArrayLike, log_growth: ArrayLike) -> ChaosIndicators:
    """The :class:`ChaosIndicators` of one orbit from its samples at the θ-maxima (module docstring)."""
    t, ell = _samples(t, log_growth)
    _, mean_Y = megno_series(t, ell)
    lam = lyapunov_slope(t, ell)
    per_rock = lam * float(t[-1] / len(t))
    megno = float(mean_Y[-1])
    return ChaosIndicators(t=t, log_growth=ell, megno=megno, lyapunov=lam, lyapunov_per_rock=per_rock,
                           regular=megno <= MEGNO_CHAOTIC, mean_megno=mean_Y)
