"""``rocknroller simulate``: integrate the direct equations of motion and report the turning points."""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

from rocknroller.analysis.model.body import Body
from rocknroller.cli.options import (add_body_options, add_budget_option, add_force_option, add_initial_state_options,
                                     add_offset_option, budget_from_args, initial_state_from_args, output_path,
                                     prepare_output_dir, print_json, sphere_from_args, start_with_default_rates)
from rocknroller.papers.lynch_bustamante import fig5_symmetry_breaking as fig5

#: Files written to --out (with samples), and with --turning-points-only.
OUTPUTS = ("samples.csv", "turning_points.csv", "contact_track.png", "contact_track.pdf", "phi_at_maxima.png",
           "phi_at_maxima.pdf", "QR_QJ_orbit.png", "QR_QJ_orbit.pdf")
OUTPUTS_TURNING_POINTS = ("turning_points.csv", "phi_at_maxima.png", "phi_at_maxima.pdf", "QR_QJ_orbit.png",
                          "QR_QJ_orbit.pdf")
_TP_COLUMNS = ("kind", "t", "theta", "phi", "psi", "Q_R", "Q_J", "X", "Y")
#: The outputs that hold the paper's Q_R and Q_J, defined for a mass centre on the third axis only (a Body).
_PAPER_ONLY = ("QR_QJ_orbit.png", "QR_QJ_orbit.pdf", "Q_R", "Q_J")


def _for_body(names: tuple[str, ...], body) -> tuple[str, ...]:
    """``names`` without the paper's Q_R and Q_J outputs unless ``body`` is a Body (the mass centre on the axis)."""
    return names if isinstance(body, Body) else tuple(n for n in names if n not in _PAPER_ONLY)
#: Written to --out with --chaos.
OUTPUT_CHAOS = "chaos.csv"


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``simulate`` subcommand and its ``--help`` to ``sub``."""
    from rocknroller.numerics.integrate import MAX_DENSE_RADIANS, MAX_GRID_POINTS, MAX_RADIANS, MAX_SAMPLES
    from rocknroller.numerics.run_limits import DEFAULT_TOL, TOL_MAX

    eps = fig5.EPSILONS[1]
    p = sub.add_parser(
        "simulate",
        help="integrate the direct ODE (default: the paper's figure-5 run)",
        description="Integrate the rock'n'roller's equations of motion (singularity-free body frame; heyoka "
        "Taylor integrator or scipy DOP853) and find every turning point of the tilt theta. Defaults: the "
        f"paper's body with eps={eps:g} and the figure-5 start theta0=0.95pi, omega=(0, 0.001, -0.001) "
        "(used only when no rate option is given). Runs are limited to what fits in memory and time: with samples, "
        f"at most {MAX_SAMPLES:,} of them and Lambda t_end <= {MAX_DENSE_RADIANS:g} radians (Lambda bounds |omega|; "
        "about one integration step per radian); --turning-points-only streams the turning points and keeps no "
        f"samples, up to Lambda t_end <= {MAX_RADIANS:g} and {MAX_GRID_POINTS:g} points of the --dt grid.",
    )
    add_body_options(p, eps_default=eps)
    add_offset_option(p)
    add_initial_state_options(p, rates_note="with none of --theta-dot0/--phi-dot0/--psi-dot0/--omega given, "
                              "simulate starts with the figure-5 omega = (0, 0.001, -0.001)")
    p.add_argument("--t-end", type=float, default=1500.0, help="final time (default 1500)")
    p.add_argument("--method", choices=("heyoka", "scipy"), default="heyoka", help="integrator (default heyoka)")
    p.add_argument("--tol", type=float, default=None,
                   help=f"heyoka's tolerance, in [{DEFAULT_TOL!r}, {TOL_MAX:g}] (default: the machine epsilon, "
                        f"{DEFAULT_TOL!r}); 1e-11 gives DOP853's best energy error at a lower Taylor order "
                        "(--chaos keeps the default)")
    p.add_argument("--dt", type=float, default=None,
                   help="output spacing (default 0.15/Lambda, about 0.05 for the paper's runs; Lambda bounds |omega|)")
    p.add_argument("--turning-points-only", action="store_true",
                   help="keep only the turning points and the invariants there (memory does not grow with t_end); "
                        "with --out, turning_points.csv is written as the run goes")
    p.add_argument("--chaos", action="store_true",
                   help="also integrate a tangent vector along the orbit (heyoka's variational equations, whatever "
                        "--method) and print MEGNO, the finite-time Lyapunov exponent per unit time and per rock, and "
                        "the verdict (chaotic when MEGNO > 3) from its samples at the theta-maxima; with --out, "
                        f"{OUTPUT_CHAOS} holds them at every maximum (needs at least 8 maxima before --t-end)")
    p.add_argument("--strict", action="store_true",
                   help="fail (exit 1) instead of warning when the energy error exceeds what the integrator's "
                        "tolerance allows")
    p.add_argument("--out", type=output_path, default=None, metavar="DIR",
                   help="write samples.csv, turning_points.csv and PNG+PDF plots to DIR (created if missing; "
                        "existing files are not overwritten without --force)")
    add_force_option(p)
    add_budget_option(p, "the run")
    p.add_argument("--json", action="store_true", help="print a one-object JSON summary on stdout")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(run=run)


def _header(method: str, body, initial) -> list[str]:
    return [f"rocknroller simulate ({method})", f"body: {body.describe()}", f"initial: {initial}"]


def _turning_point_columns(maxima, minima) -> dict[str, list]:
    cols: dict[str, list] = {"kind": ["max"] * len(maxima) + ["min"] * len(minima)}
    pairs = (("t", "t"), ("theta", "theta"), ("phi", "phi"), ("psi", "psi"), ("Q_R", "QR"), ("Q_J", "QJ"))
    for name, attr in pairs:
        if name in _for_body((name,), maxima.body):
            cols[name] = [*getattr(maxima, attr), *getattr(minima, attr)]
    cols["X"] = [*maxima.states[:, 9], *minima.states[:, 9]]
    cols["Y"] = [*maxima.states[:, 10], *minima.states[:, 10]]
    return cols


def _plots(traj, body, out: Path, names: tuple[str, ...]) -> list[Path]:
    from rocknroller.numerics.trajectory_plots import plot_contact_track, plot_invariant_orbit, plot_phi_at_maxima
    from rocknroller.papers.output import save_figure

    written = []
    for name, plot in (("contact_track", plot_contact_track), ("phi_at_maxima", plot_phi_at_maxima),
                       ("QR_QJ_orbit", plot_invariant_orbit)):
        if f"{name}.png" in _for_body(names, body):
            ax = plot(traj)
            title = (f"a={body.a:g}, I1={body.I1:g}, I3={body.I3:g}, eps={body.epsilon:.3g}" if isinstance(body, Body)
                     else f"{body.kind}: c=({', '.join(f'{v:g}' for v in body.offset)}), "
                          f"I=({body.I1:g}, {body.I2:g}, {body.I3:g})")
            ax.set_title(title, fontsize=9)
            written += save_figure(ax.figure, out, name)
    return written


def _write_outputs(traj, body, initial, out: Path) -> list[Path]:
    from rocknroller.papers.output import write_csv

    header = _header(traj.method, body, initial)
    w1, w2, w3 = traj.omega
    columns = {"t": traj.t, "theta": traj.theta, "phi": traj.phi, "psi": traj.psi, "w1": w1, "w2": w2, "w3": w3,
               "E": traj.E}
    if isinstance(body, Body):
        columns.update({"Q_J": traj.QJ, "Q_R": traj.QR})
    written = [write_csv(out / "samples.csv", {**columns, "X": traj.X, "Y": traj.Y}, header)]
    written.append(write_csv(out / "turning_points.csv", _turning_point_columns(traj.maxima, traj.minima), header))
    return written + _plots(traj, body, out, OUTPUTS)


def _chaos(body, initial, args: argparse.Namespace, budget, written: list[Path]) -> dict | None:
    """With --chaos: the direct motion's chaos indicators (a summary for the JSON), and chaos.csv with --out."""
    if not args.chaos:
        return None
    from rocknroller.numerics.megno import MEGNO_CHAOTIC
    from rocknroller.numerics.variational import direct_chaos_indicators
    from rocknroller.papers.output import write_csv

    run = direct_chaos_indicators(body, initial, args.t_end, budget=budget, strict=args.strict)
    ind = run.indicators
    if args.out is not None:
        header = _header("heyoka, variational", body, initial) + [
            f"MEGNO={ind.megno!r} lambda={ind.lyapunov!r} per time unit, {ind.lyapunov_per_rock!r} per rock; "
            f"tangent norm |dgamma|^2 + |domega|^2/Lambda^2, Lambda={run.rate!r}",
            "rows: the theta-maxima; log_growth = ln|w(t)|/|w(0)| of the tangent vector, mean_megno = <Y> there"]
        written.append(write_csv(args.out / OUTPUT_CHAOS, {"t": ind.t, "theta": run.theta_maxima,
                                                         "log_growth": ind.log_growth,
                                                         "mean_megno": ind.mean_megno}, header))
    return {"megno": ind.megno, "lyapunov": ind.lyapunov, "lyapunov_per_rock": ind.lyapunov_per_rock,
            "lyapunov_time": ind.lyapunov_time, "regular": ind.regular, "megno_threshold": MEGNO_CHAOTIC,
            "n_maxima": len(ind.t), "energy_rel_error": run.energy_rel_error, "tangent_rate_scale": run.rate}


def run(args: argparse.Namespace) -> int:
    """Run ``rocknroller simulate`` with the parsed ``args``; returns the exit status."""
    from rocknroller.numerics.integrate import AccuracyWarning, simulate
    from rocknroller.numerics.run_limits import check_tol
    from rocknroller.papers.output import CsvStream

    if args.tol is not None and args.method != "heyoka":
        raise ValueError(f"--tol is heyoka's tolerance (--method heyoka), got --tol {args.tol!r} with --method "
                         f"{args.method}")
    tol = None if args.tol is None else check_tol(args.tol, "--tol")
    body = sphere_from_args(args)
    initial = initial_state_from_args(args)
    initial = start_with_default_rates(args, initial)
    tp_only = args.turning_points_only
    if args.out is not None:
        names = _for_body(OUTPUTS_TURNING_POINTS if tp_only else OUTPUTS, body)
        names += (OUTPUT_CHAOS,) if args.chaos else ()
        prepare_output_dir(args.out, "--out", args.force, names)
    kw = dict(method=args.method, tol=tol, dt=args.dt, progress=None if not args.quiet else False, strict=args.strict,
              budget=budget_from_args(args))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", AccuracyWarning)
        if tp_only and args.out is not None:
            with CsvStream(args.out / "turning_points.csv", _for_body(_TP_COLUMNS, body),
                           _header(args.method, body, initial) + ["rows: the turning points of each stretch, "
                                                                  "maxima then minima"]) as stream:
                traj = simulate(body, initial, args.t_end, samples=False,
                                on_turning_points=lambda mx, mn: stream.write(_turning_point_columns(mx, mn)), **kw)
            written = [stream.path] + _plots(traj, body, args.out, OUTPUTS_TURNING_POINTS)
        else:
            traj = simulate(body, initial, args.t_end, samples=not tp_only, **kw)
            written = _write_outputs(traj, body, initial, args.out) if args.out is not None else []
        chaos = _chaos(body, initial, args, kw["budget"], written)  # its AccuracyWarning is caught here too
    messages = [str(w.message) for w in caught if issubclass(w.category, AccuracyWarning)]
    for w in caught:  # the others (an unusable cache, ...) reach the user too, on stderr, never in the JSON's stdout
        if not issubclass(w.category, AccuracyWarning):
            print(f"rocknroller simulate: warning: {w.message}", file=sys.stderr)
    summary = {"energy_rel_error": traj.energy_rel_error, "energy_tolerance": traj.energy_tolerance,
               "n_maxima": len(traj.maxima), "n_minima": len(traj.minima), "Phi": traj.Phi, "t_end": args.t_end,
               "n_steps": traj.n_steps, "warnings": messages}
    if chaos is not None:
        summary["chaos"] = chaos
    for msg in messages:
        print(f"rocknroller simulate: warning: {msg}", file=sys.stderr)
    if args.json:
        print_json(summary)
    else:
        print(f"body: {body.describe()}")
        print(f"initial: {initial}")
        print(f"method={traj.method}  t_end={args.t_end:g}  maxima={summary['n_maxima']}  "
              f"minima={summary['n_minima']}  Phi={summary['Phi']:.6f} rad  "
              f"energy_rel_error={summary['energy_rel_error']:.2e} (E(0) + g a scale)")
        if chaos is not None:
            print(f"chaos: MEGNO={chaos['megno']:.4g}  lambda={chaos['lyapunov']:.4g} per time unit "
                  f"({chaos['lyapunov_per_rock']:.4g} per rock)  over {chaos['n_maxima']} maxima: "
                  f"{'regular' if chaos['regular'] else 'chaotic'} (MEGNO {'<=' if chaos['regular'] else '>'} "
                  f"{chaos['megno_threshold']:g})")
    for path in written:
        print(f"wrote {path}", file=sys.stderr)
    return 0
