"""Order and chaos of the averaged slow map: its chaos indicators and the horizon up to which its point predictions
hold.  It holds :func:`map_indicators` (MEGNO and the finite-time Lyapunov exponent of a run of the map with a tangent
vector, by the package's one formula, :func:`rocknroller.numerics.megno.chaos_indicators`), :class:`StepErrorProbe`
(the map's own error over one step, against the exact step of the direct ODE), :func:`shear_rate` and
:func:`predictability_horizon` (the time at which that error, grown at the measured rate, reaches a stated fraction
of the extents), used by :class:`rocknroller.analysis.slow.prediction.SlowPrediction`.

The tangent vector.  :func:`rocknroller.analysis.slow.map.compiled_map.iterate_slow_map` with ``tangent=True`` carries a
tangent vector w of (u, v, Θ) (Q = u e + v n) through the exact derivative of each step as implemented, from
``TANGENT_START`` = (1, 1, 1)/√3 in the scaled coordinates (S u, S v, Θ), S = |∇W| at Q = 0 (the twist's gradient:
a change δQ changes the twist by ≈ S|δQ|, so both parts of w are phases, as the standard map's (p, Θ)); every run
starts from that same vector.  The samples of the indicators are the times t_k of the map's maxima after its start
and ℓ_k = ln(‖w_k‖/‖w_0‖) in the norm √(S²(w_u² + w_v²) + w_Θ²).

The predictability horizon.  The map of order p makes an error δ per step (O(ε^(p+1)) per rock): measured here as the
largest difference, in the same scaled norm, between one step of the map and one exact step of the direct ODE from
the same maximum (:func:`rocknroller.analysis.slow.map.exact_step.exact_step`), over the start and three maxima spread
along the run (:class:`StepErrorProbe`).  An error made at one step grows afterwards as a tangent vector does; summed
over the steps (continuously, n rocks of mean length T̄ = t_N/N):

* chaotic orbit (``regular`` False), growth e^(Λ m) per m rocks, Λ = λ T̄ the exponent per rock:
  e(n) = δ (e^(Λ n) − 1)/Λ, so  n_h = ln(1 + Λ R)/Λ;
* regular orbit, linear growth 1 + σ m by the shear (σ = :func:`shear_rate`): e(n) = δ (n + σ n²/2), so
  n_h = 2R/(1 + √(1 + 2σR));

with R = f S D/δ the number of per-step errors that make up the fraction f (``HORIZON_FRACTION`` = 10 %) of the
larger extent D = max(Q_R extent, Q_J extent) (scaled by S as the error is), and the horizon t_h = n_h T̄.  Both tend
to R T̄ (errors that merely add up) as the growth vanishes.  Beyond t_h the map's point predictions (the orbit's
Q and Θ at a given time, and so the region runs and crossings) are statistical only; its extents and the region
fractions over the run are what the chaotic orbit fills, not where it is.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map.compiled_map import SlowSeries, _fast, _tangent_rows, iterate_slow_map
from rocknroller.analysis.slow.map.exact_step import exact_step, step_difference
from rocknroller.numerics.megno import MIN_SAMPLES, ChaosIndicators, chaos_indicators

if TYPE_CHECKING:
    from rocknroller.analysis.slow.map.chart import SecondOrderTable, SlowMapTable

__all__ = ["HORIZON_FRACTION", "map_indicators", "tangent_scale", "StepErrorProbe", "run_indicators", "shear_rate",
           "predictability_horizon", "LAYER_GRID", "LayerWidth", "layer_width"]

#: Fraction of the extents that the grown error may reach at the predictability horizon.
HORIZON_FRACTION = 0.1
#: The decreasing log grid of ψ0 scanned by :func:`layer_width`: 16 points per decade from 1 down to 1e-10 (at
#: K ≈ 1.3 an island chain inside the layer leaves a regular band ψ0 ≈ 0.06-0.078 at θ0 = 0.95π, ε = 3e-3, below a
#: chaotic one at 0.08-0.09, which a grid of 4 points per decade steps over).
LAYER_GRID = 10.0 ** np.arange(0.0, -10.001, -1.0 / 16)
#: Most bisection steps :func:`layer_width` takes (2⁻³⁰ of a grid step is far below any orbit's resolution).
_MAX_BISECTIONS = 30
#: Maxima of a run, besides its start, at which :class:`StepErrorProbe` compares the map's step with the exact one.
_PROBES = 3


def map_indicators(t: ArrayLike, log_growth: ArrayLike) -> ChaosIndicators | None:
    """The chaos indicators of a run of the map from its maxima's times after the start and ℓ (module docstring);
    None for a run with fewer than ``MIN_SAMPLES`` maxima (too short to measure them)."""
    t = np.asarray(t, float)
    return None if t.size < MIN_SAMPLES else chaos_indicators(t, log_growth)


def tangent_scale(table: "SlowMapTable") -> float:
    """S = |∇W| at Q = 0 of a table: the weight of (u, v) in the tangent vector's norm (module docstring)."""
    return _tangent_rows(_fast(table)).scale


class StepErrorProbe:
    """The map's own error over one step along a run: computed when first asked for (``step_error``; four exact
    steps of the direct ODE, ~0.1 s), then remembered.

    Parameters
    ----------
    sym : the symmetric body of the tables.
    eps : ε > 0.
    table, second : the run's tables (``second`` None for order 1).
    points : (N, 3) array of the run's maxima (Q_R, Q_J, Θ), its start first.
    t0 : the time of the run's start (the times of its samples count from it).

    Attributes
    ----------
    scale : S = |∇W(0)| of the table (:func:`tangent_scale`).
    """

    def __init__(self, sym: Body, eps: float, table: "SlowMapTable", second: "SecondOrderTable | None",
                 points: NDArray[np.float64], t0: float = 0.0) -> None:
        self.sym, self.eps, self.table, self.second, self.t0 = sym, float(eps), table, second, float(t0)
        self.scale = tangent_scale(table)
        points = np.asarray(points, float)
        picks = np.unique(np.concatenate([[0], np.linspace(0, len(points) - 1, _PROBES + 1)[1:].round()]))
        self.points = points[picks.astype(int)]
        self._value: float | None = None

    def step_error(self) -> float:
        """δ: the largest √(S²|ΔQ|² + ΔΘ²) over the probed maxima (ΔΘ wrapped to (−π, π]) between one step of the
        map and the exact step of the direct ODE from the same maximum (module docstring)."""
        if self._value is None:
            S = self.scale
            worst = 0.0
            for QR, QJ, Th in self.points:
                exact = exact_step(self.sym, self.eps, self.table.E0, float(QR), float(QJ), 0.5 * float(Th))
                step = iterate_slow_map(self.table, self.eps, 0.5 * float(Th), 10.0 * exact[3], Q0=(QR, QJ), n_steps=1,
                                        second=self.second)
                d = step_difference(np.array([step.QR[0], step.QJ[0], step.Theta[0]]) - exact[:3])
                worst = max(worst, math.sqrt(S * S * (d[0] ** 2 + d[1] ** 2) + d[2] ** 2))
            self._value = worst
        return self._value


def run_indicators(sym: Body, eps: float, table: "SlowMapTable", second: "SecondOrderTable | None", run: SlowSeries,
                   start: tuple[float, float, float], t0: float = 0.0
                   ) -> tuple[ChaosIndicators | None, StepErrorProbe | None]:
    """The indicators of a run of the map with ``tangent=True`` (:func:`map_indicators`) and, where they exist, the
    probe of its per-step error; ``start`` is its starting (Q_R, Q_J, Θ), ``t0`` the time of its start."""
    assert run.log_growth is not None, "the run carries no tangent vector"
    chaos = map_indicators(run.t, run.log_growth)
    if chaos is None:
        return None, None
    points = np.concatenate([[start], np.stack([run.QR, run.QJ, run.Theta], axis=1)])
    return chaos, StepErrorProbe(sym, eps, table, second, points, t0)


def shear_rate(log_growth: ArrayLike) -> float:
    """σ: the least-squares slope of ‖w_k‖/‖w_0‖ = exp(ℓ_k) against the rock number k over the later half of the
    samples (the window of :func:`rocknroller.numerics.megno.lyapunov_slope`), floored at 0: the linear growth per rock
    of a tangent vector on a regular orbit (the shear of its torus)."""
    ell = np.asarray(log_growth, float)
    half = ell.size // 2
    k = np.arange(1, ell.size + 1, dtype=float)
    return max(float(np.polyfit(k[half:], np.exp(ell[half:]), 1)[0]), 0.0)


def predictability_horizon(chaos: ChaosIndicators, step_error: float, extent: float, scale: float,
                           fraction: float = HORIZON_FRACTION) -> float:
    """The time t_h at which the map's per-step error, grown at the measured rate, reaches ``fraction`` of the
    extent (module docstring):

        chaotic:  t_h = T̄ ln(1 + Λ R)/Λ,      regular:  t_h = T̄ · 2R/(1 + √(1 + 2σR)),

    R = fraction · scale · extent / step_error, T̄ the mean time between maxima, Λ the Lyapunov exponent per rock,
    σ the shear rate (:func:`shear_rate`).

    Parameters
    ----------
    chaos : the run's indicators (its samples give T̄, Λ and σ).
    step_error : δ > 0, the per-step error in the scaled norm (:meth:`StepErrorProbe.step_error`).
    extent : D > 0, the larger of the Q_R and Q_J extents.
    scale : S > 0 (:func:`tangent_scale`).
    fraction : f, 0 < f ≤ 1.

    Returns
    -------
    float : t_h, finite and > 0, in the units of the samples' times (the time since the map's start).

    Raises
    ------
    ValueError
        ``fraction`` outside (0, 1], ``extent``, ``scale`` or ``step_error`` not finite and > 0 (an orbit without
        extent is a fixed point of the map: there is no fraction of it to reach; an error of 0 means the map is
        exact to the ODE's accuracy there).
    """
    for name, value in (("step_error", step_error), ("extent", extent), ("scale", scale)):
        if not (math.isfinite(value) and value > 0.0):
            raise ValueError(f"{name} must be a finite number > 0 for a predictability horizon, got {name}={value!r}"
                             + (": the orbit does not move (a fixed point of the map), so it has no extent of which "
                                "an error could reach a fraction" if name == "extent" else ""))
    if not (math.isfinite(fraction) and 0.0 < fraction <= 1.0):
        raise ValueError(f"fraction must lie in (0, 1], got fraction={fraction!r}")
    t_bar = float(chaos.t[-1]) / chaos.t.size
    R = fraction * scale * extent / step_error
    if chaos.regular:
        sigma = shear_rate(chaos.log_growth)
        n_h = 2.0 * R / (1.0 + math.sqrt(1.0 + 2.0 * sigma * R))
    else:
        lam = chaos.lyapunov_per_rock
        n_h = math.log1p(lam * R) / lam if lam > 0.0 else R
    return n_h * t_bar


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
