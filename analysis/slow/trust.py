"""What each number of a slow prediction can be trusted for: predicted, statistical or undefined, and why.

A slow prediction's observables (the slow period of Θ = 2ψ, the Q_R and Q_J extents and the azimuth span Φ) are
computed for every start, but they do not all mean the same:

* **predicted**: the map follows the orbit over the run (a verdict that is not chaotic, or t_end within the
  predictability horizon), and the number is the orbit's own;
* **statistical**: t_end lies past the predictability horizon (:meth:`SlowPrediction.horizon_estimate
  <rocknroller.analysis.slow.prediction_result.SlowPrediction.horizon_estimate>`); the number describes the region the
  orbit fills over the run (an ensemble over nearby starts gives its spread: ``rocknroller slow --statistics``), not
  one trajectory;
* **undefined**: there is no such number: the slow period of a chaotic orbit (the mean interval between crossings of
  the mean that the run measures is not a period), a quantity the run cannot measure (None), or a closed form used
  outside its range: past the period doubling (K > 4), on a chaotic orbit, or where its regime bound exceeds
  ``REGIME_TOLERANCE`` (:mod:`rocknroller.analysis.slow.dynamics.pendulum`).

``rocknroller slow`` prints the status beside each number (text, ``--json``'s ``status``, the CSV header), and gives
no value where it is undefined.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from rocknroller.analysis.slow.dynamics.pendulum import REGIME_TOLERANCE, pendulum_regime_error
from rocknroller.analysis.slow.map.limits import K_PERIOD_DOUBLING

__all__ = ["PREDICTED", "STATISTICAL", "UNDEFINED", "QUANTITIES", "Trust", "map_trust", "closed_form_trust",
           "prediction_trust"]

PREDICTED, STATISTICAL, UNDEFINED = "predicted", "statistical", "undefined"
#: The observables marked.
QUANTITIES = ("slow_period", "QR_extent", "QJ_extent", "Phi")


@dataclass(frozen=True)
class Trust:
    """A number's status (``PREDICTED``, ``STATISTICAL`` or ``UNDEFINED``) and the reason, in words.

    Attributes
    ----------
    status : str
        One of "predicted", "statistical", "undefined".
    reason : str
        Why (empty for "predicted").
    """

    status: str
    reason: str = ""


def _undefined_value(value: Any) -> bool:
    return value is None or (isinstance(value, float) and not math.isfinite(value))


def map_trust(quantity: str, value: Any, verdict: str | None, beyond_horizon: bool | None) -> Trust:
    """The status of the averaged map's ``quantity`` (module docstring) for a start of chaos ``verdict``
    ("regular", "chaotic", "undecided", or None without indicators) whose t_end is ``beyond_horizon`` or not (None:
    no horizon, e.g. a periodic orbit or ε = 0).

    Examples
    --------
    >>> from rocknroller.analysis.slow.trust import map_trust
    >>> map_trust("slow_period", 200.3, "chaotic", True).status, map_trust("QR_extent", 0.07, "chaotic", True).status
    ('undefined', 'statistical')
    >>> map_trust("Phi", 1.5, "regular", False)
    Trust(status='predicted', reason='')
    """
    if quantity not in QUANTITIES:
        raise ValueError(f"quantity must be one of {QUANTITIES}, got {quantity!r}")
    if _undefined_value(value):
        return Trust(UNDEFINED, "not measurable over the run")
    if quantity == "slow_period" and verdict == "chaotic":
        return Trust(UNDEFINED, "a chaotic orbit has no slow period")
    if beyond_horizon:
        return Trust(STATISTICAL, "past the predictability horizon: the region the orbit fills over the run, not one "
                                  "trajectory's")
    return Trust(PREDICTED)


def closed_form_trust(quantity: str, value: Any, verdict: str | None, K: float, regime_ratio: float | None) -> Trust:
    """The status of the closed form's (the pendulum's) ``quantity`` for a start of chaos ``verdict`` at K = εκ and
    the pendulum's regime parameter R² (``PendulumPrediction.regime_ratio``; NaN or None for ε = 0).

    Examples
    --------
    >>> from rocknroller.analysis.slow.trust import closed_form_trust
    >>> closed_form_trust("slow_period", 150.6, "regular", 0.43, 40.0).status
    'predicted'
    >>> print(closed_form_trust("slow_period", 159.3, "regular", 0.43, 2.0).reason)
    outside the pendulum's regime: R^2 = 2, where its slow period may be off by up to 22%
    """
    if quantity not in QUANTITIES:
        raise ValueError(f"quantity must be one of {QUANTITIES}, got {quantity!r}")
    if _undefined_value(value):
        return Trust(UNDEFINED, "not defined for this start")
    if abs(K) > K_PERIOD_DOUBLING:
        return Trust(UNDEFINED, f"K = {K:.4g} > {K_PERIOD_DOUBLING:g}: past the period doubling, where the closed "
                                "form does not apply")
    if verdict == "chaotic":
        return Trust(UNDEFINED, "the closed form describes a regular libration, and this orbit is chaotic")
    error = pendulum_regime_error(math.nan if regime_ratio is None else regime_ratio)
    if error > REGIME_TOLERANCE:
        return Trust(UNDEFINED, f"outside the pendulum's regime: R^2 = {regime_ratio:.3g}, where its slow period may "
                                f"be off by up to {error:.0%}")
    return Trust(PREDICTED)


def prediction_trust(pred: Any) -> dict[str, Trust]:
    """The status of each of ``QUANTITIES`` of a :class:`~rocknroller.analysis.slow.prediction_result.SlowPrediction`
    (:func:`map_trust`; its horizon is measured by a short direct probe the first time it is asked for).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.slow.trust import prediction_trust
    >>> pred = rr.predict_slow_motion(rr.Body.paper(1e-3), 0.95 * math.pi, math.pi / 4, 200.0, order=1)
    >>> {q: t.status for q, t in prediction_trust(pred).items()}["QR_extent"]
    'predicted'
    """
    verdict = None if pred.chaos is None else pred.chaos.verdict
    try:
        beyond: bool | None = bool(pred.t_end > pred.horizon_estimate().t)
    except ValueError:  # no horizon: ε = 0 from rest, or a periodic orbit
        beyond = None
    return {q: map_trust(q, getattr(pred, q), verdict, beyond) for q in QUANTITIES}
