"""``rocknroller bifurcation``: the period doubling of rocking and the period-2 orbit, slow map against exact map."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

from rocknroller.analysis.slow.dynamics.periodic_orbits import MAX_BRANCH_POINTS
from rocknroller.cli.options import (add_body_options, add_budget_option, add_force_option, body_from_args,
                                     budget_from_args, output_path, parse_angle, prepare_output_dir, print_json)
from rocknroller.papers.bifurcation import EXACT_FRACTIONS


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``bifurcation`` subcommand and its ``--help`` to ``sub``."""
    p = sub.add_parser(
        "bifurcation",
        help="bifurcation diagram of rocking: its period doubling and the period-2 orbit, slow map against exact map",
        description="Find by Newton's method the rocking fixed points (about either principal axis) and, past the "
        "period doubling at eps_pd, the period-2 orbit of the slow map, continued in eps, and of the exact one-step "
        "map (the direct ODE from maximum to maximum of theta) at a few eps; their Greene residues R = (3 - tr M)/4 "
        "(stable for 0 < R < 1). Draws the standard map's angle Theta + W(Q)/2 at the kick and the residues against "
        "eps/eps_pd (slow map lines, solid stable and dashed unstable; exact map markers) and writes "
        "bifurcation.png, .pdf and .csv. The body's eps is the diagram's variable: give a, I1, I3, g only.",
    )
    add_body_options(p, asymmetry=False)
    p.add_argument("--theta0", action="append", default=None, metavar="ANGLE",
                   help="release angle (repeat for several; e.g. 0.95pi; default 0.9pi and 0.95pi)")
    p.add_argument("--theta0-range", default=None, metavar="LO:HI:N",
                   help="instead of the diagram: the period doubling's eps_pd over N release angles from LO to HI "
                        "(e.g. 0.8pi:0.99pi:60; N <= 400), at orders 1 (4/kappa) and 2 (the map's root), written to "
                        "period_doubling.png, .pdf and .csv; with the tables over energy (rocknroller warm --tables) "
                        "an angle needs no table build, else its tables are built")
    p.add_argument("--from", dest="lo", type=float, default=0.6, metavar="F",
                   help="first eps of the slow map's branches, as a fraction of eps_pd (default 0.6)")
    p.add_argument("--to", dest="hi", type=float, default=1.55, metavar="F",
                   help="last eps, as a fraction of eps_pd (default 1.55)")
    p.add_argument("--points", type=int, default=111,
                   help=f"values of eps on the branches, 3 to {MAX_BRANCH_POINTS} (default 111)")
    p.add_argument("--exact-at", type=float, nargs="+", default=None, metavar="F",
                   help="fractions of eps_pd, in (0, --to], at which the exact map's orbits are found (default: those "
                        f"of {' '.join(f'{f:g}' for f in EXACT_FRACTIONS)} up to --to)")
    p.add_argument("--order", type=int, choices=(1, 2), default=None,
                   help="order of the slow map (default 2, as rocknroller slow's for a release in the release tables' "
                        "range: the second-order tables are built once per body and theta0, then cached)")
    p.add_argument("--out", type=output_path, default=Path("."), metavar="DIR",
                   help="write bifurcation.png, .pdf and .csv to DIR (default: current directory; existing files are "
                        "not overwritten without --force)")
    add_force_option(p)
    p.add_argument("--cached-only", action="store_true",
                   help="fail instead of building the averaging tables when none are cached for this body/theta0")
    add_budget_option(p, "the diagram (its uncached tables, eps_pd, exact and slow orbits, files)")
    p.add_argument("--json", action="store_true", help="print a JSON summary (files, eps_pd, the period-2 points)")
    p.add_argument("--quiet", action="store_true", help="no progress bars (table builds)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run ``rocknroller bifurcation`` with the parsed ``args``; returns the exit status."""
    from rocknroller.analysis.slow.map.tables_at_once import release_tables
    from rocknroller.analysis.slow.prediction import default_order
    from rocknroller.analysis.slow.map.limits import check_map_theta0
    from rocknroller.numerics.budget import check_work
    from rocknroller.papers.bifurcation import (FILES_SECONDS, MAX_DIAGRAM_THETA0, MAX_EXACT_FRACTIONS, check_diagram_counts,
                                                _what, bifurcation_diagram, bifurcation_seconds)

    body = body_from_args(args, gravity=True)
    if args.theta0_range is not None:
        return _line(args, body)
    theta0s = [check_map_theta0(parse_angle(t, "--theta0")) for t in (args.theta0 or ["0.9pi", "0.95pi"])]
    exact_at = [f for f in EXACT_FRACTIONS if f <= args.hi] if args.exact_at is None else args.exact_at
    if len(theta0s) > MAX_DIAGRAM_THETA0:
        raise ValueError(f"--theta0 may be given at most {MAX_DIAGRAM_THETA0} times (a column of the figure each), "
                         f"got {len(theta0s)}")
    if len(exact_at) > MAX_EXACT_FRACTIONS:
        raise ValueError(f"--exact-at takes at most {MAX_EXACT_FRACTIONS} values (an exact-map solve each), got "
                         f"{len(exact_at)}")
    order = max(default_order(t) for t in theta0s) if args.order is None else args.order
    check_diagram_counts(args.points, exact_at)
    check_work(bifurcation_seconds(body, theta0s, args.points, exact_at, order, build=not args.cached_only)
               + FILES_SECONDS, _what(theta0s, args.points, exact_at, order), budget_from_args(args))  # before any work
    prepare_output_dir(args.out, "--out", args.force, ["bifurcation.png", "bifurcation.pdf", "bifurcation.csv"])
    progress = False if args.quiet else None
    for theta0 in theta0s:  # the tables first: --cached-only refuses before any work, --quiet hides their builds
        release_tables(body, theta0, order, build=not args.cached_only, progress=progress)
    paths, data = bifurcation_diagram(body, args.out, theta0s, fractions=(args.lo, args.hi), n_points=args.points,
                                      exact_fractions=tuple(exact_at), order=order,
                                      budget=budget_from_args(args))
    rows = [{"theta0": d.theta0, "eps": e.eps, "eps_over_pd": e.eps / d.eps_pd,
             "kick_phase": {"slow": s.kick_phase.tolist(), "exact": e.kick_phase.tolist()},
             "Theta": {"slow": s.points[:, 2].tolist(), "exact": e.points[:, 2].tolist()},
             "u": {"slow": float(s.points[0, 0]), "exact": float(e.points[0, 0])},
             "residue": {"slow": s.residue, "exact": e.residue}, "stable": {"slow": s.stable, "exact": e.stable}}
            for d in data for s, e in zip(d.slow_period2, d.exact_period2)]
    summary = {"files": [str(p) for p in paths], "order": order, "eps_pd": {f"{d.theta0 / math.pi:.6g}pi": d.eps_pd for d in data},
               "period2": rows}
    if args.json:
        print_json(summary)
    else:
        for d in data:
            print(f"theta0 = {d.theta0 / math.pi:.6g}pi: eps_pd = {d.eps_pd:.8g} (exact map); period-2 orbit, slow "
                  f"map (order {d.order}) against exact map:")
            for s, e in zip(d.slow_period2, d.exact_period2):
                print(f"  eps = {e.eps / d.eps_pd:.4g} eps_pd: kick phase {s.kick_phase[0]:.6f} / {e.kick_phase[0]:.6f} "
                      f"(differ by {abs(s.kick_phase[0] - e.kick_phase[0]):.2g}), Theta differs by "
                      f"{abs(s.points[0, 2] - e.points[0, 2]):.2g}; R = {s.residue:.5f} / {e.residue:.5f} "
                      f"({'stable' if s.stable else 'unstable'} / {'stable' if e.stable else 'unstable'})")
        for p in paths:
            print(f"wrote {p}")
    return 0


def _line(args: argparse.Namespace, body: Any) -> int:
    """``--theta0-range``: the period-doubling line over the release angles, its files and a line of text per angle."""
    from rocknroller.cli.atlas import angle_grid
    from rocknroller.numerics.budget import check_work
    from rocknroller.papers.bifurcation import FILES_SECONDS, line_seconds, period_doubling_line, period_doubling_plot

    if args.theta0 is not None:
        raise ValueError("give either --theta0 (the diagram at those angles) or --theta0-range (the period-doubling "
                         "line over a range), not both")
    theta0 = angle_grid(args.theta0_range, "--theta0-range")
    check_work(line_seconds(body, theta0, build=not args.cached_only) + FILES_SECONDS,
               f"the period-doubling line at {theta0.size} theta0", budget_from_args(args))  # before any work
    prepare_output_dir(args.out, "--out", args.force, ["period_doubling.png", "period_doubling.pdf",
                                                        "period_doubling.csv"])
    line = period_doubling_line(body, theta0, budget=None, progress=False if args.quiet else None)
    paths = period_doubling_plot(body, line, args.out)
    if args.json:
        print_json({"files": [str(p) for p in paths], "theta0": line.theta0.tolist(), "kappa": line.kappa.tolist(),
                    "eps_order1": line.eps_order1.tolist(), "eps_order2": line.eps_order2.tolist()})
    else:
        for t, e1, e2, K in zip(line.theta0, line.eps_order1, line.eps_order2, line.K_order2):
            print(f"theta0 = {t / math.pi:.6g}pi: eps_pd = {e1:.6g} (order 1, 4/kappa), {e2:.6g} (order 2), "
                  f"K = {K:.5f}")
        for p in paths:
            print(f"wrote {p}")
    return 0
