"""``rocknroller slow``: what it says on order and chaos, the map's verdict over its span with MEGNO and λ, the
predictability horizon with the method that found it (the summary's ``chaos``, ``horizon`` and ``beyond_horizon``
entries and their text lines), and what each number can be trusted for (``status``,
:mod:`rocknroller.analysis.slow.trust`).
"""

from __future__ import annotations

import math
from typing import Any

__all__ = ["chaos_summary", "chaos_lines", "two_digits", "EXTRAPOLATED", "apply_trust", "trust_lines"]

#: What the horizon's label says about the quantities past it.
_STATISTICAL = ("predictions past t = {t} are statistical only: the orbit's Q, Theta at a given time and the order "
                "of its region runs and crossings are not predicted past it; its extents, Phi and rocks per region "
                "over the run describe the region the orbit fills")


def chaos_summary(pred: Any) -> dict[str, Any]:
    """The summary's entries on order and chaos: ``chaos`` (verdict, regular, MEGNO, λ, 1/λ, the span and the
    criterion; null with ``chaos_note`` where there are no indicators), ``horizon`` (t, null if infinite; its method,
    fraction, probe window and error, rate, the label; null with ``horizon_note`` where it is not defined) and
    ``beyond_horizon`` (t_end past the horizon; null without one)."""
    out: dict[str, Any] = {"chaos": None, "horizon": None, "beyond_horizon": None}
    ch = pred.chaos
    if ch is None:
        out["chaos_note"] = "eps = 0 from rest: pure rocking, the map is the identity in Q (no indicators)"
    else:
        out["chaos"] = {"verdict": ch.verdict, "regular": pred.regular, "megno": ch.megno, "lyapunov": ch.lyapunov,
                        "lyapunov_per_rock": ch.lyapunov_per_rock,
                        "lyapunov_time": None if ch.lyapunov == 0.0 else ch.lyapunov_time,  # 1/λ; null for λ = 0
                        "span": ch.span, "criterion": ch.criterion}
    try:
        h = pred.horizon_estimate()
    except ValueError as exc:
        out["horizon_note"] = str(exc)
        return out
    beyond = bool(pred.t_end > h.t)
    out["horizon"] = {"t": h.t if math.isfinite(h.t) else None, "method": h.method, "fraction": h.fraction,
                      "probe_t": h.probe_t, "probe_error": h.probe_error, "rate": h.rate,
                      "lower_bound": h.method in EXTRAPOLATED and math.isfinite(h.t),
                      "statistical_only": _STATISTICAL.format(t=two_digits(h.t)) if beyond else None}
    out["beyond_horizon"] = beyond
    return out


#: How each method of the horizon found it, for the text.
_HORIZON_METHODS = {
    "measured": "measured: the map - ODE error reached {f:.0%} of the extents within the direct probe of t <= {p:.4g}",
    "exponential": "the map - ODE error {e:.2g} of the extents at the end of the direct probe (t = {p:.4g}), grown "
                   "exponentially at {r:.3g} per unit time",
    "linear": "the map - ODE error {e:.2g} of the extents at the end of the direct probe (t = {p:.4g}), grown linearly "
              "at its measured slope {r:.3g} per unit time",
    "beyond": "the map - ODE error {e:.2g} of the extents at the end of the direct probe (t = {p:.4g}), extrapolated "
              "at {r:.3g} per unit time, reaches it only past the longest run the map makes: beyond any t_end",
    "unresolved": "no growth of the map - ODE error ({e:.2g} of the extents) resolved over the direct probe of "
                  "t <= {p:.4g}: beyond any t_end",
}


#: The methods that extrapolate past the direct probe: their horizon is a lower bound.  Measured on five chaotic
#: starts against an independently derived direct ODE (twin runs of 15 700 time units), the two extrapolated horizons
#: fell short of the time at which the map - ODE error first reached 10 % by 1.76x and 2.09x: cautious, by about 2x.
EXTRAPOLATED = ("exponential", "linear")
_EXTRAPOLATION_NOTE = ("extrapolated past the probe, a lower bound: on chaotic starts checked against an independent "
                       "ODE such horizons fell short of the true one by about 2x")


def two_digits(t: float) -> str:
    """A horizon to the two significant digits its probe resolves: 250, 8700, 1.9e+06."""
    return f"{float(f'{t:.2g}'):g}"


def chaos_lines(s: dict[str, Any]) -> list[str]:
    """The text lines on order and chaos (:func:`chaos_summary`)."""
    ch, h = s["chaos"], s["horizon"]
    if ch is None:
        lines = [f"order/chaos: not measured ({s['chaos_note']})"]
    else:
        kind = {"regular": "regular", "chaotic": "CHAOTIC", "undecided": "UNDECIDED (MEGNO and lambda disagree)"}
        from rocknroller.analysis.slow.dynamics.chaos import SPAN_ROCKS

        lines = [f"order/chaos over the span t <= {ch['span']:.6g} (max(t_end, {SPAN_ROCKS} rocks)): {kind[ch['verdict']]} "
                 f"(MEGNO = {ch['megno']:.4g}; Lyapunov exponent {ch['lyapunov']:.4g} per unit time, "
                 f"{ch['lyapunov_per_rock']:.4g} per rock; {ch['criterion']})"]
    if h is None:
        lines.append(f"predictability horizon: not defined ({s['horizon_note']})")
        return lines
    how = _HORIZON_METHODS[h["method"]].format(f=h["fraction"], p=h["probe_t"], e=h["probe_error"], r=h["rate"])
    if h.get("lower_bound"):
        how += f"; {_EXTRAPOLATION_NOTE}"
    # two significant digits, what the probe resolves
    t = "infinite" if h["t"] is None else f"t {'>=' if h.get('lower_bound') else '='} {two_digits(h['t'])}"
    lines.append(f"predictability horizon: {t} (map - ODE error reaches {h['fraction']:.0%} of the extents; {how})")
    if s["beyond_horizon"]:
        lines.append(f"beyond the horizon: t_end = {s['t_end']:g} > {two_digits(h['t'])}: {h['statistical_only']}")
    return lines


def apply_trust(s: dict[str, Any]) -> None:
    """Mark each of the summary's quantities, the map's and the closed form's, predicted, statistical or undefined
    (:func:`~rocknroller.analysis.slow.trust.map_trust`, :func:`~rocknroller.analysis.slow.trust.closed_form_trust`),
    in ``s["status"]`` with the reasons in ``s["status_reasons"]``; an undefined number and its relative error
    become null."""
    from rocknroller.analysis.slow.trust import QUANTITIES, closed_form_trust, map_trust

    verdict = None if s["chaos"] is None else s["chaos"]["verdict"]
    pend = s.get("pendulum")
    marks = {"map": {q: map_trust(q, s[q], verdict, s["beyond_horizon"]) for q in QUANTITIES}}
    if pend is not None:
        marks["closed_form"] = {q: closed_form_trust(q, pend[q], verdict, s["K"], pend["regime_ratio"])
                                for q in QUANTITIES}
    for source, trusts in marks.items():
        values: dict[str, Any] = s if source == "map" else (pend or {})
        errors: dict[str, Any] | None = s.get("rel_error") if source == "map" else (pend or {}).get("rel_error")
        for q, trust in trusts.items():
            if trust.status == "undefined":
                values[q] = None
                if errors is not None:
                    errors[q] = None
    s["status"] = {source: {q: t.status for q, t in trusts.items()} for source, trusts in marks.items()}
    s["status_reasons"] = {source: {q: t.reason for q, t in trusts.items() if t.reason}
                           for source, trusts in marks.items()}


def trust_lines(s: dict[str, Any]) -> list[str]:
    """One line per source whose numbers are not all predicted: which are statistical or undefined, and why."""
    names = {"map": "averaged map", "closed_form": "closed form"}
    lines = []
    for source, reasons in s["status_reasons"].items():
        by_reason: dict[str, list[str]] = {}
        for q, why in reasons.items():
            by_reason.setdefault(f"{s['status'][source][q]} ({why})", []).append(q)
        if by_reason:
            lines.append(f"status, {names[source]}: " + "; ".join(f"{', '.join(qs)} {what}"
                                                                  for what, qs in by_reason.items()))
    return lines
