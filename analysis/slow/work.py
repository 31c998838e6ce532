"""The work of many runs of the averaged map, estimated before any of them starts (:mod:`rocknroller.numerics.budget`).

One run of the map is bounded (``MAX_MAXIMA`` θ-maxima, :mod:`rocknroller.analysis.slow.map.limits`), but an ensemble, an
atlas or a portrait makes thousands of them: ``map_ensemble`` of 10 000 releases over 6.6e6 time units is ~5e9 maxima,
hours of CPU.  A run from rest at θ0 over t_end makes about t_end/T_θ(0) maxima, T_θ(0) the time between maxima of the
pure rocking at the release's energy (the quadrature of :func:`rocknroller.analysis.slow.map.orbit.symmetric_data`, ~10 ms);
each costs ``MAP_SECONDS_PER_MAXIMUM`` (order 1) or ``MAP_ORDER2_SECONDS_PER_MAXIMUM`` (order 2) of CPU, times
``MAP_TANGENT_FACTOR`` with the tangent vector (the chaos indicators), and each run ``MAP_RUN_SECONDS`` besides
(:func:`map_runs_seconds`).  The tables a call would build are counted where they are not cached, found without
building or reading them (:func:`tables_seconds`).
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body, as_float
from rocknroller.analysis.slow.map.family import rest_energy
from rocknroller.analysis.slow.map.orbit import symmetric_data
from rocknroller.analysis.slow.map.limits import THETA0_RANGE
from rocknroller.numerics.budget import (MAP_ORDER2_SECONDS_PER_MAXIMUM, MAP_RUN_SECONDS, MAP_SECONDS_PER_MAXIMUM,
                                         MAP_SETUP_SECONDS, MAP_TANGENT_FACTOR, REGION_TABLE_SECONDS,
                                         RELEASE_TABLE_SECONDS, SECOND_ORDER_TABLE_SECONDS, check_work)

__all__ = ["MAX_PERIOD_KNOTS", "pure_rocking_period", "rocking_period", "map_maxima", "map_seconds",
           "check_map_work", "tables_seconds", "map_runs_seconds"]

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


def tables_seconds(body: Body, theta0: ArrayLike, order: int = 1) -> tuple[float, str]:
    """The estimated CPU seconds of building the map's tables at each distinct θ0 of ``theta0`` that are not cached
    (in memory or in the disk cache, ``ROCKNROLLER_CACHE``; found without building or reading them), and a phrase
    counting them: a release table (``RELEASE_TABLE_SECONDS``) for θ0 in ``THETA0_RANGE``, the region tables of the
    release's energy (``REGION_TABLE_SECONDS``) below it, and at ``order`` 2 a second-order table
    (``SECOND_ORDER_TABLE_SECONDS``) on each release table; none in ``THETA0_RANGE`` where the tables over energy of
    the body are cached (``rocknroller warm --tables``).

    Examples
    --------
    >>> import math, os, tempfile
    >>> import rocknroller as rr
    >>> saved = os.environ.get("ROCKNROLLER_CACHE")
    >>> os.environ["ROCKNROLLER_CACHE"] = tempfile.mkdtemp()  # an empty cache: every table is to be built
    >>> seconds, what = tables_seconds(rr.Body.paper(5e-3), [0.95 * math.pi], order=2)
    >>> print(seconds, "|", what)
    29.0 | 1 release, 0 region and 1 second-order tables to build
    >>> if saved is None:
    ...     del os.environ["ROCKNROLLER_CACHE"]
    ... else:
    ...     os.environ["ROCKNROLLER_CACHE"] = saved
    """
    from rocknroller.analysis.slow.map.region import region_table_cached
    from rocknroller.analysis.slow.map.second_order import build_second_order_table
    from rocknroller.analysis.slow.map.table import build_table, is_cached
    from rocknroller.analysis.slow.map.tables_at_once import energy_tables_cached

    sym = body.symmetric()
    n_release = n_region = n_second = 0
    over_energy = energy_tables_cached(sym)
    for t0 in np.unique(np.atleast_1d(np.asarray(theta0, float))):
        if t0 < THETA0_RANGE[0]:
            n_region += not region_table_cached(sym, rest_energy(sym, float(t0)))
            continue
        if over_energy:  # the tables over energy serve every release angle of THETA0_RANGE
            continue
        n_release += not is_cached(build_table, sym, float(t0))
        n_second += order == 2 and not is_cached(build_second_order_table, sym, float(t0))
    seconds = (n_release * RELEASE_TABLE_SECONDS + n_region * REGION_TABLE_SECONDS
               + n_second * SECOND_ORDER_TABLE_SECONDS)
    if order != 2:
        return seconds, f"{n_release} release and {n_region} region tables to build"
    return seconds, f"{n_release} release, {n_region} region and {n_second} second-order tables to build"


def map_runs_seconds(body: Body, theta0: ArrayLike, runs: int, t_end: float, order: int, *, tangent: bool = False,
                     indicator_span: bool = False, per_run: float = MAP_RUN_SECONDS) -> tuple[float, float]:
    """(estimated CPU seconds, θ-maxima) of ``runs`` runs of the map of ``order`` from each θ0 of ``theta0``: the runs'
    θ-maxima (:func:`map_maxima`) at ``MAP_SECONDS_PER_MAXIMUM`` (order 2: ``MAP_ORDER2_SECONDS_PER_MAXIMUM``), times
    ``MAP_TANGENT_FACTOR`` with the ``tangent`` vector, ``per_run`` seconds a run, and ``MAP_SETUP_SECONDS`` once per
    distinct θ0 (its tables made ready for the compiled map).  Each run spans t_end, or with ``indicator_span`` the
    chaos indicators' span max(t_end, ``SPAN_ROCKS`` · T_θ(0))
    (:func:`rocknroller.analysis.slow.dynamics.chaos.indicator_span`), over which ``predict_slow_motion`` runs the
    map by default.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(5e-3)
    >>> plain = map_runs_seconds(body, [0.95 * math.pi], 10, 100.0, 1)
    >>> chaos = map_runs_seconds(body, [0.95 * math.pi], 10, 100.0, 1, tangent=True, indicator_span=True)
    >>> print(chaos[0] > plain[0], round(chaos[1] / plain[1]))
    True 133
    """
    from rocknroller.analysis.slow.dynamics.chaos import SPAN_ROCKS

    th = np.atleast_1d(np.asarray(theta0, float))
    periods = float(t_end) / map_maxima(body, th, float(t_end))  # T_θ(0) of each θ0, as map_maxima takes it
    spans = np.maximum(float(t_end), SPAN_ROCKS * periods) if indicator_span else np.full(th.size, float(t_end))
    n = float(np.sum(spans / periods)) * runs
    seconds = map_seconds(n, order) * (MAP_TANGENT_FACTOR if tangent else 1.0)
    return seconds + th.size * runs * per_run + np.unique(th).size * MAP_SETUP_SECONDS, n
