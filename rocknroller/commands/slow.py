"""``rocknroller slow``: the ε-averaged slow (Q_R, Q_J) motion of a body released from rest."""

from __future__ import annotations

import argparse
import json
import math
import sys
import warnings
from pathlib import Path
from typing import Any

from rocknroller.options import add_body_options, body_from_args, parse_angle

_QUANTITIES = ("slow_period", "QR_extent", "QJ_extent", "Phi")


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "slow",
        help="predict the slow (Q_R, Q_J) oscillation by first-order eps-averaging",
        description="First-order eps-averaged slow dynamics of the asymmetric rock'n'roller released from rest "
        "at (theta0, psi0): the reversible slow map sampled at the maxima of theta (tables built once per body "
        "and theta0, cached) and its closed form near pure rocking (standard map / pendulum). Prints the slow "
        "period of Theta = 2 psi, the extents of Q_R and Q_J, the azimuth span Phi of phi mod pi, the rocks "
        "spent in each critical region, and the period-doubling eps. Valid for 0 <= eps with K = eps*kappa < 4.",
    )
    add_body_options(p)
    p.add_argument("--theta0", type=str, default="0.95pi", help="release tilt in (0, pi) (default 0.95pi)")
    p.add_argument("--psi0", type=str, default="pi/4", help="release spin angle (default pi/4)")
    p.add_argument("--t-end", type=float, default=1000.0, help="time span (default 1000)")
    p.add_argument("--json", action="store_true", help="print a one-object JSON summary on stdout")
    p.add_argument("--check", action="store_true",
                   help="also run the direct ODE and print both, with relative errors")
    p.add_argument("--plot", type=Path, default=None, metavar="DIR",
                   help="draw the predicted slow orbit over the direct ODE's turning points (PNG+PDF in DIR)")
    p.add_argument("--cached-only", action="store_true",
                   help="fail instead of building the averaging tables when none are cached for this body/theta0")
    p.set_defaults(run=run, eps_default=1e-3)


def _fmt(x: Any) -> str:
    if x is None:
        return "n/a"
    return f"{x:.6g}" if isinstance(x, float) else str(x)


def run(args: argparse.Namespace) -> int:
    from analysis import averaging as av
    from analysis.slow_pendulum import pendulum_constants, pendulum_prediction

    if args.eps is None and args.I2 is None:
        args.eps = args.eps_default
    if args.eps is not None and not args.eps >= 0.0:
        raise ValueError(f"--eps must be >= 0 (the averaging holds for 0 <= eps with K = eps*kappa < 4), "
                         f"got eps={args.eps!r}")
    if not (math.isfinite(args.t_end) and args.t_end > 0.0):
        raise ValueError(f"--t-end must be a finite number > 0, got {args.t_end!r}")
    body = body_from_args(args)
    theta0, psi0 = parse_angle(args.theta0), parse_angle(args.psi0)
    if not 0.0 < theta0 < math.pi:
        raise ValueError(f"--theta0 must lie in the open interval (0, pi), got theta0={theta0!r}")
    consts = pendulum_constants(body, theta0)
    messages: list[str] = []
    K = body.epsilon * consts.kappa
    if abs(K) > av.K_PERIOD_DOUBLING:
        messages.append(
            f"K = eps*kappa = {K:.4g} > {av.K_PERIOD_DOUBLING:g}: outside the valid range eps < {consts.eps_period_doubling:.4g} "
            "(pure rocking about the stable axis has period-doubled; the closed form does not apply)")
    table = av.load_or_build_table(body, theta0, build=not args.cached_only)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", av.AveragingValidityWarning)
        pred = av.predict_slow_motion(body, theta0, psi0, args.t_end, table=table)
    pend = None
    try:
        pend = pendulum_prediction(body, theta0, psi0, args.t_end, constants=consts)
    except ValueError as exc:  # psi0 on the separatrix
        messages.append(f"closed form unavailable: {exc}")
    summary: dict[str, Any] = {q: getattr(pred, q) for q in _QUANTITIES}
    summary.update({"K": K, "line_slope": pred.line_slope, "rocks_per_region": pred.rocks_per_region,
                    "region_runs": [list(r) for r in pred.region_runs or []],
                    "crossings": [list(c) for c in pred.crossings or []], "n_maxima": int(pred.series.t.size),
                    "eps": body.epsilon, "theta0": theta0, "psi0": psi0, "t_end": args.t_end})
    summary["pendulum"] = None if pend is None else {
        **{q: getattr(pend, q) for q in _QUANTITIES}, "kappa": consts.kappa,
        "eps_period_doubling": consts.eps_period_doubling, "T0": consts.T0, "C0": list(consts.C0),
        "stable_psi": consts.stable_psi}
    ode = None
    if args.check or args.plot is not None:
        from papers.averaging_check import ode_slow_summary, relative_errors

        ode = ode_slow_summary(body, theta0, psi0, args.t_end)
        summary["ode"] = {q: getattr(ode, q) for q in _QUANTITIES}
        summary["ode"]["region_runs"] = [list(r) for r in ode.region_runs]
        summary["ode"]["rocks_per_region"] = av.rocks_per_region(ode.region_runs)
        summary["rel_error"] = {q: relative_errors(pred, ode)[q] for q in _QUANTITIES}
        if pend is not None:
            summary["pendulum"]["rel_error"] = {q: relative_errors(pend, ode)[q] for q in _QUANTITIES}
    written = _plot(pred, ode, body, theta0, psi0, args.plot) if args.plot is not None else []
    summary["warnings"] = messages
    for msg in messages:
        print(f"rocknroller slow: warning: {msg}", file=sys.stderr)
    if args.json:
        json.dump(_finite_or_none(summary), sys.stdout)
        sys.stdout.write("\n")
    else:
        _print_table(summary, body, theta0, psi0, args.t_end)
    for path in written:
        print(f"wrote {path}", file=sys.stderr)
    return 0


def _finite_or_none(x: Any) -> Any:
    """JSON has no inf/nan: non-finite numbers become null."""
    if isinstance(x, dict):
        return {k: _finite_or_none(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_finite_or_none(v) for v in x]
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


def _print_table(s: dict[str, Any], body, theta0: float, psi0: float, t_end: float) -> None:
    print(f"body: {body.describe()}")
    print(f"released from rest at theta0={theta0:.6g}, psi0={psi0:.6g}; t_end={t_end:g}; K = eps*kappa = {s['K']:.4g}")
    cols = ["quantity", "averaged map", "closed form"] + (["direct ODE", "map rel.err", "closed rel.err"]
                                                         if "ode" in s else [])
    rows = []
    pend = s["pendulum"] or {}
    for q in _QUANTITIES:
        row = [q, _fmt(s[q]), _fmt(pend.get(q))]
        if "ode" in s:
            row += [_fmt(s["ode"][q]), _fmt(s["rel_error"][q]), _fmt((pend.get("rel_error") or {}).get(q))]
        rows.append(row)
    widths = [max(len(r[i]) for r in rows + [cols]) for i in range(len(cols))]
    for r in [cols] + rows:
        print("  ".join(x.ljust(w) for x, w in zip(r, widths)))
    if pend:
        print(f"kappa = {pend['kappa']:.6g}; period doubling of rocking about the stable axis "
              f"(psi = {pend['stable_psi']:.4g}) at eps = {pend['eps_period_doubling']:.6g}")
    print(f"line of the turning points: dQ_J/dQ_R = {s['line_slope']:.6g}")
    runs = ", ".join(f"{lab}:{n}" for lab, n, _ in s["region_runs"])
    print(f"rocks per critical region (consecutive runs): {runs}")
    if "ode" in s:
        print(f"direct ODE runs:                             "
              f"{', '.join(f'{lab}:{n}' for lab, n, _ in s['ode']['region_runs'])}")


def _plot(pred, ode, body, theta0: float, psi0: float, out: Path) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from papers.output import save_figure

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    ax1.plot(ode.QR, ode.QJ, "o", ms=5, mfc="none", color="tab:red", label="direct ODE (maxima)")
    ax1.plot(pred.series.QR, pred.series.QJ, ".", ms=3, color="k", label="averaged map")
    ax1.set_xlabel("$Q_R$ at the maxima of $\\theta$")
    ax1.set_ylabel("$Q_J$")
    ax1.ticklabel_format(style="sci", scilimits=(-2, 2))
    ax1.legend(fontsize=8, loc="best")
    ax2.plot(ode.t, np.mod(0.5 * ode.Theta, np.pi), "o", ms=4, mfc="none", color="tab:red", label="direct ODE")
    ax2.plot(pred.series.t, pred.series.psi_mod_pi, ".", ms=3, color="k", label="averaged map")
    ax2.set_xlabel("t")
    ax2.set_ylabel("$\\psi$ mod $\\pi$ at the maxima")
    ax2.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    fig.suptitle(f"slow motion: eps={body.epsilon:.3g}, theta0={theta0:.4g}, psi0={psi0:.4g}", fontsize=10)
    fig.tight_layout()
    return save_figure(fig, out, "slow_orbit")
