"""Comparison of the averaged predictions with the direct ODE (shared by the tests, the CLI and the docs table).

The observables follow the shared definitions of :mod:`rocknroller.analysis.model.diagnostics`: slow period of
Θ = 2ψ at the θ-maxima (crossings of the mean), extents of Q_R and Q_J over the maxima within t_end,
and Φ, the span of φ mod π at the maxima.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.dynamics.pendulum import PendulumConstants, pendulum_prediction

__all__ = ["OBSERVABLES", "OdeSlowSummary", "ode_slow_summary", "PredictionCheck", "check_prediction",
           "timed_map_and_ode", "relative_errors", "sample_errors", "loglog_slope", "Comparison", "compare_with_ode"]

#: Observables compared with the ODE.
OBSERVABLES = ("slow_period", "QR_extent", "QJ_extent", "Phi", "line_slope")


@dataclass(frozen=True)
class OdeSlowSummary:
    """The direct ODE's turning-point samples and slow observables (released from rest)."""

    t: np.ndarray
    QR: np.ndarray
    QJ: np.ndarray
    Theta: np.ndarray
    phi: np.ndarray
    slow_period: float | None
    QR_extent: float
    QJ_extent: float
    Phi: float
    line_slope: float | None
    region_runs: list[tuple[str, int, float]]


def ode_slow_summary(body: Body, theta0: float | EulerState, psi0: float | None, t_end: float, *,
                     progress: bool | None = False) -> OdeSlowSummary:
    """Run the direct ODE (heyoka) from rest at (θ0, ψ0), or from an initial state (then psi0 is None), and
    summarise its θ-maxima (as :func:`rocknroller.analysis.slow.prediction.predict_slow_motion` takes its start);
    ``progress`` as :func:`rocknroller.numerics.integrate.simulate`'s."""
    from rocknroller.numerics.integrate import simulate

    if isinstance(theta0, EulerState):
        start = theta0
    elif psi0 is None:
        raise ValueError("psi0 is needed with a tilt theta0 (None only with an initial EulerState)")
    else:
        start = EulerState(theta0, 0.0, psi0)
    tr = simulate(body, start, t_end, dt=t_end / 10, progress=progress)
    m = tr.maxima
    return OdeSlowSummary(t=m.t, QR=m.QR, QJ=m.QJ, Theta=2.0 * m.psi, phi=m.phi, slow_period=tr.slow_period,
                          QR_extent=tr.QR_extent, QJ_extent=tr.QJ_extent, Phi=tr.Phi,
                          line_slope=av.line_slope(m.QR, m.QJ),
                          region_runs=av.critical_regions(m.QR, m.QJ, m.t, body)[1])


@dataclass(frozen=True)
class PredictionCheck:
    """A slow prediction beside the direct ODE from the same start over the same span (``rocknroller slow --check``).

    Attributes
    ----------
    prediction : SlowPrediction
    ode : OdeSlowSummary
        The direct ODE's θ-maxima and its observables, defined as the prediction's.
    rel_errors : dict
        prediction/ODE − 1 for each of ``OBSERVABLES``; None where either is not measurable, and all None for pure
        rocking (ε = 0 from rest: the ODE's Q and Θ are round-off about constants).
    sample_errors : dict or None
        The largest differences maximum by maximum (:func:`sample_errors`); None for pure rocking.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> check = rr.check_prediction(body, rr.predict_slow_motion(body, 0.95 * math.pi, math.pi / 4, 200.0, order=1))
    >>> print(type(check.prediction).__name__, abs(check.rel_errors["Phi"]) < 0.05)
    SlowPrediction True
    """

    prediction: av.SlowPrediction
    ode: OdeSlowSummary
    rel_errors: dict[str, float | None]
    sample_errors: dict[str, float] | None


def check_prediction(body: Body, prediction: av.SlowPrediction, *, progress: bool | None = False) -> PredictionCheck:
    """Run the direct ODE (heyoka) from ``prediction``'s start (its release from rest at (θ0, ψ0), or its initial
    state) over its span, and compare: what ``rocknroller slow --check`` prints.

    Parameters
    ----------
    body : Body
        The body the prediction was made for (its ε is checked).
    prediction : SlowPrediction
        From :func:`rocknroller.analysis.slow.prediction.predict_slow_motion`.
    progress : bool or None
        A tqdm bar over the ODE's time span on stderr (None: only if stderr is a terminal).

    Raises
    ------
    ValueError
        If ``body``'s ε is not the prediction's.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> pred = rr.predict_slow_motion(body, 0.95 * math.pi, math.pi / 4, 200.0, order=1)
    >>> check = rr.check_prediction(body, pred)
    >>> print({k: (None if v is None else abs(v) < 0.05) for k, v in check.rel_errors.items()})
    {'slow_period': True, 'QR_extent': True, 'QJ_extent': True, 'Phi': True, 'line_slope': True}
    """
    if body.epsilon != prediction.eps:
        raise ValueError(f"the prediction is for eps={prediction.eps!r}, not this body's eps={body.epsilon!r}")
    if prediction.start is not None:
        ode = ode_slow_summary(body, prediction.start, None, prediction.t_end, progress=progress)
    else:
        ode = ode_slow_summary(body, prediction.theta0, prediction.psi0, prediction.t_end, progress=progress)
    if prediction.pure_rocking:
        return PredictionCheck(prediction, ode, {q: None for q in OBSERVABLES}, None)
    return PredictionCheck(prediction, ode, relative_errors(prediction, ode), sample_errors(prediction.series, ode))


def timed_map_and_ode(body: Body, start: EulerState, t_end: float, table: Any, order: int = 1,
                      second: Any = None) -> tuple[av.SlowPrediction, OdeSlowSummary, float, float, float]:
    """The map's prediction of ``order`` from ``start`` (tables given or None) and the ODE's summary, each timed
    (benchmarks): (prediction, summary, seconds of the first prediction (it builds the tables' run-time form once a
    process), of a second one, of the ODE)."""
    import time

    t0 = time.perf_counter()
    av.predict_slow_motion(body, start, t_end=t_end, table=table, order=order, second=second)
    t_first = time.perf_counter() - t0
    t0 = time.perf_counter()
    pred = av.predict_slow_motion(body, start, t_end=t_end, table=table, order=order, second=second)
    t_map = time.perf_counter() - t0
    t0 = time.perf_counter()
    ode = ode_slow_summary(body, start, None, t_end)
    return pred, ode, t_first, t_map, time.perf_counter() - t0


def relative_errors(pred: Any, ref: Any) -> dict[str, float | None]:
    """pred/ref − 1 for each of ``OBSERVABLES`` present on both (None if not measurable)."""
    out: dict[str, float | None] = {}
    for q in OBSERVABLES:
        a, b = getattr(pred, q, None), getattr(ref, q, None)
        out[q] = None if a is None or b is None or b == 0.0 or not math.isfinite(a) else a / b - 1.0
    return out


def sample_errors(series: av.SlowSeries, ref: OdeSlowSummary) -> dict[str, float]:
    """Largest differences map − ODE maximum by maximum: |ΔQ|/(Q_R extent), Θ, t and φ mod π.  Where the ODE's Q_R
    does not move (pure rocking), the Q entry is 0 if the map's Q agrees to the bit and infinite otherwise."""
    n = min(series.t.size, ref.t.size)
    dQ = float(np.hypot(series.QR[:n] - ref.QR[:n], series.QJ[:n] - ref.QJ[:n]).max())
    extent = float(np.ptp(ref.QR))
    return {"Q": dQ / extent if extent > 0.0 else (math.inf if dQ > 0.0 else 0.0),
            "Theta": float(np.abs(wrap_angle(series.Theta[:n] - ref.Theta[:n])).max()),
            "t": float(np.abs(series.t[:n] - ref.t[:n]).max()),
            "phi": float(np.abs(wrap_angle(series.phi[:n] - ref.phi[:n], math.pi)).max())}


def loglog_slope(x: ArrayLike, err: ArrayLike) -> float:
    """Least-squares slope of log|err| against log x (the power of a convergence law err ∝ x^p)."""
    return float(np.polyfit(np.log10(np.asarray(x, float)), np.log10(np.abs(np.asarray(err, float))), 1)[0])


@dataclass(frozen=True)
class Comparison:
    """Map, closed form and ODE for one (ε, ψ0)."""

    eps: float
    psi0: float
    map: av.SlowPrediction
    pendulum: Any
    ode: OdeSlowSummary
    map_errors: dict[str, float | None]
    pendulum_errors: dict[str, float | None]
    sample_errors: dict[str, float]


def compare_with_ode(body: Body, theta0: float, psi0: float, t_end: float, *, table: av.SlowMapTable,
                     constants: PendulumConstants) -> Comparison:
    """Averaged map, closed form and direct ODE side by side (released from rest at (θ0, ψ0))."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", av.AveragingValidityWarning)
        pred = av.predict_slow_motion(body, theta0, psi0, t_end, table=table, order=1)
    try:
        pend = pendulum_prediction(body, theta0, psi0, t_end, constants=constants)
    except ValueError:
        pend = None
    ref = ode_slow_summary(body, theta0, psi0, t_end)
    return Comparison(eps=body.epsilon, psi0=psi0, map=pred, pendulum=pend, ode=ref,
                      map_errors=relative_errors(pred, ref),
                      pendulum_errors=relative_errors(pend, ref) if pend is not None else {},
                      sample_errors=sample_errors(pred.series, ref))
