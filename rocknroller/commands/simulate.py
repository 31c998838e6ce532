"""``rocknroller simulate``: integrate the direct equations of motion and report the turning points."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from papers.lynch_bustamante import fig5_symmetry_breaking as fig5
from rocknroller.options import add_body_options, add_initial_state_options, body_from_args, initial_state_from_args


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "simulate",
        help="integrate the direct ODE (default: the paper's figure-5 run)",
        description="Integrate the rock'n'roller's equations of motion (singularity-free body frame; heyoka "
        "Taylor integrator or scipy DOP853) and find every turning point of the tilt theta. Defaults: the "
        "paper's body with eps=1e-3 and the figure-5 start theta0=0.95pi, omega=(0, 0.001, -0.001).",
    )
    add_body_options(p)
    add_initial_state_options(p)
    p.add_argument("--t-end", type=float, default=1500.0, help="final time (default 1500)")
    p.add_argument("--method", choices=("heyoka", "scipy"), default="heyoka", help="integrator (default heyoka)")
    p.add_argument("--dt", type=float, default=None, help="output spacing (default 0.05)")
    p.add_argument("--out", type=Path, default=None, metavar="DIR",
                   help="write samples.csv, turning_points.csv and PNG+PDF plots to DIR")
    p.add_argument("--json", action="store_true", help="print a one-object JSON summary on stdout")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(run=run, eps_default=fig5.EPSILONS[1], omega_default=fig5.OMEGA0)


def _write_outputs(traj, body, initial, out: Path) -> list[Path]:
    from papers.output import save_figure, write_csv
    from papers.trajectory_plots import plot_contact_track, plot_invariant_orbit, plot_phi_at_maxima

    header = [f"rocknroller simulate ({traj.method})", f"body: {body.describe()}", f"initial: {initial}"]
    w1, w2, w3 = traj.omega
    written = [write_csv(out / "samples.csv", {
        "t": traj.t, "theta": traj.theta, "phi": traj.phi, "psi": traj.psi, "w1": w1, "w2": w2, "w3": w3,
        "E": traj.E, "Q_J": traj.QJ, "Q_R": traj.QR, "X": traj.X, "Y": traj.Y}, header)]
    kinds = ["max"] * len(traj.maxima) + ["min"] * len(traj.minima)
    cols = {"kind": kinds}
    for name in ("t", "theta", "phi", "psi", "QR", "QJ"):
        cols[{"QR": "Q_R", "QJ": "Q_J"}.get(name, name)] = [*getattr(traj.maxima, name), *getattr(traj.minima, name)]
    written.append(write_csv(out / "turning_points.csv", cols, header))
    for name, plot in (("contact_track", plot_contact_track), ("phi_at_maxima", plot_phi_at_maxima),
                       ("QR_QJ_orbit", plot_invariant_orbit)):
        ax = plot(traj)
        ax.set_title(f"a={body.a:g}, I1={body.I1:g}, I3={body.I3:g}, eps={body.epsilon:.3g}", fontsize=9)
        written += save_figure(ax.figure, out, name)
    return written


def run(args: argparse.Namespace) -> int:
    from numerics.integrate import simulate

    if args.eps is None and args.I2 is None:
        args.eps = args.eps_default
    if args.omega is None and not (args.theta_dot0 or args.phi_dot0 or args.psi_dot0):
        args.omega = list(args.omega_default)
    body = body_from_args(args)
    initial = initial_state_from_args(args)
    traj = simulate(body, initial, args.t_end, method=args.method, dt=args.dt,
                    progress=None if not args.quiet else False)
    summary = {"energy_rel_error": traj.energy_rel_error, "n_maxima": len(traj.maxima),
               "n_minima": len(traj.minima), "Phi": traj.Phi, "t_end": args.t_end}
    written = _write_outputs(traj, body, initial, args.out) if args.out is not None else []
    if args.json:
        json.dump(summary, sys.stdout)
        sys.stdout.write("\n")
    else:
        print(f"body: {body.describe()}")
        print(f"initial: {initial}")
        print(f"method={traj.method}  t_end={args.t_end:g}  maxima={summary['n_maxima']}  "
              f"minima={summary['n_minima']}  Phi={summary['Phi']:.6f} rad  "
              f"energy_rel_error={summary['energy_rel_error']:.2e}")
    for path in written:
        print(f"wrote {path}", file=sys.stderr)
    return 0
