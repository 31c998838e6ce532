"""The work of many runs of the averaged map, estimated before any of them starts (:mod:`rocknroller.numerics.budget`).

One run of the map is bounded (``MAX_MAXIMA`` θ-maxima, :mod:`rocknroller.analysis.slow.map.limits`), but an ensemble, an
atlas or a portrait makes thousands of them: ``map_ensemble`` of 10 000 releases over 6.6e6 time units is ~5e9 maxima,
hours of CPU.  A run from rest at θ0 over t_end makes about t_end/T_θ(0) maxima, T_θ(0) the time between maxima of the
pure rocking at the release's energy (the quadrature of :func:`rocknroller.analysis.slow.map.orbit.symmetric_data`, ~10 ms);
each costs ``MAP_SECONDS_PER_MAXIMUM`` (order 1) or ``MAP_ORDER2_SECONDS_PER_MAXIMUM`` (order 2) of CPU.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body, as_float
from rocknroller.analysis.slow.map.family import rest_energy
from rocknroller.analysis.slow.map.orbit import symmetric_data
from rocknroller.numerics.budget import MAP_ORDER2_SECONDS_PER_MAXIMUM, MAP_SECONDS_PER_MAXIMUM, check_work

__all__ = ["MAX_PERIOD_KNOTS", "pure_rocking_period", "rocking_period", "map_maxima", "map_seconds",
           "check_map_work"]

#: Most release angles at which T_θ(0) is computed for one estimate; a longer grid uses these as knots (below).
MAX_PERIOD_KNOTS = 16


@functools.lru_cache(maxsize=256)
def pure_rocking_period(sym: Body, E: float) -> float:
    """T_θ(0), the time between θ-maxima of pure rocking (Q = 0) of the symmetric body ``sym`` at energy E
    (quadrature, ~10 ms; remembered)."""
    return float(symmetric_data(sym, E, 0.0, 0.0)[0])


def rocking_period(body: Body, theta0: float) -> float:
    """T_θ(0), the time between θ-maxima of the pure rocking released from rest at θ0 (0 < θ0 < π), of the body's
    symmetric member (:func:`pure_rocking_period` at the release's energy)."""
    sym = body.symmetric()
    return pure_rocking_period(sym, rest_energy(sym, float(theta0)))


def map_maxima(body: Body, theta0: ArrayLike, t_end: float) -> NDArray[np.float64]:
    """The estimated number of θ-maxima of a run of the map from rest at each θ0 over t_end: t_end/T_θ(0).

    T_θ(0) grows with the amplitude θ0 (towards the upright equilibrium it diverges), so for a grid of more than
    ``MAX_PERIOD_KNOTS`` distinct θ0 each takes the period at the largest of ``MAX_PERIOD_KNOTS`` knots (quantiles
    of the grid, the smallest θ0 among them) at or below it: an estimate on the high side, at a bounded cost.
    """
    th = np.atleast_1d(np.asarray(theta0, float))
    distinct = np.unique(th)
    knots = distinct if distinct.size <= MAX_PERIOD_KNOTS else \
        distinct[np.linspace(0, distinct.size - 1, MAX_PERIOD_KNOTS).astype(int)]
    periods = np.array([rocking_period(body, float(t)) for t in knots])
    at = np.clip(np.searchsorted(knots, th, side="right") - 1, 0, knots.size - 1)
    return float(t_end) / periods[at]


def map_seconds(n_maxima: float, order: int) -> float:
    """CPU seconds of ``n_maxima`` θ-maxima of the map of ``order`` (1 or 2), tangent vector included."""
    return float(n_maxima) * (MAP_ORDER2_SECONDS_PER_MAXIMUM if order == 2 else MAP_SECONDS_PER_MAXIMUM)


def check_map_work(body: Body, theta0: ArrayLike, runs: int, t_end: float, order: int, what: str,
                   budget: float | None) -> float:
    """Refuse ``runs`` runs of the map from rest at each θ0 of ``theta0`` over t_end (``what``: "an ensemble of 10000
    releases") when their estimated CPU time exceeds ``budget`` (None: no limit); returns the estimated maxima.

    Raises
    ------
    ValueError
        t_end not a finite number > 0.
    WorkBudgetError
        A ValueError naming the estimate, before any work.
    """
    t_end = as_float("t_end", t_end)
    if not 0.0 < t_end < math.inf:  # also NaN; each run checks its own upper limit
        raise ValueError(f"t_end must be a finite number > 0, got t_end={t_end!r}")
    n = float(np.sum(map_maxima(body, theta0, t_end))) * runs
    check_work(map_seconds(n, order), f"{what}, about {n:.2g} theta-maxima of the order-{order} map,", budget)
    return n
