"""``rocknroller slow``: the ε-averaged slow (Q_R, Q_J) motion of a body released from rest, or from any start.

Without a rate option (or ``--critical-line``) the body is released from rest at (θ0, ψ0): the release tables
and the closed form near pure rocking.  With one, the start is carried to its first θ-maximum by the direct ODE
and the map runs on the region tables of its energy (``rocknroller.analysis.slow.map.region``).

The body, the angles and ``--t-end`` are checked before any table is built, and errors name the option
given (``--eps``, ``--I2``, ``--theta0``, ``--t-end``).  ``--json`` prints strict JSON (no NaN or Infinity); a quantity that is
undefined is null: the slow period when the samples cross their mean fewer than twice or for pure rocking
(ε = 0, where the closed form's period is infinite), the line slope when all samples coincide, the
closed form when ψ0 is its unstable equilibrium, and the relative errors of a quantity the ODE gives as 0
or that is undefined.

Order and chaos.  Every prediction reports the map's verdict over a stated span (max(t_end, 1000 rocks), whatever
t_end is), regular, chaotic or undecided (MEGNO and λ·span must agree: the criterion is printed;
:mod:`rocknroller.analysis.slow.dynamics.chaos`), MEGNO, the finite-time Lyapunov exponent per unit time and per rock, and the
predictability horizon (:meth:`rocknroller.analysis.slow.prediction_result.SlowPrediction.horizon_estimate`: the time at which
the map − ODE error reaches 10 % of the extents, measured over a short direct probe and extrapolated by its growth law;
its method is printed).  A t_end past the horizon is labelled
(``beyond_horizon``; "predictions past t = ... are statistical only"), in the text, the JSON and the CSV (``--csv``:
the maxima, each with ``beyond_horizon``).  For ε = 0 from rest (pure rocking) there are no indicators and no horizon
(null, with the reason).  Beside a release's past-horizon numbers stands the statistical prediction, the map's
ensemble over a stated small ball of releases (``--statistics``; :mod:`rocknroller.cli.slow_statistics`): in the
text, the JSON (``statistics``) and, with ``--csv``, ``slow_statistics.csv`` and the maxima's header.  Pure rocking
(ψ0 = 0 or π/2) is reported as that periodic orbit with its stability instead (:mod:`rocknroller.cli.slow_periodic`).
"""

from __future__ import annotations

import argparse
import math
import sys
import warnings
from pathlib import Path
from typing import Any

from rocknroller.analysis.slow import prediction as av
from rocknroller.cli.options import (add_body_options, add_critical_line_options, add_force_option,
                                     add_initial_state_options, body_from_args, check_critical_line_options,
                                     critical_line_state, output_path, parse_angle, prepare_output_dir, print_json,
                                     rates_given)
from rocknroller.cli.slow_chaos import apply_trust, chaos_lines, chaos_summary, trust_lines
from rocknroller.cli.slow_periodic import apply_periodic, periodic_lines, periodic_summary
from rocknroller.cli.slow_statistics import (STATISTICS_CSV, add_statistics_options, check_statistics_options,
                                             check_statistics_work, statistics_lines, statistics_summary,
                                             write_statistics_csv)
from rocknroller.numerics.parallel import check_processes

_QUANTITIES = ("slow_period", "QR_extent", "QJ_extent", "Phi")
CSV_NAME = "slow_maxima.csv"
#: Body options (attribute, flag), for error messages that name what the user gave.
_BODY_OPTIONS = (("a", "--a"), ("I1", "--I1"), ("I2", "--I2"), ("eps", "--eps"), ("I3", "--I3"), ("g", "--g"),
                 ("polar_cap", "--polar-cap"))
_LO, _HI = (x / math.pi for x in av.THETA0_RANGE)
_PURE_ROCKING = ("eps = 0 (Routh's sphere) released from rest: pure rocking in a fixed vertical plane; Q_R = Q_J = 0 "
                 "at every maximum, the intersection of both critical lines (no critical region, no crossings); "
                 "no slow motion (slow period and line slope undefined)")


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``slow`` subcommand and its ``--help`` to ``sub``."""
    p = sub.add_parser(
        "slow",
        help="predict the slow (Q_R, Q_J) oscillation by eps-averaging (first or second order)",
        description="eps-averaged slow dynamics (first order; second order with --order 2, the default for releases "
        "from rest in the release tables' range) of the asymmetric rock'n'roller released from rest "
        "at (theta0, psi0): the reversible slow map sampled at the maxima of theta (tables built once per body "
        "and theta0, cached) and its closed form near pure rocking (standard map / pendulum); or, with any rate "
        "option or --critical-line, from that start (carried to its first maximum of theta by the direct ODE; "
        "the map on the tables of its energy over the whole (Q_R, Q_J) region, built once per body and energy, "
        "and cached; the costs of every build: docs/performance.md). Prints the slow "
        "period of Theta = 2 psi, the extents of Q_R and Q_J, the azimuth span Phi of phi mod pi, the rocks "
        "spent in each critical region, the period-doubling eps, and the map's order or chaos: regular or chaotic "
        "(MEGNO and lambda*span agree; else undecided), over a span of max(t_end, 1000 rocks), MEGNO, the "
        "Lyapunov exponent per unit time and per rock, and the predictability horizon (the time at which the map - "
        "ODE error reaches 10% of the extents, measured over a 40-rock direct probe and extrapolated by its growth "
        "law; a t_end past it is labelled: the predictions past it are statistical only, and for a release from rest the "
        "statistical prediction, the map's ensemble over a small ball of releases, is given beside them: "
        "--statistics). Valid for 0 <= eps with K = eps*kappa < 4 "
        f"and, for releases from rest, 0 < theta0 <= {_HI:g}pi: the release tables in [{_LO:g}pi, {_HI:g}pi], the "
        "region tables below (to ~1e-9: over the whole region up to the energy of a release from 0.65pi, above it "
        "over the band about Q_J,pi^crit, where the paper's reversal starts live). "
        "eps defaults to 1e-3 here; eps = 0 (Routh's sphere) is pure "
        "rocking on both critical lines. In --json, undefined quantities are null (never NaN or Infinity).",
    )
    add_body_options(p, eps_default=1e-3)
    add_initial_state_options(p, psi0_default="pi/4", rates_note=(
        f"with none of them (and no --critical-line) the body is released from rest at 0 < theta0 <= {_HI:g}pi "
        f"(on the release tables from {_LO:g}pi up, below on the region tables of its energy); with any, the region "
        "tables of the start's energy are used (--chart)"),
        theta0_range=f"in (0, {_HI:g}pi] for a release from rest, in [0, pi] with rates")
    add_critical_line_options(p.add_argument_group("start on a critical line"))
    p.add_argument("--processes", type=int, default=2, metavar="N",
                   help="processes of this machine that build the tables (the region tables of a start with "
                        "velocity, the second-order tables; default 2; the tables do not depend on it)")
    p.add_argument("--chart", choices=("auto", "spindle", "band"), default="auto",
                   help="the region tables' chart: 'spindle' along Q_J,0^crit over the whole region of the energy, "
                        "'band' along Q_J,pi^crit over the band about it (its stretch follows the layer in which the "
                        "spin advance W turns by 2pi across that line: the one accurate at high amplitude); 'auto' "
                        "(default) takes the band from the energy of a release from rest at 0.65pi up")
    p.add_argument("--nodes", type=int, nargs=2, default=None, metavar=("NU", "NV"),
                   help="Chebyshev nodes of the region tables along and across the chart's line (default 128 64 for "
                        "the spindle, 80 96 for the band: interpolation error ~1e-10 to 2e-9; fewer are faster and "
                        "coarser, and the prediction then warns)")
    p.add_argument("--t-end", type=float, default=1000.0,
                   help=f"time span, 0 < T <= {av.MAX_MAXIMA:.0e} * T_theta/2 with T_theta the time between maxima "
                   f"of pure rocking (6.6e6 at theta0 = 0.95pi): at most {av.MAX_MAXIMA:.0e} maxima, held in "
                   "memory (default 1000)")
    p.add_argument("--json", action="store_true", help="print a one-object JSON summary on stdout (strict JSON: "
                   "undefined quantities are null)")
    p.add_argument("--check", action="store_true",
                   help="also run the direct ODE and print both, with relative errors")
    p.add_argument("--order", type=int, choices=(1, 2), default=None,
                   help="order of the map in eps: 2 adds the second-order kick (its tables are built once per body "
                        "and theta0 or energy, and cached; measured from rest at 0.95pi, its largest errors are a median 12x "
                        "smaller than order 1's at eps = 3e-3, 27x at 1e-3, 81x at 3e-4, docs/slow_validation.md); "
                        "default, the same as predict_slow_motion's: 2 for releases from rest in "
                        f"[{_LO:g}pi, {_HI:g}pi] (their second-order tables are built once per body and theta0), 1 for "
                        "starts with velocity and lower releases (theirs are per energy, several times dearer: ask "
                        "for them with --order 2; the costs: docs/performance.md)")
    p.add_argument("--period-doubling", action="store_true",
                   help="releases from rest: also compute the eps at which rocking about the stable axis "
                        "period-doubles from the exact one-step map (all orders in eps; seconds), beside the first-order "
                        "4/kappa and, with --order 2, the second-order map's")
    p.add_argument("--csv", type=output_path, default=None, metavar="DIR",
                   help=f"write the predicted maxima to DIR/{CSV_NAME} (t, Q_R, Q_J, Theta, phi, critical region, the "
                        "tangent vector's log-growth, and beyond_horizon: true past the predictability horizon; the "
                        "header records the parameters, the indicators, the horizon and the statistical prediction), "
                        f"and, when the ensemble ran (--statistics), its statistics to DIR/{STATISTICS_CSV}; DIR is "
                        "created if missing, an existing file is not overwritten without --force")
    p.add_argument("--plot", type=output_path, default=None, metavar="DIR",
                   help="draw the predicted slow orbit over the direct ODE's turning points (slow_orbit.png and .pdf "
                        "in DIR, created if missing; existing files are not overwritten without --force)")
    add_statistics_options(p)
    add_force_option(p)
    p.add_argument("--quiet", action="store_true", help="no progress bars (table builds, the --check ODE)")
    p.add_argument("--cached-only", action="store_true",
                   help="fail instead of building the averaging tables when none are cached for this body/theta0")
    p.set_defaults(run=run)


def _progress(args: argparse.Namespace) -> bool | None:
    """Progress bars on stderr, as every command shows them: on a terminal unless --quiet."""
    return False if args.quiet else None


def _fmt(x: Any) -> str:
    if x is None:
        return "n/a"
    return f"{x:.6g}" if isinstance(x, float) else str(x)


def _given(args: argparse.Namespace) -> str:
    """The body options the user gave, as typed (for error messages)."""
    return " ".join(f"{flag} {getattr(args, k)!r}" for k, flag in _BODY_OPTIONS if getattr(args, k) is not None)


def _body(args: argparse.Namespace, given: str) -> Any:
    """The body of the options; errors name the options the user gave (not a derived moment)."""
    eps_given = args.eps is not None
    if eps_given and args.I2 is not None:
        raise ValueError("give either --I2 or --eps, not both")
    if eps_given and not (math.isfinite(args.eps) and args.eps >= 0.0):
        raise ValueError(f"--eps must be a finite number >= 0 (the averaging holds for 0 <= eps with "
                         f"K = eps*kappa < 4), got --eps {args.eps!r}")
    if args.I2 is None and not eps_given:
        args.eps = args.eps_default
    try:
        sym = body_from_args(argparse.Namespace(**{**vars(args), "eps": None, "eps_default": 0.0}), gravity=True)
    except ValueError as exc:
        raise ValueError(f"the body options {given} give no valid body: {exc}" if given else str(exc)) from None
    if args.I2 is not None:
        return sym
    try:
        return sym.with_epsilon(args.eps)
    except ValueError as exc:
        what = f"--eps {args.eps!r}" if eps_given else f"the default --eps {args.eps!r} (give a smaller --eps)"
        raise ValueError(f"{what}: out of range for this body: {exc}") from None


def _parse(args: argparse.Namespace, option: str) -> float:
    try:
        return parse_angle(getattr(args, option))
    except ValueError as exc:
        raise ValueError(f"--{option}: {exc}") from None


def _from_state(args: argparse.Namespace, body: Any, start: Any,
                order: int) -> tuple[Any, dict[str, Any], list[str]]:
    """The prediction of ``order`` from a start with velocity, its extra summary entries and its warnings."""
    from rocknroller.analysis.slow.map.family import first_maximum
    from rocknroller.analysis.slow.map.region import load_or_build_region_table, region_options

    fm = first_maximum(body, start)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", av.AveragingValidityWarning)
        nu, nv = args.nodes if args.nodes is not None else (None, None)
        table = load_or_build_region_table(body, fm.E, build=not args.cached_only, workers=args.processes,
                                           progress=_progress(args), axis=args.chart, nu=nu, nv=nv)
        second = None
        if order == 2:
            from rocknroller.analysis.slow.map.second_order import load_or_build_second_order_region_table

            second = load_or_build_second_order_region_table(body, fm.E, build=not args.cached_only,
                                                             workers=args.processes, progress=_progress(args))
        pred = av.predict_slow_motion(body, start, t_end=args.t_end, table=table, order=order, second=second)
    messages = list(dict.fromkeys(str(w.message) for w in caught if issubclass(w.category, av.AveragingValidityWarning)))
    extra = {"start": {k: getattr(start, k) for k in ("theta", "phi", "psi", "theta_dot", "phi_dot", "psi_dot")},
             "E": fm.E, "first_maximum": {"t": fm.t, "theta": fm.theta, "QR": fm.QR, "QJ": fm.QJ},
             "table_interp_error": table.interp_error, "chart": region_options(body, fm.E, args.chart)[0]}
    return pred, extra, messages


def run(args: argparse.Namespace) -> int:
    """Run ``rocknroller slow`` with the parsed ``args``; returns the exit status."""
    from rocknroller.analysis.slow.dynamics.pendulum import pendulum_constants, pendulum_prediction
    from rocknroller.analysis.slow.dynamics.periodic_starts import on_rocking_axis, periodic_start
    from rocknroller.analysis.slow.map.tables_at_once import release_tables

    if args.plot is not None:
        prepare_output_dir(args.plot, "--plot", args.force, ["slow_orbit.png", "slow_orbit.pdf"])
    if args.csv is not None:
        prepare_output_dir(args.csv, "--csv", args.force, [CSV_NAME, STATISTICS_CSV])
    check_processes(args.processes, "--processes")
    given = _given(args)
    body = _body(args, given)
    if (rates_given(args) or args.critical_line is not None or _parse(args, "phi0") != 0.0
            or av.releases_on_region_tables(_parse(args, "theta0"))):
        if args.order == 2 and (args.nodes is not None or args.chart != "auto"):
            raise ValueError("--order 2 with a start with velocity (or a release below "
                             f"{_LO:g}pi) uses the second-order tables on the default region tables: leave out --nodes "
                             "and --chart")
        if args.period_doubling:
            raise ValueError("--period-doubling applies to releases from rest (the rocking it follows is that of the "
                             "release's energy): give --theta0 and --psi0 only")
        check_statistics_options(args, release=False)
        start, _ = critical_line_state(args, body)
        pred, extra, messages = _from_state(args, body, start, av.default_order(start) if args.order is None
                                            else args.order)
        summary: dict[str, Any] = {q: getattr(pred, q) for q in _QUANTITIES}
        summary.update({"K": pred.K, "order": pred.order, "line_slope": pred.line_slope, "pure_rocking": False,
                        "routh_sphere": body.is_symmetric,
                        "rocks_per_region": pred.rocks_per_region,
                        "region_runs": [list(r) for r in pred.region_runs or []],
                        "crossings": [list(c) for c in pred.crossings or []], "n_maxima": int(pred.series.t.size),
                        "eps": float(body.epsilon_text()), "theta0": start.theta, "psi0": start.psi,
                        "t_end": args.t_end,
                        "pendulum": None, "periodic_orbit": None, **extra})
        return _finish(args, body, pred, None, start, summary, messages)
    check_critical_line_options(args)  # --QR and --offset place a start on a line; a release reads neither
    check_statistics_options(args, release=True)
    if args.nodes is not None or args.chart != "auto":  # the release tables have their own chart and grid
        raise ValueError(f"--nodes and --chart set the region tables of a start with velocity (or of a release below "
                         f"{_LO:g}pi); a release from rest at --theta0 in [{_LO:g}pi, {_HI:g}pi] uses the release "
                         "tables: leave them out")
    theta0 = av.check_map_theta0(av.check_release_theta0(_parse(args, "theta0"), "--theta0"), "--theta0")
    psi0 = _parse(args, "psi0")
    unresolved = f"cannot be computed for --theta0 {args.theta0} and the body options {given} ({body.describe()})"
    try:
        consts = pendulum_constants(body, theta0)
    except (RuntimeError, ArithmeticError) as exc:
        raise ValueError(f"the closed-form constants {unresolved}: {exc}") from None
    av.check_t_end(args.t_end, consts.T0, "--t-end")
    check_statistics_work(args, body, theta0, av.default_order(theta0) if args.order is None else args.order)
    messages = []
    K = body.epsilon * consts.kappa
    if abs(K) > av.K_PERIOD_DOUBLING:
        messages.append(
            f"K = eps*kappa = {K:.4g} > {av.K_PERIOD_DOUBLING:g}: outside the valid range eps < {consts.eps_period_doubling:.4g} "
            "(pure rocking about the stable axis has period-doubled; the closed form does not apply)")
    order = av.default_order(theta0) if args.order is None else args.order
    try:
        table, second = release_tables(body, theta0, order if body.epsilon > 0.0 else 1, build=not args.cached_only,
                                       workers=args.processes, progress=_progress(args))
    except av.AveragingRangeError as exc:
        raise ValueError(f"--theta0 {args.theta0}: {exc}") from None
    except (RuntimeError, ArithmeticError) as exc:
        raise ValueError(f"the averaging tables {unresolved}: {exc}") from None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", av.AveragingValidityWarning)
        try:
            pred = av.predict_slow_motion(body, theta0, psi0, args.t_end, table=table, order=order, second=second)
        except av.ChartWidthError as exc:  # wider than the release tables: the region tables of its energy hold it
            start = av.EulerState(theta0, 0.0, psi0)
            pred, _, more = _from_state(args, body, start, av.default_order(start) if args.order is None else args.order)
            messages += [f"{exc}: predicted on the region tables of its energy (map of order {pred.order})", *more]
    pend = None
    try:
        pend = pendulum_prediction(body, theta0, psi0, args.t_end, constants=consts)
    except ValueError as exc:  # psi0 on the separatrix
        messages.append(f"closed form unavailable: {exc}")
    summary = {q: getattr(pred, q) for q in _QUANTITIES}
    # one key per meaning: pure_rocking, the release rocks in a vertical plane (eps = 0, or psi0 on a rocking axis,
    # where the map's fixed point is the periodic orbit "pure rocking"); routh_sphere, eps = 0 (no slow motion at all)
    summary.update({"K": K, "order": pred.order, "line_slope": pred.line_slope,
                    "pure_rocking": pred.pure_rocking or on_rocking_axis(psi0), "routh_sphere": pred.pure_rocking,
                    "rocks_per_region": pred.rocks_per_region,
                    "region_runs": [list(r) for r in pred.region_runs or []],
                    "crossings": [list(c) for c in pred.crossings or []], "n_maxima": int(pred.series.t.size),
                    "eps": float(body.epsilon_text()), "theta0": theta0, "psi0": psi0, "t_end": args.t_end})
    summary["periodic_orbit"] = periodic_summary(periodic_start(body, theta0, psi0, order=pred.order),
                                                 on_rocking_axis(psi0))
    # the release's constants, whether or not the closed form applies to its psi0 (on the separatrix it does not)
    summary["constants"] = {"kappa": consts.kappa, "eps_period_doubling": consts.eps_period_doubling,
                            "stable_psi": consts.stable_psi}
    summary["pendulum"] = None if pend is None else {
        **{q: getattr(pend, q) for q in _QUANTITIES}, "kappa": consts.kappa,
        "eps_period_doubling": consts.eps_period_doubling, "T0": consts.T0, "C0": list(consts.C0),
        "stable_psi": consts.stable_psi,
        "regime_ratio": None if math.isnan(pend.regime_ratio) else pend.regime_ratio}  # NaN for eps = 0
    if pend is not None and pred.pure_rocking:
        summary["pendulum"]["slow_period"] = None  # K = 0: no libration (the closed form's period is infinite)
    if args.period_doubling:
        from rocknroller.analysis.slow.dynamics.period_doubling import map_period_doubling, period_doubling

        pd = period_doubling(body, theta0)
        summary["period_doubling"] = {"eps_first_order": pd.eps_first_order, "eps_exact": pd.eps_exact,
                                      "K_exact": pd.K_exact, "correction": pd.correction,
                                      "stable_psi": pd.stable_psi,
                                      "eps_second_order": (map_period_doubling(body, theta0, 2, workers=args.processes)
                                                           if order == 2 else None)}
    return _finish(args, body, pred, pend, None, summary, messages)


def _finish(args: argparse.Namespace, body: Any, pred: Any, pend: Any, start: Any, summary: dict[str, Any],
            messages: list[str]) -> int:
    """The direct ODE (--check, --plot), the outputs and the exit status, for either kind of start."""
    theta0, psi0 = summary["theta0"], summary["psi0"]
    if summary["n_maxima"] == 0:  # no sample: the extents and the span are undefined (null), not 0
        for part in (summary, summary.get("pendulum") or {}):
            part.update(QR_extent=None, QJ_extent=None, Phi=None)
    ode = None
    if args.check or args.plot is not None:
        from rocknroller.papers.averaging_check import check_prediction, relative_errors

        check = check_prediction(body, pred, progress=_progress(args))
        ode = check.ode
        summary["ode"] = {q: getattr(ode, q) for q in _QUANTITIES}
        summary["rel_error"] = {q: check.rel_errors[q] for q in _QUANTITIES}
        if pred.pure_rocking:  # the ODE's Q, Θ are round-off about constants: no regions, period or relative errors
            summary["ode"].update(slow_period=None, region_runs=[], rocks_per_region={})
        else:
            summary["ode"]["region_runs"] = [list(r) for r in ode.region_runs]
            summary["ode"]["rocks_per_region"] = av.rocks_per_region(ode.region_runs)
        if pend is not None:
            summary["pendulum"]["rel_error"] = {q: summary["rel_error"][q] if pred.pure_rocking else
                                                relative_errors(pend, ode)[q] for q in _QUANTITIES}
    if summary["periodic_orbit"] is None:
        summary.update(chaos_summary(pred))
    else:
        apply_periodic(summary)
        note = "a periodic orbit of the map: its multipliers and residue give its stability"
        summary.update(chaos=None, horizon=None, beyond_horizon=None, chaos_note=note, horizon_note=note)
    off_tables = None
    if start is not None and not (rates_given(args) or args.critical_line is not None):
        off_tables = (f"a release from rest off the release tables (theta0 below {_LO:g}pi or --phi0 not 0) runs from "
                      f"its state on the region tables; the ensemble is a ball of release angles psi0 on the release "
                      f"tables, theta0 in [{_LO:g}pi, {_HI:g}pi] with --phi0 0")
    summary.update(statistics_summary(args, body, pred, summary, release=start is None, off_tables=off_tables))
    apply_trust(summary)
    horizon = None if summary["horizon"] is None else summary["horizon"]["t"]
    written = _plot(pred, ode, horizon, args.plot) if args.plot is not None else []
    if args.csv is not None:
        written.append(_write_csv(args.csv / CSV_NAME, pred, body, summary))
        if summary["statistics"] is not None:
            written.append(write_statistics_csv(args.csv / STATISTICS_CSV, body, summary))
    summary["warnings"] = messages
    for msg in messages:
        print(f"rocknroller slow: warning: {msg}", file=sys.stderr)
    if args.json:
        print_json(summary)
    else:
        _print_table(summary, body, theta0, psi0, args.t_end, start)
    for path in written:
        print(f"wrote {path}", file=sys.stderr)
    return 0


def _write_csv(path: Path, pred: Any, body: Any, s: dict[str, Any]) -> Path:
    """The predicted maxima with their regions, log-growth and ``beyond_horizon``; the header records the run."""
    import numpy as np

    from rocknroller.papers.output import angle_text, write_csv

    ser = pred.series
    t_h = None if s["horizon"] is None else (math.inf if s["horizon"]["t"] is None else s["horizon"]["t"])
    header = [f"rocknroller slow: body {body.describe()}; eps={body.epsilon_text()}; "
              f"theta0={angle_text(s['theta0'])}; psi0={angle_text(s['psi0'])}; t_end={s['t_end']!r}; "
              f"map of order {pred.order} in eps; K={s['K']!r}",
              "status of the summary's numbers: " + "; ".join(f"{src} {q} {st}" for src, marks in s["status"].items()
                                                              for q, st in marks.items()),
              *trust_lines(s), *chaos_lines(s), *statistics_lines(s),
              "columns: the maxima of theta: t, Q_R, Q_J, Theta = 2 psi (unwrapped), phi, critical region, "
              "log_growth = ln(|w|/|w0|) of the tangent vector since the map's start (empty without indicators), "
              "beyond_horizon (true past the predictability horizon: statistical only; empty without a horizon)"]
    n = ser.t.size
    ell = [None] * n if ser.log_growth is None else ser.log_growth
    beyond = [None] * n if t_h is None else ["true" if x else "false" for x in ser.t > t_h]
    regions = [None] * n if pred.regions is None else list(np.asarray(pred.regions))
    return write_csv(path, {"t": ser.t, "QR": ser.QR, "QJ": ser.QJ, "Theta": ser.Theta, "phi": ser.phi,
                            "region": regions, "log_growth": ell, "beyond_horizon": beyond}, header)


def _print_table(s: dict[str, Any], body, theta0: float, psi0: float, t_end: float, start: Any = None) -> None:
    from rocknroller.papers.output import angle_text

    print(f"body: {body.describe()}")
    if start is None:
        print(f"released from rest at theta0={angle_text(theta0)}, psi0={angle_text(psi0)}; t_end={t_end:g}; "
              f"K = eps*kappa = {s['K']:.4g}; map of order {s['order']} in eps")
    else:
        fm = s["first_maximum"]
        print(f"start: {start}; first maximum of theta at t={fm['t']:.6g} (theta={fm['theta']:.6g}, "
              f"Q_R={fm['QR']:.6g}, Q_J={fm['QJ']:.6g}); E={s['E']:.8g}; region tables interpolate to "
              f"{s['table_interp_error']:.1e}; t_end={t_end:g}; K = eps*kappa = {s['K']:.4g}")
    cols = ["quantity", "averaged map", "status", "closed form", "status"] + (
        ["direct ODE", "map rel.err", "closed rel.err"] if "ode" in s else [])
    rows = []
    pend = s["pendulum"] or {}
    status = s["status"]
    for q in _QUANTITIES:
        row = [q, _fmt(s[q]), status["map"][q], _fmt(pend.get(q)), status.get("closed_form", {}).get(q, "")]
        if "ode" in s:
            row += [_fmt(s["ode"][q]), _fmt(s["rel_error"][q]), _fmt((pend.get("rel_error") or {}).get(q))]
        rows.append(row)
    widths = [max(len(r[i]) for r in rows + [cols]) for i in range(len(cols))]
    for r in [cols] + rows:
        print("  ".join(x.ljust(w) for x, w in zip(r, widths)))
    constants = s.get("constants")
    if constants:
        print(f"kappa = {constants['kappa']:.6g}; period doubling of rocking about the stable axis "
              f"(psi = {constants['stable_psi']:.4g}) at eps = 4/kappa = {constants['eps_period_doubling']:.6g} to "
              "first order (K = eps*kappa = 4; --period-doubling: to all orders)")
    if s.get("pure_rocking") and pend.get("slow_period") is not None:
        print("closed form: its slow_period is that of small librations about this pure rocking (starts near it); "
              "the release itself is the fixed point, with no slow motion (the map's n/a)")
    if "period_doubling" in s:
        pd = s["period_doubling"]
        if pd["eps_second_order"] is not None:
            print(f"second-order map: period doubling at eps = {pd['eps_second_order']:.8g}")
        print(f"exact one-step map: period doubling at eps = {pd['eps_exact']:.8g} (first order 4/kappa = "
              f"{pd['eps_first_order']:.8g}; K = eps*kappa = {pd['K_exact']:.8g} = 4 {'-' if pd['correction'] < 0 else '+'} "
              f"{abs(pd['correction']):.4g} eps)")
    for line in trust_lines(s) + chaos_lines(s) + statistics_lines(s) + periodic_lines(s):
        print(line)
    if s["routh_sphere"]:
        print(_PURE_ROCKING)
        return
    if s["periodic_orbit"] is not None:
        return
    print(f"line of the turning points: dQ_J/dQ_R = {_fmt(s['line_slope'])}")
    runs = ", ".join(f"{lab}:{n}" for lab, n, _ in s["region_runs"])
    print(f"rocks per critical region (consecutive runs): {runs}")
    if "ode" in s:
        print(f"direct ODE runs:                             "
              f"{', '.join(f'{lab}:{n}' for lab, n, _ in s['ode']['region_runs'])}")


def _plot(pred, ode, horizon: float | None, out: Path) -> list[Path]:
    """The --plot figure, that of :meth:`SlowPrediction.plot` with the direct ODE beside the map
    (:func:`rocknroller.analysis.slow.dynamics.result_plots.plot_prediction`) and the summary's horizon, as PNG and
    PDF."""
    from rocknroller.analysis.slow.dynamics.result_plots import plot_prediction
    from rocknroller.papers.output import new_figure, save_figure

    fig = plot_prediction(pred, new_figure(figsize=(11, 4.2), layout="constrained"), horizon=horizon, ode=ode)
    return save_figure(fig, out, "slow_orbit")
