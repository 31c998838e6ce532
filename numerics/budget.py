"""The total work of a call, estimated before it starts, and the budget past which the work must be asked for.

The limits elsewhere bound one run, one table or one grid (``numerics.integrate``, ``analysis.slow.map.limits``); a call
that makes many of them (an ensemble, an atlas, a table of mpmath points) or runs the slow independent check (DOP853)
for long could still take hours with no sign of it (measured: ``atlas --theta0 0.8pi:0.95pi:3000``, 100 runs
of ``--t-end 1e7``, ``simulate --method scipy --t-end 1e7`` ~5 h, ``table --dps 1000`` on 2000 points).  Such calls
estimate their CPU time from the rates below and refuse past ``budget`` seconds (default ``WORK_BUDGET_SECONDS``),
naming the estimate: ``budget=`` in the API (None: no limit), ``--budget`` on the command line.

The rates are CPU seconds measured on this kind of machine (2 cores), rounded up: an estimate errs on the high side,
by up to 2.5× (4× for mpmath at 120-240 digits), which is what a budget of an hour needs.  A command's estimate counts
all of its work, each part at its rate: the tables not cached (:func:`rocknroller.analysis.slow.work.tables_seconds`),
the map's runs with their tangent vectors and overheads, direct and variational runs with theirs, and its files;
``benchmarks/bench_budget.py commands`` checks the sums against whole commands (estimate/measured 1.3-2.9).
``benchmarks/bench_budget.py`` measures them again beside the constants (at load 1.3: heyoka 9.6e-6 s and DOP853
1.1e-3 s per radian, a release table 1.6 s, a band-chart region table 13.5 s, mpmath points 0.26, 1.3 and 4.7 s at
30, 120 and 240 digits), and the averaged map's cost per θ-maximum at orders 1 and 2.
"""

from __future__ import annotations

import math

from rocknroller.analysis.model.body import float_or_nan

__all__ = ["WORK_BUDGET_SECONDS", "HEYOKA_SECONDS_PER_RADIAN", "HEYOKA_EXTENDED_SECONDS_PER_RADIAN",
           "DOP853_SECONDS_PER_RADIAN", "RELEASE_TABLE_SECONDS",
           "REGION_TABLE_SECONDS", "MAP_SECONDS_PER_MAXIMUM", "MAP_ORDER2_SECONDS_PER_MAXIMUM",
           "EXACT_ORBIT_SECONDS", "PERIOD_DOUBLING_SECONDS", "SLOW_ORBIT_SECONDS", "SECOND_ORDER_TABLE_SECONDS",
           "MAP_TANGENT_FACTOR", "MAP_SETUP_SECONDS", "MAP_RUN_SECONDS", "ATLAS_POINT_SECONDS", "DIRECT_RUN_SECONDS", "WorkBudgetError",
           "check_budget", "check_work", "mp_point_seconds", "format_seconds"]

#: CPU seconds a call may take without being asked for explicitly.
WORK_BUDGET_SECONDS = 3600.0
#: The direct ODE (``simulate``, turning points only) per radian of Λ·t: heyoka 9.6e-6 (1.4e-5 at load 3).
HEYOKA_SECONDS_PER_RADIAN = 1.0e-5
#: The same in 80-bit extended precision (``precision="extended"``): 6.2e-5 measured, 5.6× double.
HEYOKA_EXTENDED_SECONDS_PER_RADIAN = 6.5e-5
#: The same with scipy's DOP853 (the independent check): 1.1e-3 measured, ~100× heyoka's.
DOP853_SECONDS_PER_RADIAN = 1.0e-3
#: One release table (first order, default grid, one process): 1.6-2.1 s measured.
RELEASE_TABLE_SECONDS = 4.0
#: One region table (default grid, one process): the band chart's 13.5 s measured (26 s at load 25).
REGION_TABLE_SECONDS = 30.0
#: The averaged map of order 1 per θ-maximum, with its tangent vector and the run's diagnostics (a release's
#: ``predict_slow_motion``, an atlas point, a portrait orbit): 3.9-4.6e-6 measured (θ0 = 0.95π, 1.5e4 maxima,
#: load 7); the number of maxima of a run is estimated as t_end/T_θ(0) (1.035 × that counted at ε = 5e-3).
MAP_SECONDS_PER_MAXIMUM = 6.0e-6
#: The same at order 2 (the second-order kick besides): 7.8-9.1e-6 measured.
MAP_ORDER2_SECONDS_PER_MAXIMUM = 1.2e-5
#: One second-order release table (order 2's k₂ on a release table's chart, default grid, one process; the release
#: table it stands on not included): 13.5 s measured at θ0 = 0.95π (load 0.7; docs/performance.md: 6.7 s).
SECOND_ORDER_TABLE_SECONDS = 25.0
#: The factor the map's tangent vector (the chaos indicators: ``tangent=True``) puts on its cost per θ-maximum:
#: 1.5-1.6 measured (atlases of 1000-3000 points, t_end 200-5000; benchmarks/bench_chaos_map.py: 1.5-1.8).
MAP_TANGENT_FACTOR = 2.0
#: Making one table ready for the compiled map (once per table and call): ~0.3 s measured (a portrait's first orbits).
MAP_SETUP_SECONDS = 0.4
#: The overhead of one run of the map besides its θ-maxima (the call, its checks, its indicators; a portrait's
#: orbit): below 0.5 ms measured (portraits of 100 orbits of 2000 time units: 0.06-0.13 s in all).
MAP_RUN_SECONDS = 1.0e-3
#: The overhead of one point of an atlas besides its map's θ-maxima (``predict_slow_motion``'s start, the run's
#: diagnostics and its crossings of the critical lines): ~0.27 ms measured (3000 points of 200 time units, 0.31 ms a
#: point in all).
ATLAS_POINT_SECONDS = 5.0e-4
#: The overhead of one direct run besides its radians (the call, its turning points; a horizon probe of 40 rocks is
#: mostly this): ~0.02 s measured (a probe of 40 rocks at θ0 = 0.95π, 1540 radians, takes 0.036-0.040 s).
DIRECT_RUN_SECONDS = 5.0e-2
#: One periodic orbit of the exact one-step map (Newton on direct-ODE steps, ``periodic_orbit(map="exact")``) of
#: period 1; one of period 2 counts twice: 0.17-0.31 s measured for period 1 and 0.48-0.53 s for period 2 at
#: θ0 = 0.9π and 0.95π (0.25-0.32 and 0.89 s at 0.93π before).
EXACT_ORBIT_SECONDS = 0.6
#: The exact map's period doubling ε_pd of one θ0 (``period_doubling``, its release table cached): 2.2-3.2 s measured
#: at θ0 = 0.85π-0.99π (10.3 s at 0.93π in an earlier version).
PERIOD_DOUBLING_SECONDS = 6.0
#: One periodic orbit of the slow map on a continued branch (``continue_orbit``, 111 points; the map's setup,
#: ``MAP_SETUP_SECONDS``, once per θ0 besides): 1.0-1.1 ms measured a point at order 2 (θ0 = 0.9π, 0.95π), 4.7 ms at
#: order 1 with the first call's setup; 1.2 ms before.
SLOW_ORBIT_SECONDS = 3.0e-3


def mp_point_seconds(dps: int) -> float:
    """CPU seconds of one mpmath precession point at ``dps`` digits: 0.3 s · (dps/30)² (measured 0.28, 1.4, 5.0 and
    28 s at 30, 120, 240 and 480 digits; steeper than the square at the top, where points near steady rolling also
    cost more)."""
    return 0.3 * (dps / 30.0) ** 2


class WorkBudgetError(ValueError):
    """A call's estimated work exceeds its budget (raised before any work)."""


def check_budget(budget: float | None) -> float:
    """``budget`` as seconds (None: no limit, +inf), or a ValueError naming it unless it is a number > 0."""
    if budget is None:
        return math.inf
    value = math.nan if isinstance(budget, (str, bytes, bool)) else float_or_nan(budget)  # '10' is text, not seconds
    if not value > 0.0:  # also NaN
        raise ValueError(f"budget must be a number of seconds > 0 (or None: no limit), got budget={budget!r}")
    return value


def format_seconds(seconds: float) -> str:
    """A duration for people: 45 s, 12 min, 3.2 h, 5.1 days; below 10 s two significant digits (4.5 s, 0.0032 s,
    1e-300 s), so that a small estimate or budget never reads as 0 s."""
    if seconds < 10.0:
        return f"{seconds:.2g} s"
    if seconds < 120.0:
        return f"{seconds:.0f} s"
    if seconds < 7200.0:
        return f"{seconds / 60.0:.0f} min"
    if seconds < 172800.0:
        return f"{seconds / 3600.0:.1f} h"
    return f"{seconds / 86400.0:.1f} days"


def check_work(seconds: float, what: str, budget: float | None) -> None:
    """Refuse ``what`` (a phrase: "100 direct runs of 1e7 time units") when its estimated CPU ``seconds`` exceed
    ``budget`` (None: no limit), naming the estimate and how to ask for it.

    Raises
    ------
    WorkBudgetError
        A ValueError, before any work.
    """
    limit = check_budget(budget)
    if seconds > limit:
        raise WorkBudgetError(
            f"{what} would take about {format_seconds(seconds)} of CPU (estimated from the rates measured on this "
            f"kind of machine, rocknroller.numerics.budget), over the budget of {format_seconds(limit)}; to run it "
            f"anyway give budget=SECONDS above the estimate, or make it smaller")
