"""The result of a slow-motion prediction, :class:`SlowPrediction` (made by
:func:`rocknroller.analysis.slow.prediction.predict_slow_motion`), and what it is read with: the critical region of
each maximum and the runs and crossings of the critical lines (:func:`critical_regions`, :func:`rocks_per_region`;
paper eqs. QJcrit_0, QJcrit_pi) and the slope of the line the maxima lie on (:func:`line_slope`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.routh.reduction import u_ends
from rocknroller.analysis.slow.dynamics.chaos import HORIZON_FRACTION, Horizon, HorizonProbe, MapChaos
from rocknroller.analysis.slow.map.compiled_map import SlowSeries

if TYPE_CHECKING:
    import pandas

__all__ = ["SlowPrediction", "critical_regions", "rocks_per_region", "line_slope"]


def rocks_per_region(runs: list[tuple[str, int, float]] | None) -> dict[str, int]:
    """Total number of rocks (maxima) in each critical region, from the runs of :func:`critical_regions`."""
    out: dict[str, int] = {}
    for lab, n, _ in runs or []:
        out[lab] = out.get(lab, 0) + n
    return out


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
    slow_period : float or None
        The period of Θ = 2ψ at the maxima; None if undefined (pure rocking) or not measurable
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

    def plot(self, fig: Any = None, ode: Any = None) -> Any:
        """Draw the prediction on ``fig`` (a new pyplot figure without one), as ``rocknroller slow --plot`` does
        (:func:`rocknroller.analysis.slow.dynamics.result_plots.plot_prediction`): the (Q_R, Q_J) at the θ-maxima
        over the critical lines Q_J,π^crit and Q_J,0^crit of its ``body`` (paper eqs. QJcrit_pi, QJcrit_0) and ψ mod π
        at the maxima against t with the predictability horizon (:meth:`horizon`, where it is finite: a line at it
        before t_end, the span past it shaded, or named in the legend after t_end), titled with the body, ε, θ0, ψ0
        and the map's order; ``ode``: the direct ODE's maxima beside the map's (``check_prediction(...).ode``).
        Returns the figure.

        Examples
        --------
        >>> import math, matplotlib.figure, rocknroller as rr
        >>> pred = rr.predict_slow_motion(rr.Body.paper(5e-3), 0.95 * math.pi, 0.05, 400.0, order=1)
        >>> fig = pred.plot(matplotlib.figure.Figure(figsize=(11, 4.2), layout="constrained"))
        >>> print(fig.axes[1].get_lines()[1].get_label() == f"predictability horizon t = {pred.horizon():.4g}")
        True
        """
        from rocknroller.analysis.slow.dynamics.result_plots import plot_prediction

        try:
            t_h = self.horizon()
        except ValueError:  # no horizon: ε = 0, no indicators, or a fixed point of the map
            t_h = math.inf
        return plot_prediction(self, fig, horizon=t_h if math.isfinite(t_h) else None, ode=ode)


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
