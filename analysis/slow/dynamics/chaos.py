"""Order and chaos of the averaged slow map: its chaos indicators and the horizon up to which its point predictions
hold.  It holds :func:`map_indicators` (MEGNO and the finite-time Lyapunov exponent of a run of the map with a tangent
vector, by the package's one formula, :func:`rocknroller.numerics.megno.chaos_indicators`, with their span and
verdict: :class:`MapChaos`, :func:`map_verdict`, :func:`indicator_span`), :class:`HorizonProbe` and
:func:`horizon_from_errors` (the time at which the map − ODE error, measured over a short direct probe and
extrapolated by its growth law, reaches a stated fraction of the extents: :class:`Horizon`), used by
:class:`rocknroller.analysis.slow.prediction_result.SlowPrediction`, and :func:`layer_width`.

The tangent vector.  :func:`rocknroller.analysis.slow.map.compiled_map.iterate_slow_map` with ``tangent=True`` carries a
tangent vector w of (u, v, Θ) (Q = u e + v n) through the exact derivative of each step as implemented, from
``TANGENT_START`` = (1, 1, 1)/√3 in the scaled coordinates (S u, S v, Θ), S = |∇W| at Q = 0 (the twist's gradient:
a change δQ changes the twist by ≈ S|δQ|, so both parts of w are phases, as the standard map's (p, Θ)); every run
starts from that same vector.  The samples of the indicators are the times t_k of the map's maxima after its start
and ℓ_k = ln(‖w_k‖/‖w_0‖) in the norm √(S²(w_u² + w_v²) + w_Θ²).

The span.  A prediction's indicators are measured over a span that its start fixes, not over the t_end asked for:
``span = max(t_end, SPAN_ROCKS · T_θ(0))`` (:func:`indicator_span`; T_θ(0) the time between maxima of pure rocking
at the start's energy), the map being run that far and its series cut at t_end.  Over a span of ~SPAN_ROCKS rocks a
sticky orbit, which stays near an island for a hundred rocks or more before it leaves, is seen to leave: at 0.93π,
ε = 5e-3, ψ0 = 0.05 the map's verdict is regular over 80 rocks (MEGNO 2.3) and chaotic from 160 rocks on (MEGNO 6.5,
then 16, 51, 73 over 250, 500, 1000 rocks).  If the map's orbit leaves its tables after t_end and before the span's
end, the span is t_end (and says so).

The verdict.  MEGNO ⟨Y⟩ ≈ λt/2 on a chaotic orbit and → 2 on a regular one, and the finite-time exponent λ (the
slope of ℓ over the later half of the span) makes λ·span ≈ 2 ln 2 on a regular orbit (‖w‖ growing linearly): the
two agree when MEGNO > ``MEGNO_CHAOTIC`` = 3 goes with λ·span ≥ ``LYAPUNOV_SPAN`` = 6 = 2 · 3 (chaotic) and
MEGNO ≤ 3 with λ·span < 6 (regular).  Where they do not (an orbit chaotic early in the span that stuck to an island
in its later half: MEGNO ≫ 2 beside λ ≈ 0) the verdict is ``"undecided"``, with both numbers (:func:`map_verdict`).

The predictability horizon.  Measured, not modelled: the direct ODE (heyoka) runs from the start over a probe window
of ``PROBE_ROCKS`` rocks (:class:`HorizonProbe`; ~0.03 s of CPU per 1000 time units), and the map − ODE error at each
maximum, e_k = max(|ΔQ_R|/D_R, |ΔQ_J|/D_J) over the extents D of the map's orbit over the span, is followed by its
running maximum (the envelope).  If the envelope reaches the fraction f (``HORIZON_FRACTION`` = 10 %) within the
window, the horizon is that time (method ``"measured"``).  Otherwise its growth law is extrapolated from the window's
end (t_p, e_p) (:func:`horizon_from_errors`):

* chaotic or undecided: exponential at the rate Λ = max(λ, 2 MEGNO/span) (MEGNO's own rate, where λ of the later
  half is smaller): t_h = t_p + ln(f/e_p)/Λ  (method ``"exponential"``);
* regular: linear (a phase drift along the torus): the least-squares slope a of the envelope over the window's later
  half, t_h = t_p + (f − e_p)/a  (method ``"linear"``); with no growth resolved (a = 0) the horizon is infinite
  (method ``"unresolved"``).

An extrapolated horizon past the longest run the map makes (``t_end_limit``: ``MAX_MAXIMA`` maxima, ~5·10⁵ rocks) is
beyond any t_end a prediction can ask for, and its value there rests on a growth rate resolved only to a few digits
over the window (a slope of the envelope of ~10⁻⁹ per unit time gives 10⁸, or 10²¹ for one at round-off): it is
reported as infinite (method ``"beyond"``), so that it does not change with t_end.

Past t_h the map's point predictions (the orbit's Q and Θ at a given time, and so the region runs and crossings) are
statistical only; its extents and the region fractions over the run are what a chaotic orbit fills, not where it is.
The accuracy of the horizon against the measured time at which the map − ODE error first exceeds 10 % is tabulated by
``validation/horizon_table.py`` (docs/order_and_chaos.md, "How long a prediction holds").
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.slow.map.compiled_map import SlowSeries, _fast, _tangent_rows
from rocknroller.analysis.slow.map.limits import t_end_limit
from rocknroller.numerics.megno import MEGNO_CHAOTIC, MIN_SAMPLES, ChaosIndicators, chaos_indicators

if TYPE_CHECKING:
    from rocknroller.analysis.slow.map.chart import SlowMapTable

__all__ = ["HORIZON_FRACTION", "SPAN_ROCKS", "LYAPUNOV_SPAN", "CRITERION", "PROBE_ROCKS", "MapChaos", "map_verdict",
           "map_indicators", "indicator_span", "tangent_scale", "Horizon", "map_ode_errors", "horizon_from_errors",
           "HorizonProbe", "LAYER_GRID", "LayerWidth", "layer_width", "ENVELOPE_RESOLUTION"]

#: Fraction of the extents that the map − ODE error reaches at the predictability horizon.
HORIZON_FRACTION = 0.1
#: Fewest rocks, in units of T_θ(0), over which a prediction's indicators are measured (:func:`indicator_span`).
SPAN_ROCKS = 1000
#: λ·span that a chaotic verdict needs beside MEGNO > ``MEGNO_CHAOTIC`` (MEGNO ≈ λt/2 on a chaotic orbit).
LYAPUNOV_SPAN = 2.0 * MEGNO_CHAOTIC
#: The verdict's criterion, as every output states it.
CRITERION = (f"chaotic: MEGNO > {MEGNO_CHAOTIC:g} and lambda*span >= {LYAPUNOV_SPAN:g}; regular: MEGNO <= "
             f"{MEGNO_CHAOTIC:g} and lambda*span < {LYAPUNOV_SPAN:g}; otherwise undecided")
#: Length of the horizon's direct-ODE probe window, in rocks (units of T_θ(0)).
PROBE_ROCKS = 40
#: The decreasing log grid of ψ0 scanned by :func:`layer_width`: 16 points per decade from 1 down to 1e-10 (at
#: K ≈ 1.3 an island chain inside the layer leaves a regular band ψ0 ≈ 0.06-0.078 at θ0 = 0.95π, ε = 3e-3, below a
#: chaotic one at 0.08-0.09, which a grid of 4 points per decade steps over).
LAYER_GRID = 10.0 ** np.arange(0.0, -10.001, -1.0 / 16)
#: Most bisection steps :func:`layer_width` takes (2⁻³⁰ of a grid step is far below any orbit's resolution).
_MAX_BISECTIONS = 30


@dataclass(frozen=True)
class MapChaos(ChaosIndicators):
    """The map's indicators over a stated span, with the verdict of both (module docstring).

    Attributes
    ----------
    span : the time over which the indicators were measured (from the map's start).
    (and those of :class:`~rocknroller.numerics.megno.ChaosIndicators`; its ``regular`` is MEGNO ≤ 3 alone)
    """

    span: float

    @property
    def verdict(self) -> str:
        """The verdict, "regular", "chaotic" or "undecided": :func:`map_verdict` of MEGNO, λ and the span."""
        return map_verdict(self.megno, self.lyapunov, self.span)

    @property
    def criterion(self) -> str:
        """The rule the verdict follows, ``CRITERION`` (stated in every output beside the verdict)."""
        return CRITERION


def map_verdict(megno: float, lyapunov: float, span: float) -> str:
    """"chaotic" if MEGNO > ``MEGNO_CHAOTIC`` and λ·span ≥ ``LYAPUNOV_SPAN``, "regular" if MEGNO ≤ ``MEGNO_CHAOTIC``
    and λ·span < ``LYAPUNOV_SPAN``, "undecided" where the two disagree (module docstring)."""
    by_megno, by_lambda = megno > MEGNO_CHAOTIC, lyapunov * span >= LYAPUNOV_SPAN
    if by_megno != by_lambda:
        return "undecided"
    return "chaotic" if by_megno else "regular"


def map_indicators(t: ArrayLike, log_growth: ArrayLike) -> MapChaos | None:
    """The chaos indicators of a run of the map from its maxima's times after the start and ℓ, over the run's span
    (its last maximum), with their verdict; None for a run with fewer than ``MIN_SAMPLES`` maxima."""
    t = np.asarray(t, float)
    if t.size < MIN_SAMPLES:
        return None
    c = chaos_indicators(t, log_growth)
    span = float(t[-1])
    return MapChaos(**{f: getattr(c, f) for f in ChaosIndicators.__dataclass_fields__}, span=span)


def indicator_span(t_end: float, rock_time: float) -> float:
    """The span of a prediction's indicators: max(t_end, ``SPAN_ROCKS`` · T_θ(0)), ``rock_time`` = T_θ(0)."""
    return max(float(t_end), SPAN_ROCKS * float(rock_time))


def tangent_scale(table: "SlowMapTable") -> float:
    """S = |∇W| at Q = 0 of a table: the weight of (u, v) in the tangent vector's norm (module docstring)."""
    return _tangent_rows(_fast(table)).scale


@dataclass(frozen=True)
class Horizon:
    """The predictability horizon of a start and how it was found (:func:`horizon_from_errors`).

    Attributes
    ----------
    t : the horizon, in time since the start (inf where no growth of the error was resolved: method "unresolved").
    method : "measured" (the error reached the fraction within the probe window), "exponential", "linear" or
        "unresolved" (the law extrapolated from the window's end), or "beyond" (extrapolated past the longest run
        the map makes: t is inf).
    probe_t : the end of the probe window (the time of its last maximum).
    probe_error : the error envelope at the window's end (a fraction of the extents).
    rate : the growth used: Λ per unit time ("exponential"), the envelope's slope per unit time ("linear"), 0 else.
    fraction : the fraction of the extents the error reaches at t.
    """

    t: float
    method: str
    probe_t: float
    probe_error: float
    rate: float
    fraction: float


def map_ode_errors(QR: ArrayLike, QJ: ArrayLike, QR_ode: ArrayLike, QJ_ode: ArrayLike,
                   extents: tuple[float, float]) -> NDArray[np.float64]:
    """e_k = max(|ΔQ_R|/D_R, |ΔQ_J|/D_J) at the maxima both series share (paired by their index from the start),
    with ``extents`` = (D_R, D_J) > 0."""
    qr, qj = np.asarray(QR, float), np.asarray(QJ, float)
    qr_ode, qj_ode = np.asarray(QR_ode, float), np.asarray(QJ_ode, float)
    n = min(qr.size, qr_ode.size)
    DR, DJ = extents
    return np.maximum(np.abs(qr[:n] - qr_ode[:n]) / DR, np.abs(qj[:n] - qj_ode[:n]) / DJ)


#: The smallest growth of the map − ODE error envelope (a fraction of the extents) that counts as growth: 16 u, the
#: rounding of a few differences of Q's each rounded to about u of the extents, × 4 margin.
ENVELOPE_RESOLUTION = 16.0 * float(np.finfo(float).eps) / 2.0


def horizon_from_errors(t: ArrayLike, error: ArrayLike, law: str, rate: float = 0.0,
                        fraction: float = HORIZON_FRACTION) -> Horizon:
    """The horizon from the map − ODE errors over a probe window (module docstring): the first time the error
    exceeds ``fraction``, else the window end's envelope e_p extrapolated by ``law``: "exponential" at ``rate`` Λ > 0
    per unit time (t_p + ln(f/e_p)/Λ), or "linear" at the least-squares slope of the envelope over the window's later
    half (t_p + (f − e_p)/a; inf, method "unresolved", for a = 0).

    Raises
    ------
    ValueError
        Fewer than 2 samples, times not increasing, errors not finite, ``law`` unknown, an exponential ``rate`` not
        finite and > 0, or ``fraction`` outside (0, 1].
    """
    t, e = np.asarray(t, float), np.asarray(error, float)
    if t.ndim != 1 or t.shape != e.shape or t.size < 2 or not np.all(np.diff(t) > 0.0):
        raise ValueError("t and error must be 1-d arrays of one length >= 2, t increasing")
    if not np.all(np.isfinite(e)):
        raise ValueError("error must be finite")
    if not (math.isfinite(fraction) and 0.0 < fraction <= 1.0):
        raise ValueError(f"fraction must lie in (0, 1], got fraction={fraction!r}")
    if law not in ("exponential", "linear"):
        raise ValueError(f"law must be 'exponential' or 'linear', got law={law!r}")
    if law == "exponential" and not (math.isfinite(rate) and rate > 0.0):
        raise ValueError(f"an exponential law needs a rate > 0 per unit time, got rate={rate!r}")
    envelope = np.maximum.accumulate(e)
    over = np.flatnonzero(e > fraction)
    t_p, e_p = float(t[-1]), float(envelope[-1])
    if over.size:
        return Horizon(float(t[over[0]]), "measured", t_p, e_p, 0.0, fraction)
    if law == "exponential":
        return Horizon(t_p + math.log(fraction / max(e_p, np.finfo(float).tiny)) / rate, law, t_p, e_p, rate,
                       fraction)
    half = t.size // 2
    slope = max(float(np.polyfit(t[half:], envelope[half:], 1)[0]), 0.0) if t.size - half >= 2 else 0.0
    # a growth over the window's later half below the envelope's own resolution (its errors are differences of Q's
    # rounded to a few u of the extents) is round-off, not a rate (a slope of 3.2e-21 gave a horizon of 1e+17)
    if slope * (t_p - float(t[half])) <= ENVELOPE_RESOLUTION:
        slope = 0.0
    if slope == 0.0:
        return Horizon(math.inf, "unresolved", t_p, e_p, 0.0, fraction)
    return Horizon(t_p + (fraction - e_p) / slope, law, t_p, e_p, slope, fraction)


class HorizonProbe:
    """The map − ODE error over the probe window of a prediction: the direct ODE is run (heyoka, ~0.03 s of CPU per
    1000 time units) when the horizon is first asked for, then remembered.

    Parameters
    ----------
    body : the asymmetric body.
    start : the start's initial state (a release from rest: (θ0, 0, ψ0) with zero rates).
    series : the map's maxima from the start over at least the probe window (the prediction's run over its span).
    chaos : the map's indicators over the span (their verdict chooses the growth law, λ and MEGNO its rate).
    t_probe : the probe window's length, > 0.
    extents : (D_R, D_J) over the span when ``series`` holds less than the span (default: ``series``'s own).

    Attributes
    ----------
    extents : (D_R, D_J), the map's Q_R and Q_J extents over the span.
    """

    def __init__(self, body: Body, start: EulerState, series: SlowSeries, chaos: MapChaos, t_probe: float,
                 extents: tuple[float, float] | None = None) -> None:
        self.body, self.start, self.chaos, self.t_probe = body, start, chaos, float(t_probe)
        self.extents = (float(np.ptp(series.QR)), float(np.ptp(series.QJ))) if extents is None else extents
        keep = series.t <= self.t_probe
        self.t, self.QR, self.QJ = series.t[keep], series.QR[keep], series.QJ[keep]
        self._errors: NDArray[np.float64] | None = None

    def errors(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(t_k, e_k): the map's maxima in the window and their errors against the direct ODE's
        (:func:`map_ode_errors`)."""
        if self._errors is None:
            from rocknroller.numerics.integrate import simulate

            m = simulate(self.body, self.start, self.t_probe, samples=False).maxima
            self._errors = map_ode_errors(self.QR, self.QJ, m.QR, m.QJ, self.extents)
        return self.t[: self._errors.size], self._errors

    def horizon(self, fraction: float = HORIZON_FRACTION) -> Horizon:
        """The horizon (:func:`horizon_from_errors`): exponential growth at Λ = max(λ, 2 MEGNO/span) for a chaotic
        or undecided verdict, linear for a regular one; infinite (method "beyond") where it extrapolates past the
        longest run the map makes (module docstring), the probe window being ``PROBE_ROCKS`` rocks.

        Raises
        ------
        ValueError
            An orbit without extent in Q_R or Q_J (a fixed point of the map: no fraction of its extent to reach).
        """
        if not min(self.extents) > 0.0:
            raise ValueError("the orbit does not move (a fixed point of the map): it has no extent of which an error "
                             "could reach a fraction, and no predictability horizon")
        t, e = self.errors()
        c = self.chaos
        if c.verdict == "regular":
            h = horizon_from_errors(t, e, "linear", fraction=fraction)
        else:
            h = horizon_from_errors(t, e, "exponential", max(c.lyapunov, 2.0 * c.megno / c.span), fraction)
        if h.method in ("linear", "exponential") and h.t > t_end_limit(self.t_probe / PROBE_ROCKS):
            return Horizon(math.inf, "beyond", h.probe_t, h.probe_error, h.rate, fraction)
        return h


@dataclass(frozen=True)
class LayerWidth:
    """The separatrix layer's width along the release line (:func:`layer_width`).

    Attributes
    ----------
    width : the geometric mean of ``bracket``.
    bracket : (ψ_in, ψ_out): the largest ψ0 found chaotic and the smallest above it found regular.
    megno_in, megno_out : MEGNO of the releases at ψ_in and ψ_out.
    runs : releases evaluated.
    """

    width: float
    bracket: tuple[float, float]
    megno_in: float
    megno_out: float
    runs: int


def layer_width(chaos: Callable[[float], ChaosIndicators], grid: ArrayLike | None = None,
                bisections: int = 2) -> LayerWidth:
    """The width of the chaotic layer about the unstable rocking axis ψ0 = 0, along the line of releases from rest.

    Definition: ψ0 is scanned down the decreasing grid ``grid`` to the first (largest) ψ0 whose release is chaotic
    (``not chaos(psi0).regular``: MEGNO > 3 over the span ``chaos`` integrates); then ln ψ0 is bisected ``bisections``
    times between it and the grid point above it (regular), keeping a chaotic lower and a regular upper end.  The
    width is the geometric mean of the final bracket.  The layer is not a clean interval (island chains sit in it,
    and a chaotic band above a regular one narrower than a grid step is not seen): the width is that of the
    outermost chaotic release the scan meets.

    Parameters
    ----------
    chaos : the indicators of the release at ψ0 (the map's, or the direct ODE's, over a fixed span).
    grid : at least two ψ0 in (0, π/2], strictly decreasing (default None: ``LAYER_GRID``, 10^(−j/16), j = 0..160).
    bisections : 0 ≤ bisections ≤ 30; each halves the bracket in ln ψ0 (2 on the default grid: a factor 1.037).

    Returns
    -------
    LayerWidth

    Raises
    ------
    ValueError
        A grid that is not as stated, ``bisections`` out of range, the grid's first (largest) ψ0 chaotic (no edge
        below it), or no chaotic ψ0 on the grid (the layer is thinner than its smallest ψ0, or the span too short).
    """
    psi = np.asarray(LAYER_GRID if grid is None else grid, float)
    if psi.ndim != 1 or psi.size < 2 or not (np.all(np.isfinite(psi)) and psi[-1] > 0.0 and psi[0] <= 0.5 * math.pi
                                             and np.all(np.diff(psi) < 0.0)):
        raise ValueError("grid must be at least two psi0 in (0, pi/2], strictly decreasing")
    if not (isinstance(bisections, int) and 0 <= bisections <= _MAX_BISECTIONS):
        raise ValueError(f"bisections must be an integer in [0, {_MAX_BISECTIONS}], got bisections={bisections!r}")
    runs = 0
    above: tuple[float, ChaosIndicators] | None = None
    for p in psi:
        c = chaos(float(p))
        runs += 1
        if not c.regular:
            if above is None:
                raise ValueError(f"the release at the grid's largest psi0={p:g} is chaotic: the layer's edge lies "
                                 "above the grid; start the grid higher")
            (lo, c_lo), (hi, c_hi) = (float(p), c), above
            break
        above = (float(p), c)
    else:
        raise ValueError(f"no release on the grid (psi0 down to {psi[-1]:g}) is chaotic over the span: the layer is "
                         "thinner than the grid reaches, or the span too short for MEGNO to exceed 3")
    for _ in range(bisections):
        mid = math.sqrt(lo * hi)
        c = chaos(mid)
        runs += 1
        if c.regular:
            hi, c_hi = mid, c
        else:
            lo, c_lo = mid, c
    return LayerWidth(math.sqrt(lo * hi), (lo, hi), c_lo.megno, c_hi.megno, runs)
