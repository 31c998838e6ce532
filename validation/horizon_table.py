"""Regenerates the table of docs/order_and_chaos.md, "How long a prediction holds": the slow map's predictability
horizon against the measured time at which the map − ODE error first exceeds 10 % of the extents, and the map's
verdict over its span against two direct twin runs and the direct MEGNO.

Run:  nice -n 10 python validation/horizon_table.py [--t-end 3000] [--csv DIR]
(~3 min of CPU on 2 shared cores once the tables of the starts are cached; a start whose tables are not cached is
reported as such, not built: ``--build`` builds them, ~2-5 min per θ0 or energy).

Paper body, a grid of starts chosen across θ0 = 0.8π-0.97π and K = εκ(θ0) = 0.1 to 3.9 (ε = K/κ), releases from rest
and starts with velocity, each at the package's default order (:func:`rocknroller.analysis.slow.prediction.default_order`):

* the map's prediction over ``--t-end`` (its indicators over their span, :func:`rocknroller.analysis.slow.dynamics.chaos.indicator_span`,
  and its horizon, :meth:`~rocknroller.analysis.slow.prediction_result.SlowPrediction.horizon_estimate`, with the CPU time
  of the horizon's direct probe);
* the direct ODE over ``--t-end`` from the same start: the error e_k = max(|ΔQ_R|/D_R, |ΔQ_J|/D_J) at the maxima
  (D the direct ODE's extents over ``--t-end``; :func:`rocknroller.analysis.slow.dynamics.chaos.map_ode_errors`), its first
  time above 10 % (t_10, "never" if it stays below) and its largest value;
* the verdict of two direct runs from ψ0 and ψ0 + 1e-10 over the span: chaotic if their Q differ by more than
  ``TWIN_CHAOTIC`` = 1e-3 of the extents within it (a growth of 10⁷ from 1e-10: e^16, while a regular orbit's twins
  separate linearly), and the direct MEGNO over the span (heyoka's variational equations,
  :func:`rocknroller.numerics.variational.direct_chaos_indicators`; chaotic above 3);
* the horizon's dependence on t_end: the verdict and horizon at t_end = span and 2 · span.

Prints a Markdown table and the acceptance counts; ``--csv DIR`` writes ``horizon_table.csv`` with a header.
"""

from __future__ import annotations

import argparse
import math
import time
import warnings
from pathlib import Path

import numpy as np

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.dynamics.chaos import HORIZON_FRACTION, map_ode_errors
from rocknroller.analysis.slow.map.limits import AveragingRangeError, AveragingValidityWarning
from rocknroller.analysis.slow.dynamics.pendulum import pendulum_constants
from rocknroller.numerics.integrate import simulate
from rocknroller.numerics.megno import MEGNO_CHAOTIC
from rocknroller.numerics.variational import direct_chaos_indicators
from rocknroller.papers.output import write_csv

#: Releases from rest (θ0/π, K = εκ(θ0), ψ0).
RELEASES = ((0.80, 0.5, 0.3), (0.80, 2.0, 0.02), (0.85, 0.493, 0.003), (0.85, 1.0, 0.7), (0.85, 3.0, 1.2),
            (0.90, 0.1, 0.05), (0.90, 1.5, 0.01), (0.90, 3.9, 0.4), (0.93, 1.75, 0.003), (0.93, 1.1, 0.05),
            (0.93, 2.5, 1.0), (0.95, 0.426, math.pi / 4), (0.95, 1.28, 0.05), (0.95, 3.5, 0.1), (0.97, 0.3, 0.5),
            (0.97, 2.0, 0.01))
#: Starts with velocity (θ0/π, K of the release from θ0, ψ0, φ̇0): carried to their first maximum by the ODE.
MOVING = ((0.85, 1.0, 0.4, 0.3), (0.90, 2.0, 0.1, 0.2))
#: Offset of the twin run in ψ0.
TWIN = 1e-10
#: Twins' largest |ΔQ| (a fraction of the extents) within the span above which the direct motion is chaotic.
TWIN_CHAOTIC = 1e-3


def _body(theta0: float, K: float) -> Body:
    return Body.paper(K / pendulum_constants(Body.paper(1e-3), theta0).kappa)


def _twins(body: Body, start: EulerState, span: float) -> tuple[str, float]:
    """The twin runs' verdict and their largest |ΔQ| over the extents within ``span``."""
    a = simulate(body, start, span, samples=False).maxima
    b = simulate(body, EulerState(start.theta, start.phi, start.psi + TWIN, start.theta_dot, start.phi_dot,
                                  start.psi_dot), span, samples=False).maxima
    d = float(np.max(map_ode_errors(a.QR, a.QJ, b.QR, b.QJ, (np.ptp(a.QR), np.ptp(a.QJ)))))
    return ("chaotic" if d > TWIN_CHAOTIC else "regular"), d


def row(body: Body, start: EulerState, t_end: float, build: bool) -> dict[str, object]:
    """The measurements of one start (module docstring)."""
    release = start.theta_dot == start.phi_dot == start.psi_dot == 0.0
    args = (start.theta, start.psi) if release else (start,)
    try:
        t0 = time.process_time()
        pred = av.predict_slow_motion(body, *args, t_end=t_end, build=build)
        cpu_map = time.process_time() - t0
    except av.TableNotCachedError:
        return {"note": "tables not cached (--build)"}
    except AveragingRangeError as exc:
        return {"note": f"map: {str(exc)[:60]}"}
    ch = pred.chaos
    t0 = time.process_time()
    h = pred.horizon_estimate()
    cpu_probe = time.process_time() - t0
    m = simulate(body, start, t_end, samples=False).maxima
    err = map_ode_errors(pred.series.QR, pred.series.QJ, m.QR, m.QJ, (np.ptp(m.QR), np.ptp(m.QJ)))
    over = np.flatnonzero(err > HORIZON_FRACTION)
    t10 = float(m.t[over[0]]) if over.size else math.inf
    twin, twin_d = _twins(body, start, ch.span)
    megno_ode = direct_chaos_indicators(body, start, ch.span, budget=None).indicators.megno
    later = []
    for te in (ch.span, 2.0 * ch.span):
        try:
            p = av.predict_slow_motion(body, *args, t_end=te, build=build)  # longer: may need the region tables
            later.append((p.chaos.verdict, p.horizon()))
        except av.TableNotCachedError:
            later.append(("tables not cached (--build)", math.nan))
        except AveragingRangeError:
            later.append(("left the tables", math.nan))
    return {"K": pred.K, "order": pred.order, "verdict": ch.verdict, "megno": ch.megno, "lyapunov": ch.lyapunov,
            "span": ch.span, "horizon": h.t, "method": h.method, "t10": t10, "max_error": float(err.max()),
            "twins": twin, "twin_separation": twin_d, "megno_ode": megno_ode,
            "verdict_span": later[0][0], "horizon_span": later[0][1], "verdict_2span": later[1][0],
            "horizon_2span": later[1][1], "cpu_map": cpu_map, "cpu_probe": cpu_probe, "note": ""}


def _starts() -> list[tuple[str, Body, EulerState]]:
    out = []
    for th, K, psi in RELEASES:
        out.append((f"{th:.2f}π rest ψ0={psi:.4g}", _body(th * math.pi, K), EulerState(th * math.pi, 0.0, psi)))
    for th, K, psi, phid in MOVING:
        out.append((f"{th:.2f}π ψ0={psi:.4g} φ̇0={phid:g}", _body(th * math.pi, K),
                    EulerState(th * math.pi, 0.0, psi, phi_dot=phid)))
    return out


def _f(x: object, spec: str = ".3g") -> str:
    if isinstance(x, float):
        return "never" if x == math.inf else ("–" if math.isnan(x) else format(x, spec))
    return str(x)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--t-end", type=float, default=3000.0)
    parser.add_argument("--csv", type=Path, default=None)
    parser.add_argument("--build", action="store_true", help="build tables that are not cached")
    args = parser.parse_args()
    warnings.simplefilter("ignore", AveragingValidityWarning)
    rows = []
    for name, body, start in _starts():
        r = row(body, start, args.t_end, args.build)
        rows.append((name, body, r))
        print(name, r, flush=True)
    cols = ("K", "order", "verdict", "megno", "lyapunov", "span", "twins", "megno_ode", "horizon", "method", "t10",
            "max_error", "verdict_span", "horizon_span", "verdict_2span", "horizon_2span", "cpu_probe")
    print("\n| start | ε | K | map: verdict (MEGNO, λ) over the span | span | twins | direct MEGNO | horizon (method) "
          "| t_10 | horizon/t_10 | largest error to t_end | t_end = span, 2 span: verdicts, horizons |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, body, r in rows:
        if r["note"]:
            print(f"| {name} | {body.epsilon:.3g} | | {r['note']} | | | | | | | | |")
            continue
        ratio = r["horizon"] / r["t10"] if math.isfinite(r["t10"]) else math.nan
        print(f"| {name} | {body.epsilon:.3g} | {r['K']:.3g} | {r['verdict']} ({r['megno']:.3g}, "
              f"{r['lyapunov']:.2g}) | {r['span']:.0f} | {r['twins']} | {r['megno_ode']:.3g} | {_f(r['horizon'], '.4g')} "
              f"({r['method']}) | {_f(r['t10'], '.4g')} | {_f(ratio)} | {r['max_error']:.2g} | {r['verdict_span']}, "
              f"{r['verdict_2span']}; {_f(r['horizon_span'], '.4g')}, {_f(r['horizon_2span'], '.4g')} |")
    done = [r for _, _, r in rows if not r["note"]]
    agree = sum(r["verdict"] == r["twins"] for r in done)
    agree_megno = sum(r["verdict"] == ("chaotic" if r["megno_ode"] > MEGNO_CHAOTIC else "regular") for r in done)
    chaotic = [r for r in done if r["verdict"] != "regular" and math.isfinite(r["t10"])]
    within = sum(1 / 3 <= r["horizon"] / r["t10"] <= 3 for r in chaotic)
    quiet = [r for r in done if r["max_error"] < 0.01]
    quiet_ok = sum(r["horizon"] >= args.t_end for r in quiet)
    # the same verdict, and horizons within 1.5x of each other or both infinite (beyond any t_end, or unresolved)
    stable = sum(r["verdict_span"] == r["verdict_2span"] and (
        (math.isinf(r["horizon_span"]) and math.isinf(r["horizon_2span"]))
        or 1 / 1.5 < r["horizon_2span"] / r["horizon_span"] < 1.5) for r in done)
    print(f"\nstarts run: {len(done)} of {len(rows)}; map verdict = twins' at {agree}, = direct MEGNO's at "
          f"{agree_megno}; chaotic or undecided with a measured t_10: horizon within 3x at {within} of "
          f"{len(chaotic)}; error < 1 % over t_end: horizon >= t_end at {quiet_ok} of {len(quiet)}; t_end = span and "
          f"2 span: same verdict and horizons within 1.5x (or both infinite) at {stable} of {len(done)}; CPU of the horizon's probe over the map's "
          f"prediction: median {np.median([r['cpu_probe'] / r['cpu_map'] for r in done]):.2g}")
    if args.csv is not None:
        keys = ("note", "cpu_map") + cols
        write_csv(args.csv / "horizon_table.csv",
                  {"start": [n for n, _, _ in rows], "eps": [b.epsilon for _, b, _ in rows],
                   **{k: [r.get(k) for _, _, r in rows] for k in keys}},
                  [f"paper body; t_end = {args.t_end!r}; map at the default order; t10: first time the map - ODE "
                   "error exceeds 10 % of the ODE's extents; twins: two direct runs 1e-10 apart in psi0 over the span"])


if __name__ == "__main__":
    main()
