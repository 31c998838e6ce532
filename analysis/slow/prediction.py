"""The prediction of the slow (Q_R, Q_J) motion of the asymmetric rock'n'roller by the ε-averaged map, to first or
second order in ε = (I2 − I1)/I1.  It holds :func:`predict_slow_motion`, for a release from rest at (θ0, ψ0) with
0 < θ0 ≤ 0.999π or any initial state with velocity, at ``order`` 1 or 2, and its result :class:`SlowPrediction`
with the diagnostics of the series of maxima: slow period, extents, azimuth span Φ, :func:`line_slope`, and the
critical regions and crossings of the lines Q_J,0^crit and Q_J,π^crit (:func:`critical_regions`; paper eqs.
QJcrit_0, QJcrit_pi).  It re-exports the public names of the stages below it.

The motion is sampled at successive maxima of θ.  The slow variables are Q = (Q_R, Q_J)
(paper eq. JelletandRouth_Qtys) and the phase Θ = 2ψ mod 2π (ψ itself jumps by about ±π at each
passage near θ = 0; 2ψ does not).  The energy E is exact and fixed by the start (paper eq. energy): the release
tables belong to (body, θ0) with E = U(θ0; 0, 0), the energy of the body released from rest at θ0, the region
tables to (body, E).

One step (maximum n → maximum n+1), to first order in ε at fixed Q_n:

    Q_{n+1} = Q_n + ε ΔQ(Q_n, Θ_n),     Θ_{n+1} = Θ_n + W(Q_n) + ε ΔΘ(Q_n, Θ_n),
    t_{n+1} = t_n + T_θ(Q_n) + ε Δt(Q_n, Θ_n),   φ_{n+1} = φ_n + Δφ(Q_n) + ε Δφ₁(Q_n, Θ_n),

with T_θ, W = 2(Δψ − π) and Δφ those of the symmetric body (from the quadratures,
``rocknroller.analysis.routh.quadrature``, for the release tables; from the variational orbits themselves for the
region tables) and the first-order terms from the symmetric orbit integrated together with its first-order
variational equations in ε (:mod:`rocknroller.analysis.slow.map.orbit`; one orbit per Q with three ε-responses, from
three spin angles, gives the harmonics 0 and 1 of Θ_n).

Reversible form.  The exact map is reversible under (Q, Θ) → (−Q, Θ) (time reversal).  The same
first-order data are written as drift–kick–drift: a half twist Θ += W(Q)/2, a kick
(Q, Θ) += ε k((x + x')/2) by the implicit midpoint rule, and a half twist W(Q')/2, with

    k_Q(Q, Θ') = ΔQ(Q, Θ' − W/2),   k_Θ(Q, Θ') = ΔΘ(Q, Θ' − W/2) − ½ ∇W·k_Q(Q, Θ'),

k_Q even and k_Θ odd in Q (enforced on the symmetric grid).  The ε ΔΘ term is kept: it is the phase
change of the part of the kick received before the passage near θ = 0, multiplied by the large ∂W/∂Q.
To second order (``order=2``) the kick is k₁ + ε k₂ (:mod:`rocknroller.analysis.slow.map.second_order`), and the map
stays reversible.

Starts.  A release from rest at θ0 in ``THETA0_RANGE`` = [0.75π, 0.999π] runs on the release tables of (body, θ0).
A release below 0.75π, and any initial state (an ``EulerState``, with velocity), is first carried to its first
maximum of θ by a short direct integration (:func:`rocknroller.analysis.slow.map.family.first_maximum`; a release from
rest is its own first maximum), and runs on the region tables of its energy
(:mod:`rocknroller.analysis.slow.map.region`).  Order 2 adds the second-order tables on the same chart: per (body, θ0)
for a release table, per (body, E) on the default region tables.  For ε = 0 a release on the release tables is
returned as the exact pure rocking (``SlowPrediction.pure_rocking``).

Stages.  The coefficient functions are tabulated once per (body, θ0) or (body, energy) and cached
(:mod:`rocknroller.analysis.slow.map.chart`, :mod:`rocknroller.analysis.slow.map.table`, and
:mod:`rocknroller.analysis.slow.map.region` for whole regions); the map is iterated on them in compiled code
(:mod:`rocknroller.analysis.slow.map.compiled_map`); this module predicts the slow motion of a start
(:func:`predict_slow_motion`) and its diagnostics.  The stages' public names, and the limits' of
:mod:`rocknroller.analysis.slow.map.limits`, are re-exported here.

Range.  The release tables are built and validated for releases 0.75π ≤ θ0 ≤ 0.999π (``THETA0_RANGE``;
docs/averaging.md, "Releases from rest: the range of θ0"); the region tables need an energy below that of the upright
position and cover
distances (E − min U)/E ≥ 0.05 to steady rolling (docs/averaging.md, "Starts with velocity: the region tables").
One run produces at most ``MAX_MAXIMA`` maxima (:func:`max_t_end`).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import replace
from typing import TYPE_CHECKING, Callable

import numpy as np

from rocknroller.analysis.model.body import Body, as_float
from rocknroller.analysis.model.diagnostics import azimuth_span, slow_period, span, unwrap_phase
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.slow.dynamics.chaos import (PROBE_ROCKS, HorizonProbe, MapChaos, indicator_span,
                                                      map_indicators)
from rocknroller.analysis.slow.map.chart import TABLE_FUNCTIONS, SlowMapTable  # noqa: F401 (re-exported)
from rocknroller.analysis.slow.map.compiled_map import SlowSeries, centre_period, iterate_slow_map
from rocknroller.analysis.slow.map.family import first_maximum, rest_energy
# The stages' public names are re-exported (``prediction.load_or_build_table`` etc., module docstring); pyflakes
# reports those this module does not use itself as unused.
from rocknroller.analysis.slow.map.limits import (K_PERIOD_DOUBLING, MAX_MAXIMA, THETA0_RANGE,  # noqa: F401
                                                  AveragingRangeError, AveragingValidityWarning, ChartWidthError,
                                                  check_angle, check_map_theta0, check_release_theta0, check_t_end, default_order,
                                                  eps_period_doubling, t_end_limit)
from rocknroller.analysis.slow.map.table import (REGION_TABLE_ACCURACY, TableNotCachedError, build_table,  # noqa: F401
                                                 load_or_build_table)
from rocknroller.analysis.slow.work import pure_rocking_period
from rocknroller.analysis.slow.prediction_result import (SlowPrediction, critical_regions, line_slope,  # noqa: F401
                                                         rocks_per_region)

if TYPE_CHECKING:
    from rocknroller.analysis.slow.map.chart import SecondOrderTable


#: Defined here (the result, ``SlowPrediction``, and its readers are :mod:`rocknroller.analysis.slow.prediction_result`'s,
#: importable from here too); the tables' and the map's public names (``SlowMapTable``, ``build_table``, ``load_or_build_table``,
#: ``iterate_slow_map``, ...) and the limits' (``THETA0_RANGE``, ``AveragingRangeError``, ...) are importable from
#: here too, and documented in their own modules.
__all__ = [
    "max_t_end",
    "predict_slow_motion",
    "releases_on_region_tables",
    "default_order",
]


# ----------------------------------------------------------------------------- small helpers
def max_t_end(body: Body, theta0: float) -> float:
    """Largest t_end accepted by :func:`predict_slow_motion` for (body, θ0): ``MAX_MAXIMA`` · T_θ(0)/2, with T_θ(0)
    the time between maxima of pure rocking (quadrature)."""
    theta0 = check_map_theta0(theta0)
    sym = body.symmetric()
    return t_end_limit(pure_rocking_period(sym, rest_energy(sym, theta0)))


def predict_slow_motion(body: Body, theta0: float | EulerState, psi0: float | None = None,
                        t_end: float = 1000.0, *,
                        table: SlowMapTable | None = None, build: bool = True, order: int | None = None,
                        second: "SecondOrderTable | None" = None, progress: bool | None = None,
                        indicators: bool = True, span: float | None = None) -> SlowPrediction:
    """Predict the slow (Q_R, Q_J) motion of ``body`` released from rest at θ0 with spin angle ψ0, or from any
    initial state.

    Parameters
    ----------
    body : Body
        The asymmetric body (ε = body.epsilon ≥ 0).
    theta0 : float or EulerState
        Release tilt, 0 < θ0 ≤ 0.999π: in ``THETA0_RANGE`` = [0.75π, 0.999π] the release tables (validated
        against the direct ODE, docs/averaging.md); below, the region tables of the release's energy (as for an
        EulerState from rest); other values are refused (ValueError).
        Or an initial state (the one ``simulate`` takes): it is carried to its first θ-maximum by a short
        direct integration (:func:`rocknroller.analysis.slow.map.family.first_maximum`) and the map is iterated from
        there on the region tables of its energy (:mod:`rocknroller.analysis.slow.map.region`); then ``psi0`` is
        not given and ``table`` is a region table of that energy, if given.
    psi0 : float
        Release spin angle (Θ0 = 2ψ0).
    t_end : float
        Time span, 0 < t_end ≤ ``MAX_MAXIMA`` · T_θ(0)/2 (:func:`max_t_end`; 6.6e6 at θ0 = 0.95π): checked
        before anything is built.
    table : SlowMapTable, optional
        Precomputed tables of (body, θ0); by default :func:`load_or_build_table`.
    build : bool
        Build the tables if they are not cached (else ValueError).
    order : {1, 2}, optional
        The map's order in ε.  Order 2 adds the second-order kick k₂ (:mod:`rocknroller.analysis.slow.map.second_order`,
        tables built once per (body, θ0) for a release in ``THETA0_RANGE``, or per (body, E) on the default region
        tables for any other start, and cached).  Default: :func:`default_order`, the same as ``rocknroller slow``'s
        (2 for a release from rest in ``THETA0_RANGE``, 1 for any other start; the costs are stated there).
    second : SecondOrderTable, optional
        Precomputed second-order tables of (body, θ0), or of (body, E) for a start on the region tables.
    progress : bool or None
        Tables built here (seconds to a minute each; docs/slow_howto.md) show a tqdm bar on stderr that names them
        and the time left; None: only if stderr is a terminal.  Tables from memory or the disk cache show none.
    indicators : bool
        Carry a tangent vector along the map and give the prediction its chaos indicators (``chaos``, ``regular``)
        and its predictability horizon (:meth:`SlowPrediction.horizon`); ~1.5× the map's own cost
        (benchmarks/bench_chaos_map.py).
    span : float, optional
        The time over which the indicators are measured, ≥ t_end: by default max(t_end, ``SPAN_ROCKS`` · T_θ(0))
        (:func:`rocknroller.analysis.slow.dynamics.chaos.indicator_span`; ~1000 rocks, whatever t_end is); t_end itself for
        indicators over the run only (an atlas's, compared with the direct motion's over the same t_end).

    Returns
    -------
    SlowPrediction
        For ε = 0 (Routh's sphere) the exact pure rocking (``pure_rocking``): no slow motion, Q = 0 on
        both critical lines, no region runs; the slow period and line slope are None.

    Raises
    ------
    ValueError
        θ0, ψ0, t_end or order out of range (naming it), or a table for another (body, θ0).

    Warns
    -----
    AveragingValidityWarning
        If K = ε κ > 4 (pure rocking about the stable axis has period-doubled).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> pred = rr.predict_slow_motion(body, 0.95 * math.pi, math.pi / 4, 200.0, order=1)
    >>> print(f"K = {pred.K:.4f}, maxima: {pred.series.t.size}")
    K = 0.4262, maxima: 15
    >>> rocking = rr.predict_slow_motion(rr.Body.paper(), 0.95 * math.pi, math.pi / 4, 200.0, order=1)
    >>> print(rocking.pure_rocking, rocking.slow_period)
    True None
    """
    body.require_gravity("the slow-motion prediction")
    requested = order
    if order is None:
        order = default_order(theta0)
    if order not in (1, 2) or isinstance(order, bool):
        raise ValueError(f"order must be 1 or 2, got order={order!r}")
    if isinstance(theta0, EulerState):
        if psi0 is not None:
            raise ValueError("psi0 is part of the initial state: give either (theta0, psi0) or an EulerState")
        return _predict_from_state(body, theta0, t_end, table=table, build=build, order=order, second=second,
                                   progress=progress, indicators=indicators, span=span)
    if psi0 is None:
        raise ValueError("psi0 must be given with a release angle theta0")
    theta0 = check_release_theta0(theta0)
    if table is None and releases_on_region_tables(theta0):
        return _predict_from_state(body, EulerState(float(theta0), 0.0, float(psi0)), t_end, table=None, build=build,
                                   order=order, second=second, progress=progress, indicators=indicators,
                                   span=span)
    theta0 = check_map_theta0(theta0)
    eps, psi0 = body.epsilon, as_float("psi0", psi0)
    psi0 = check_angle("psi0", psi0)
    own_table = table is None  # a release table of the caller's is used as given, without the region tables' fallback
    if table is None:
        sym = body.symmetric()
        check_t_end(t_end, pure_rocking_period(sym, rest_energy(sym, theta0)))
        from rocknroller.analysis.slow.map.tables_at_once import release_tables

        table, span_second = release_tables(body, theta0, order, build=build, progress=progress)
        second = span_second if second is None else second
    elif abs(table.theta0 - theta0) > 1e-15:
        raise ValueError(f"the table is for theta0={table.theta0!r}, not {theta0!r}")
    elif table.body != body.symmetric():
        raise ValueError(f"the table is for the body {table.body.describe()}, not {body.symmetric().describe()}")
    K = eps * table.kappa
    _warn_validity(eps, table)
    if eps == 0.0:  # Routh's sphere from rest: rocking in a fixed vertical plane, Q ≡ 0, ψ and φ mod π fixed
        from rocknroller.analysis.criticality.lines import ON_BOTH

        T0 = centre_period(table)
        t = T0 * np.arange(1, int(check_t_end(t_end, T0) // T0) + 1, dtype=float)
        zero = np.zeros_like(t)
        return SlowPrediction(
            eps=eps, theta0=theta0, psi0=psi0, t_end=float(t_end), K=0.0, slow_period=None, QR_extent=0.0,
            QJ_extent=0.0, Phi=0.0, line_slope=None,
            series=SlowSeries(t=t, QR=zero, QJ=zero.copy(), Theta=np.full_like(t, 2.0 * psi0), phi=zero.copy()),
            regions=np.full(t.size, ON_BOTH, dtype=object), region_runs=[], crossings=[], pure_rocking=True,
            order=order, body=table.body)
    if order == 2:
        from rocknroller.analysis.slow.map.second_order import load_or_build_second_order_table

        if second is None:
            second = load_or_build_second_order_table(body, theta0, build=build, progress=progress)
        elif abs(second.theta0 - theta0) > 1e-15 or second.E0 != table.E0:
            raise ValueError(f"the second-order table is for theta0={second.theta0!r}, not {theta0!r}")
    second = second if order == 2 else None
    T0 = centre_period(table)
    try:
        run = _run(lambda t: iterate_slow_map(table, eps, psi0, t, second=second, tangent=indicators), t_end, T0,
                   indicators, span)
    except ChartWidthError as exc:
        if not own_table:
            raise
        # the orbit spreads across the kick direction beyond the release tables (ε large): the region tables of its
        # energy, at the order asked for, or their default
        start = EulerState(theta0, 0.0, psi0)
        warnings.warn(f"{exc}: predicted on the region tables of its energy instead", AveragingValidityWarning,
                      stacklevel=2)
        return _predict_from_state(body, start, t_end, table=None, build=build,
                                   order=default_order(start) if requested is None else order, progress=progress,
                                   indicators=indicators, span=span)
    chaos, probe = _indicators(body, EulerState(float(theta0), 0.0, psi0), run, run, T0, indicators)
    return replace(_prediction(eps, theta0, psi0, t_end, K, run.until(t_end), table.body), order=order, chaos=chaos,
                   horizon_probe=probe)


def _run(iterate: Callable[[float], SlowSeries], t_end: float, T0: float, indicators: bool,
         span: float | None) -> SlowSeries:
    """The map's run from its start over the indicators' span (``indicator_span``, or ``span``; t_end without
    indicators), or over t_end where the orbit leaves the tables after t_end and before the span's end (the span is
    then t_end)."""
    if span is not None and not (math.isfinite(span) and span >= t_end):
        raise ValueError(f"span must be a time >= t_end, got span={span!r}")
    span = float(t_end) if not indicators else indicator_span(t_end, T0) if span is None else float(span)
    try:
        return iterate(span)
    except AveragingRangeError:
        if span == t_end:
            raise
        return iterate(float(t_end))


def _indicators(body: Body, start: EulerState, run: SlowSeries, series: SlowSeries, T0: float,
                indicators: bool) -> tuple[MapChaos | None, HorizonProbe | None]:
    """The indicators of the map's ``run`` (from its start, over its span) and the probe of its horizon along
    ``series`` (the maxima from the start); (None, None) without indicators."""
    chaos = map_indicators(run.t, run.log_growth) if indicators and run.log_growth is not None else None
    return chaos, None if chaos is None else HorizonProbe(body, start, series, chaos, PROBE_ROCKS * T0)


def _warn_validity(eps: float, table: SlowMapTable) -> None:
    """AveragingValidityWarning if K = ε κ exceeds 4 or a region table interpolates worse than its accuracy."""
    K = eps * table.kappa
    if abs(K) > K_PERIOD_DOUBLING:
        warnings.warn(
            f"K = eps*kappa = {K:.3g} > {K_PERIOD_DOUBLING:g}: pure rocking about the stable principal axis is "
            f"unstable (period doubling at eps = 4/kappa = {eps_period_doubling(table.kappa):.4g} to first order); the "
            f"first-order "
            f"averaging is expected to hold for K < {K_PERIOD_DOUBLING:g}", AveragingValidityWarning, stacklevel=3)
    if table.delta_min > 0.0 and table.interp_error > REGION_TABLE_ACCURACY:
        from rocknroller.analysis.slow.map.region import accuracy_cause

        warnings.warn(
            f"the region tables of E={table.E0:.6g} interpolate the map's coefficients only to "
            f"{table.interp_error:.1e} (> {REGION_TABLE_ACCURACY:g}), and the prediction carries that error: "
            f"{accuracy_cause(table)}",
            AveragingValidityWarning, stacklevel=3)


def releases_on_region_tables(theta0: float) -> bool:
    """True for release angles 0 < θ0 < ``THETA0_RANGE[0]``, which the region tables serve (the release tables'
    rectangle would leave the region of motion there)."""
    return isinstance(theta0, (int, float)) and 0.0 < float(theta0) < THETA0_RANGE[0]


def _prediction(eps: float, theta0: float, psi0: float, t_end: float, K: float, series: SlowSeries,
                sym: Body, start: EulerState | None = None) -> SlowPrediction:
    """The diagnostics of a series of maxima."""
    regions, runs, crossings = critical_regions(series.QR, series.QJ, series.t, sym)
    return SlowPrediction(
        eps=eps, theta0=theta0, psi0=float(psi0), t_end=float(t_end), K=K,
        slow_period=slow_period(series.t, series.Theta) if series.t.size >= 3 else None,
        QR_extent=span(series.QR), QJ_extent=span(series.QJ), Phi=azimuth_span(series.phi),
        line_slope=line_slope(series.QR, series.QJ),
        series=series, regions=regions, region_runs=runs, crossings=crossings, start=start, body=sym)


def _predict_from_state(body: Body, start: EulerState, t_end: float, *, table: SlowMapTable | None,
                        build: bool, order: int = 1, second: "SecondOrderTable | None" = None,
                        progress: bool | None = None, indicators: bool = True,
                        span: float | None = None) -> SlowPrediction:
    """predict_slow_motion from an initial state: its first maximum, then the map on the region tables (and for
    order 2 the second-order tables on their chart)."""
    from rocknroller.analysis.routh.steady_rolling import boundary_distance
    from rocknroller.analysis.slow.map.region import DELTA_MIN_DEFAULT, load_or_build_region_table, region_options

    t_end = float(t_end)
    if not (math.isfinite(t_end) and t_end > 0.0):
        raise ValueError(f"t_end must be a finite number > 0, got t_end={t_end!r}")
    fm = first_maximum(body, start)
    if fm.t >= t_end:
        raise ValueError(f"t_end={t_end!r} ends before the first maximum of theta (t = {fm.t:.6g})")
    if table is None:
        try:
            table = load_or_build_region_table(body, fm.E, build=False)
        except TableNotCachedError:
            # before a build of seconds: a start nearer steady rolling than the tables reach (with tables at hand the
            # map itself says so, naming the distance, and this 7 ms check is skipped), and a t_end over the limit
            delta = float(boundary_distance(body, fm.E, fm.QR, fm.QJ))
            if delta < DELTA_MIN_DEFAULT:
                raise AveragingRangeError(
                    f"the start's first maximum of theta is at distance (E - min U)/E = {delta:.3g} from steady "
                    f"rolling (Q=({fm.QR:.6g}, {fm.QJ:.6g}), E={fm.E:.6g}); the region tables cover distances >= "
                    f"{DELTA_MIN_DEFAULT:g}: nearer steady rolling the oscillation of theta is too small to average "
                    "over; run this start by the direct ODE (rocknroller simulate)") from None
            # the map's limit on t_end (checked again on the table), from T_θ at Q = 0 of this energy
            check_t_end(t_end - fm.t, pure_rocking_period(body.symmetric(), fm.E))
            if not build:
                raise
            table = load_or_build_region_table(body, fm.E, build=True, progress=progress)
    elif abs(table.E0 - fm.E) > 8.0 * math.ulp(fm.E) or table.delta_min == 0.0:  # E from two formulas: rounding
        raise ValueError(f"the table is not the region table of this start's energy E={fm.E!r}")
    elif table.body != body.symmetric():
        raise ValueError(f"the table is for the body {table.body.describe()}, not {body.symmetric().describe()}")
    if order == 2:
        from rocknroller.analysis.slow.map.second_order import load_or_build_second_order_region_table

        if (table.coef.shape[1:] != region_options(body, fm.E)[1:]  # cheap first: another grid
                or not table.same_chart(load_or_build_region_table(body, fm.E, build=build, progress=progress))):
            raise ValueError("order=2 uses the second-order tables on the default region tables of the start's "
                             "energy (axis 'auto', the default grid); this table has another chart or grid")
        if second is None:
            second = load_or_build_second_order_region_table(body, fm.E, build=build, progress=progress)
        elif second.E0 != table.E0:
            raise ValueError(f"the second-order table is for E={second.E0!r}, not this start's E={fm.E!r}")
    eps = body.epsilon
    _warn_validity(eps, table)
    second = second if order == 2 else None
    T0 = centre_period(table)
    rest = _run(lambda t: iterate_slow_map(table, eps, fm.psi, t - fm.t, Q0=(fm.QR, fm.QJ), phi0=fm.phi,
                                           second=second, tangent=indicators), t_end, T0, indicators, span)
    first = [fm.t > 0.0]  # a start that is itself a maximum is not a sample (the ODE reports none at t = 0)
    series = SlowSeries(t=np.concatenate([[fm.t][: sum(first)], fm.t + rest.t]),
                        QR=np.concatenate([[fm.QR][: sum(first)], rest.QR]),
                        QJ=np.concatenate([[fm.QJ][: sum(first)], rest.QJ]),
                        Theta=unwrap_phase(np.concatenate([[2.0 * fm.psi][: sum(first)], rest.Theta])),
                        phi=np.concatenate([[fm.phi][: sum(first)], rest.phi]),
                        log_growth=None if rest.log_growth is None
                        else np.concatenate([[0.0][: sum(first)], rest.log_growth]))
    chaos, probe = _indicators(body, start, rest, series, T0, indicators)
    return replace(_prediction(eps, float(start.theta), float(start.psi), t_end, eps * table.kappa,
                               series.until(t_end), table.body, start=start), order=order, chaos=chaos,
                   horizon_probe=probe)
