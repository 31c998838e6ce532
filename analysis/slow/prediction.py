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
variational equations in ε (:mod:`rocknroller.analysis.slow.map.orbit`; three orbits per Q give the harmonics 0 and 1
of Θ_n).

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

import functools
import math
import warnings
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Callable

import numpy as np
from numpy.typing import ArrayLike

from rocknroller.analysis.model.body import Body, as_float
from rocknroller.analysis.model.diagnostics import azimuth_span, slow_period, span, unwrap_phase
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.routh.reduction import u_ends
from rocknroller.analysis.slow.dynamics.chaos import (HORIZON_FRACTION, PROBE_ROCKS, Horizon, HorizonProbe, MapChaos,
                                            indicator_span, map_indicators)
from rocknroller.analysis.slow.map.chart import TABLE_FUNCTIONS, SlowMapTable  # noqa: F401 (re-exported)
from rocknroller.analysis.slow.map.compiled_map import SlowSeries, centre_period, iterate_slow_map
from rocknroller.analysis.slow.map.family import first_maximum, rest_energy
# The stages' public names are re-exported (``prediction.load_or_build_table`` etc., module docstring); pyflakes
# reports those this module does not use itself as unused.
from rocknroller.analysis.slow.map.limits import (K_PERIOD_DOUBLING, MAX_MAXIMA, THETA0_RANGE,  # noqa: F401
                                                  AveragingRangeError, AveragingValidityWarning, ChartWidthError,
                                                  check_map_theta0, check_release_theta0, check_t_end,
                                                  eps_period_doubling, t_end_limit)
from rocknroller.analysis.slow.map.orbit import symmetric_data
from rocknroller.analysis.slow.map.table import (REGION_TABLE_ACCURACY, TableNotCachedError, build_table,  # noqa: F401
                                             load_or_build_table)

if TYPE_CHECKING:
    import pandas

    from rocknroller.analysis.slow.map.chart import SecondOrderTable


#: Defined here; the tables' and the map's public names (``SlowMapTable``, ``build_table``, ``load_or_build_table``,
#: ``iterate_slow_map``, ...) and the limits' (``THETA0_RANGE``, ``AveragingRangeError``, ...) are importable from
#: here too, and documented in their own modules.
__all__ = [
    "max_t_end",
    "SlowPrediction",
    "predict_slow_motion",
    "line_slope",
    "critical_regions",
    "rocks_per_region",
    "releases_on_region_tables",
    "default_order",
]


def rocks_per_region(runs: list[tuple[str, int, float]] | None) -> dict[str, int]:
    """Total number of rocks (maxima) in each critical region, from the runs of :func:`critical_regions`."""
    out: dict[str, int] = {}
    for lab, n, _ in runs or []:
        out[lab] = out.get(lab, 0) + n
    return out


# ----------------------------------------------------------------------------- small helpers
def max_t_end(body: Body, theta0: float) -> float:
    """Largest t_end accepted by :func:`predict_slow_motion` for (body, θ0): ``MAX_MAXIMA`` · T_θ(0)/2, with T_θ(0)
    the time between maxima of pure rocking (quadrature)."""
    theta0 = check_map_theta0(theta0)
    sym = body.symmetric()
    return t_end_limit(_rocking_period(sym, rest_energy(sym, theta0)))


@functools.lru_cache(maxsize=256)
def _rocking_period(sym: Body, E: float) -> float:
    """T_θ(0), the time between maxima of pure rocking at energy E (Q = 0; quadrature, ~10 ms; remembered)."""
    return float(symmetric_data(sym, E, 0.0, 0.0)[0])


def line_slope(QR: ArrayLike, QJ: ArrayLike) -> float | None:
    """Slope dQ_J/dQ_R of the straight line through turning-point samples (total least squares).

    The line's direction is the principal axis of the samples' 2×2 scatter matrix S, at the angle
    α = ½ atan2(2 S_RJ, S_RR − S_JJ); the slope is tan α.  None (undefined) for fewer than two samples or
    samples that all coincide (S = 0: no line, e.g. pure rocking at Q = 0).
    """
    x, y = np.asarray(QR, float), np.asarray(QJ, float)
    if x.size < 2:
        return None
    x, y = x - x.mean(), y - y.mean()
    sxx, syy, sxy = float(x @ x), float(y @ y), float(x @ y)
    if sxx == 0.0 and syy == 0.0:
        return None
    return math.tan(0.5 * math.atan2(2.0 * sxy, sxx - syy))


@dataclass(frozen=True)
class SlowPrediction:
    """Averaged prediction of the slow motion of a body released from rest at (θ0, ψ0).

    Attributes
    ----------
    eps, theta0, psi0, t_end : inputs (θ0 and ψ0 of the initial state, for a start with velocity).
    K : ε κ, the standard-map parameter near pure rocking.
    slow_period : period of Θ = 2ψ at the maxima; None if undefined (pure rocking) or not measurable
        within t_end (fewer than two crossings of the mean).
    QR_extent, QJ_extent : max − min of Q_R, Q_J at the maxima within t_end.
    Phi : span of φ mod π at the maxima within t_end.
    line_slope : dQ_J/dQ_R of the line through the samples; None if undefined (:func:`line_slope`).
    series : SlowSeries.
    regions, region_runs, crossings : critical region of each sample, runs of consecutive rocks in
        one region, and the crossings of the critical lines (:func:`critical_regions`).
    pure_rocking : True for ε = 0 (Routh's sphere released from rest): Q_R = Q_J = 0 exactly at every
        maximum, the intersection of both critical lines, and Θ, φ mod π are constant.  Then every
        sample's region is ``criticality.ON_BOTH``, there are no region runs or crossings, the extents
        and Φ are 0 and the slow period and line slope are None.
    start : the initial state of a start with velocity (None for a release from rest).
    order : the map's order in ε (1 or 2).
    chaos : the map's chaos indicators over their span (:class:`rocknroller.analysis.slow.dynamics.chaos.MapChaos`: MEGNO,
        the finite-time Lyapunov exponent per unit time and per rock, ``span``, ``verdict`` regular, chaotic or
        undecided, and its ``criterion``), from a tangent vector carried along the map from its start (the first
        maximum, for a start with velocity) over ``span`` = max(t_end, ``SPAN_ROCKS`` · T_θ(0)), whatever t_end is.
        None for pure rocking (ε = 0 from rest: the map is the identity in Q there, Q ≡ 0 and Θ fixed, and no map is
        run) and with ``indicators=False``.
    horizon_probe : the map − ODE error over the first ``PROBE_ROCKS`` rocks, the direct ODE run when the horizon is
        first asked for (:class:`rocknroller.analysis.slow.dynamics.chaos.HorizonProbe`); None where ``chaos`` is.
    body : the symmetric body of the map's tables (whose critical lines :meth:`plot` draws); None for a prediction
        made by hand without it.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> pred = rr.predict_slow_motion(body, 0.95 * math.pi, math.pi / 4, 200.0, order=1)
    >>> print(pred.order, pred.pure_rocking, pred.regular, pred.series.QR.shape == pred.series.t.shape)
    1 False True True
    >>> print(f"Phi = {pred.Phi:.4f}")
    Phi = 1.5092
    """

    eps: float
    theta0: float
    psi0: float
    t_end: float
    K: float
    slow_period: float | None
    QR_extent: float
    QJ_extent: float
    Phi: float
    line_slope: float | None
    series: SlowSeries = field(repr=False)
    regions: Any = field(default=None, repr=False)
    region_runs: list[tuple[str, int, float]] | None = field(default=None, repr=False)
    crossings: list[tuple[float, str, str, str]] | None = field(default=None, repr=False)
    pure_rocking: bool = False
    start: EulerState | None = field(default=None, repr=False)
    order: int = 1
    chaos: MapChaos | None = None
    horizon_probe: HorizonProbe | None = field(default=None, repr=False, compare=False)
    body: Body | None = field(default=None, repr=False)

    @property
    def regular(self) -> bool | None:
        """The map's verdict over its span: True (regular), False (chaotic); None where it is undecided or there are
        no indicators (``chaos.verdict``)."""
        return None if self.chaos is None or self.chaos.verdict == "undecided" else self.chaos.verdict == "regular"

    def horizon(self, fraction: float = HORIZON_FRACTION) -> float:
        """The predictability horizon: the time since the start at which the map − ODE error reaches ``fraction`` of
        the extents, measured over a probe window of the direct ODE and extrapolated by its growth law
        (:meth:`horizon_estimate`; inf where no growth is resolved).  Past it the point predictions are statistical
        only.  The first call runs the direct ODE over ``PROBE_ROCKS`` rocks (~0.02 s).

        Raises
        ------
        ValueError
            For ε = 0 (the map is exact: Routh's sphere is integrable, Q is conserved, and no error grows), without
            indicators (``indicators=False``), for an orbit without extent (a fixed
            point of the map), or ``fraction`` outside (0, 1].
        """
        return self.horizon_estimate(fraction).t

    def horizon_estimate(self, fraction: float = HORIZON_FRACTION) -> Horizon:
        """The horizon with its method, probe window and growth rate
        (:meth:`rocknroller.analysis.slow.dynamics.chaos.HorizonProbe.horizon`); raises as :meth:`horizon`."""
        if self.eps == 0.0:
            raise ValueError("a predictability horizon is not defined for eps = 0: the map is then exact (Routh's "
                             "sphere is integrable: Q_R, Q_J are conserved, and released from rest it rocks in a fixed "
                             "plane), so there is no error to grow")
        if self.horizon_probe is None:
            raise ValueError("a predictability horizon needs the chaos indicators (indicators=True)")
        return self.horizon_probe.horizon(fraction)

    def beyond_horizon(self, fraction: float = HORIZON_FRACTION) -> bool:
        """True if t_end lies past :meth:`horizon` (same errors)."""
        return self.t_end > self.horizon(fraction)

    @property
    def rocks_per_region(self) -> dict[str, int]:
        """Total number of rocks (maxima) in each critical region within t_end."""
        return rocks_per_region(self.region_runs)

    def to_dataframe(self) -> "pandas.DataFrame":
        """The series at the maxima (:meth:`SlowSeries.to_dataframe`) with each maximum's critical region."""
        frame = self.series.to_dataframe()
        if self.regions is not None:
            frame["region"] = np.asarray(self.regions)
        return frame

    def plot(self, ax: Any = None) -> Any:
        """Draw the predicted (Q_R, Q_J) at the θ-maxima on ``ax`` (a new pyplot figure without one, its layout
        constrained so that no label is cut off) over the critical lines Q_J,π^crit and Q_J,0^crit of its ``body``
        (paper eqs. QJcrit_pi, QJcrit_0; :func:`rocknroller.analysis.slow.dynamics.result_plots.plot_prediction`), with a
        legend; the axes keep the samples' range.  Returns the axes."""
        from rocknroller.analysis.slow.dynamics.result_plots import plot_prediction

        return plot_prediction(self, ax)


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
    if not math.isfinite(psi0):
        raise ValueError(f"psi0 must be finite, got psi0={psi0!r}")
    own_table = table is None  # a release table of the caller's is used as given, without the region tables' fallback
    if table is None:
        sym = body.symmetric()
        check_t_end(t_end, _rocking_period(sym, rest_energy(sym, theta0)))
        table = load_or_build_table(body, theta0, build=build, progress=progress)
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
    return replace(_prediction(eps, theta0, psi0, t_end, K, _until(run, t_end), table.body), order=order, chaos=chaos,
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


def _until(series: SlowSeries, t_end: float) -> SlowSeries:
    """The maxima of ``series`` at t ≤ t_end."""
    keep = series.t <= t_end
    return SlowSeries(*(getattr(series, n)[keep] for n in ("t", "QR", "QJ", "Theta", "phi")),
                      log_growth=None if series.log_growth is None else series.log_growth[keep])


def _indicators(body: Body, start: EulerState, run: SlowSeries, series: SlowSeries, T0: float,
                indicators: bool) -> tuple[MapChaos | None, HorizonProbe | None]:
    """The indicators of the map's ``run`` (from its start, over its span) and the probe of its horizon along
    ``series`` (the maxima from the start); (None, None) without indicators."""
    chaos = map_indicators(run.t, run.log_growth) if indicators else None
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


def default_order(start: float | EulerState) -> int:
    """The order of the map in ε when none is given, for a release angle θ0 or an initial state: the default of
    :func:`predict_slow_motion` and of ``rocknroller slow`` alike.

    2 for a release from rest in ``THETA0_RANGE``: the second-order release tables bring the map 10–1000× closer to the
    direct ODE at ε ≤ 3e-3 (at the command's default release, 0.95π, ψ0 = π/4, ε = 1e-3, 1000 time units: slow period
    within 3.5e-6 of the ODE, order 1 2.2e-4; docs/slow_validation.md, "Releases from rest, second order"), for a build
    once per (body, θ0), then cached, and little more than the run time of order 1.  1 for any other start (an initial
    state, or a release below ``THETA0_RANGE``): its second-order tables are per energy, several times dearer, so
    order 2 is asked for explicitly there.  The costs: docs/performance.md.
    """
    # compared as given (int or float; Python compares them exactly, so 10**400 or NaN is simply out of range)
    in_range = (isinstance(start, (int, float)) and not isinstance(start, bool)
                and THETA0_RANGE[0] <= start <= THETA0_RANGE[1])
    return 2 if in_range else 1


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
            check_t_end(t_end - fm.t, _rocking_period(body.symmetric(), fm.E))
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
                               _until(series, t_end), table.body, start=start), order=order, chaos=chaos,
                   horizon_probe=probe)


def critical_regions(QR: ArrayLike, QJ: ArrayLike, t: ArrayLike, body: Body):
    """Critical region of each turning-point sample, the runs of consecutive rocks in one region, and
    the crossings of the critical lines.

    Returns
    -------
    (regions, runs, crossings)
        regions: array of "I".."IV"; runs: list of (region, number of rocks, time of the first);
        crossings: list of (t, from, to, line) with line "QJ0crit" (full-angle reversal) and/or
        "QJpicrit" (visible-angle reversal).  A sample exactly on a line (u = 0) counts as above it.
    """
    from rocknroller.analysis.criticality.lines import region_from_offsets, side_code  # imported here: it loads sympy

    u0, upi = u_ends(QR, QJ, body.symmetric())
    regions = region_from_offsets(u0, upi).astype(object)
    side = side_code(u0, upi)
    starts = np.flatnonzero(np.concatenate([[True], side[1:] != side[:-1]]))[: side.size].tolist()
    labels, sides, times = regions.tolist(), side.tolist(), np.asarray(t, float).tolist()
    runs = [(labels[i], j - i, times[i]) for i, j in zip(starts, starts[1:] + [len(labels)])]
    crossings = []
    for i in starts[1:]:
        flip = sides[i] ^ sides[i - 1]  # the lines crossed (bits of side_code)
        lines = "+".join(name for name, bit in (("QJ0crit", 2), ("QJpicrit", 1)) if flip & bit)
        crossings.append((times[i], labels[i - 1], labels[i], lines))
    return regions, runs, crossings
