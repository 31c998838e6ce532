"""``rocknroller diagram``: the four critical regions (paper fig. 4), optionally with a simulated orbit (figs. 7–10)."""

from __future__ import annotations

import argparse
from pathlib import Path

from rocknroller.cli.options import (add_body_options, add_critical_line_options, add_force_option,
                                     add_initial_state_options, body_from_args, critical_line_state, output_path,
                                     prepare_output_dir, print_json)

#: Defaults of the paper's critical-line runs (§numerics "Recession and Criticality"): ε = 1e-3, θ0 = 0.95π, ψ0 = π/4, 200 time units.
SIM_EPS, SIM_PSI0, SIM_T_END = 1e-3, "pi/4", 200.0


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``diagram`` subcommand and its ``--help`` to ``sub``."""
    p = sub.add_parser(
        "diagram",
        help="critical Jellett lines and regions I-IV (paper fig. 4), optionally with a simulated orbit",
        description="Draw the (Q_R, Q_J) plane with the critical lines Q_J = Q_J,pi^crit (red) and Q_J = Q_J,0^crit "
        "(blue, dashed), the four regions, and V_phi(theta) at one representative point of each region. With "
        "--simulate, integrate the direct ODE (same initial-state options as 'simulate'; defaults: the paper's "
        f"critical-line runs, eps={SIM_EPS:g}, theta0=0.95pi, psi0={SIM_PSI0}, t_end={SIM_T_END:g}) and overlay the "
        "orbit (Q_R(t), Q_J(t)) with dots at the theta-maxima (red) and minima (blue) (paper figs. 7-10).",
    )
    add_body_options(p, eps_default=0.0)
    p.add_argument("--QR-max", type=float, default=1.0, metavar="Q",
                   help="half-width of the Q_R axis without --simulate (default 1)")
    p.add_argument("--out", type=output_path, default=Path("."), metavar="DIR",
                   help="write regions[_orbit].png and .pdf to DIR (default: current directory; existing files "
                        "are not overwritten without --force)")
    add_force_option(p)
    p.add_argument("--json", action="store_true", help="print a JSON summary (files, representative points, crossings)")
    sim = p.add_argument_group("orbit overlay")
    sim.add_argument("--simulate", action="store_true",
                     help=f"integrate the direct ODE and overlay its orbit (eps defaults to {SIM_EPS:g} then)")
    sim.add_argument("--t-end", type=float, default=SIM_T_END, help=f"final time (default {SIM_T_END:g})")
    sim.add_argument("--method", choices=("heyoka", "scipy"), default="heyoka", help="integrator (default heyoka)")
    add_critical_line_options(sim)
    add_initial_state_options(p, psi0_default=SIM_PSI0)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run ``rocknroller diagram`` with the parsed ``args``; returns the exit status."""
    from rocknroller.analysis.criticality import lines as crit
    from rocknroller.analysis.criticality import reversals
    from rocknroller.papers.output import save_figure
    from rocknroller.papers.plotting import region_diagram

    summary: dict = {}
    traj = None
    name = "regions_orbit" if args.simulate else "regions"
    prepare_output_dir(args.out, "--out", args.force, [f"{name}.png", f"{name}.pdf"])
    if args.simulate:
        from rocknroller.numerics.integrate import simulate

        if args.eps is None and args.I2 is None:
            args.eps = SIM_EPS
        body = body_from_args(args)
        initial, start = critical_line_state(args, body)
        traj = simulate(body, initial, args.t_end, method=args.method)
        ra = reversals.reversal_analysis(traj)
        summary.update({
            "initial": {"theta0": initial.theta, "psi0": initial.psi, "phi_dot0": initial.phi_dot,
                        "psi_dot0": initial.psi_dot},
            "QR0": float(traj.QR[0]), "QJ0": float(traj.QJ[0]),
            "region0": str(crit.region(traj.QR[0], traj.QJ[0], body)),
            "crossings_QJ0crit": ra.count("0"), "crossings_QJpicrit": ra.count("pi"),
            "energy_rel_error": traj.energy_rel_error,
        })
    else:
        if args.critical_line is not None or args.QR is not None or args.offset is not None:
            raise ValueError("--critical-line, --QR and --offset need --simulate")
        body = body_from_args(args)
    fig, data = region_diagram(body, QR_max=args.QR_max, traj=traj)
    paths = save_figure(fig, args.out, name)
    summary["files"] = [str(p) for p in paths]
    summary["representatives"] = {k: list(v) for k, v in data.representatives.items()}
    if args.json:
        print_json(summary)
    else:
        print(f"body: {body.describe()}")
        print(f"Q_J,0^crit = {float(crit.QJ_crit_0(1.0, body)):.12g} Q_R,  "
              f"Q_J,pi^crit = {float(crit.QJ_crit_pi(1.0, body)):.12g} Q_R")
        if traj is not None:
            where = summary["region0"] if summary["region0"].startswith("on ") else f"in {summary['region0']}"
            print(f"start (Q_R, Q_J) = ({summary['QR0']:.6g}, {summary['QJ0']:.6g}) {where}; "
                  f"crossings of Q_J,0^crit: {summary['crossings_QJ0crit']}, of Q_J,pi^crit: "
                  f"{summary['crossings_QJpicrit']} (t_end={args.t_end:g})")
        for p in paths:
            print(f"wrote {p}")
    return 0
