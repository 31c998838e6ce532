"""``rocknroller atlas``: the averaged slow map over a plane of releases from rest, confirmed by the direct ODE."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

from rocknroller.options import (add_body_options, add_cluster_options, add_force_option, body_from_args,
                                 cluster_from_args, parse_angle, prepare_output_dir, print_json)

#: Files written to --out.
OUTPUTS = ("atlas.csv", "atlas.png", "atlas.pdf", "atlas_check.png", "atlas_check.pdf")


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``atlas`` subcommand and its ``--help`` to ``sub``."""
    p = sub.add_parser(
        "atlas",
        help="map recession over a plane of releases from rest (averaged map, ODE-confirmed sample)",
        description="For every release from rest (theta0, psi0) of a grid, the eps-averaged slow map's slow period, "
        "azimuth span Phi, Q_R and Q_J extents and full-angle / visible-angle reversals per 1000 time units; heat "
        "maps (PNG and PDF) with the paper's starts starred, the data as CSV, and the direct ODE at 1 point in "
        "--confirm-every (and at the --confirm points) with the map's errors there, run in this process or on a "
        "dask cluster (--scheduler / --workers; the numbers do not depend on where). Tables are built once per "
        "body and theta0 and cached (release tables for theta0 >= 0.75pi, region tables below).",
    )
    add_body_options(p, eps_default=1e-3)
    p.add_argument("--theta0", type=str, default="0.8pi:0.95pi:16", metavar="LO:HI:N",
                   help="release tilts, an inclusive grid of N values (angles like 0.95pi), or one value; "
                        "0 < theta0 <= 0.999pi (default 0.8pi:0.95pi:16)")
    p.add_argument("--psi0", type=str, default="0.02pi:0.48pi:16", metavar="LO:HI:N",
                   help="release spin angles, as --theta0 (default 0.02pi:0.48pi:16: psi0 = 0 and pi/2 are the "
                        "unstable and stable rocking, where a run is the equilibrium and its round-off)")
    p.add_argument("--t-end", type=float, default=1000.0, help="time span of each run (default 1000)")
    p.add_argument("--confirm-every", type=int, default=50, metavar="K",
                   help="run the direct ODE at 1 point in K, row by row from the first (default 50; 0: none)")
    p.add_argument("--confirm", action="append", default=[], metavar="THETA0,PSI0",
                   help="also confirm the grid point nearest to THETA0,PSI0 (repeatable)")
    p.add_argument("--processes", type=int, default=2, metavar="N",
                   help="processes that share the map's rows (default 2; the numbers do not depend on it)")
    add_cluster_options(p)
    p.add_argument("--out", type=Path, default=Path("atlas"), metavar="DIR",
                   help="write atlas.csv and the figures to DIR (default ./atlas; created if missing; existing files "
                        "are not overwritten without --force)")
    add_force_option(p)
    p.add_argument("--cached-only", action="store_true",
                   help="fail instead of building the averaging tables of a theta0 when none are cached")
    p.add_argument("--json", action="store_true", help="print a one-object JSON summary on stdout")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    p.set_defaults(run=run)


def angle_grid(text: str, name: str) -> np.ndarray:
    """``LO:HI:N`` (an inclusive grid of N ≥ 1 angles) or one angle; angles as :func:`parse_angle` reads them."""
    from rocknroller.analysis.atlas import MAX_ATLAS_POINTS

    parts = str(text).split(":")
    try:
        if len(parts) == 1:
            return np.array([parse_angle(parts[0])])
        if len(parts) == 3 and parts[2].strip().isdigit() and 1 <= int(parts[2]) <= MAX_ATLAS_POINTS:
            return np.linspace(parse_angle(parts[0]), parse_angle(parts[1]), int(parts[2]))
    except ValueError:
        pass
    raise ValueError(f"{name} must be an angle or a grid LO:HI:N with 1 <= N <= {MAX_ATLAS_POINTS} "
                     f"(e.g. 0.8pi:0.95pi:16), got {text!r}")


def _nearest(atlas: Any, text: str) -> tuple[int, int]:
    try:
        t0, p0 = (parse_angle(s) for s in text.split(","))
    except ValueError:
        raise ValueError(f"--confirm must be THETA0,PSI0 (e.g. 0.95pi,pi/4), got {text!r}") from None
    return int(np.argmin(np.abs(atlas.theta0 - t0))), int(np.argmin(np.abs(atlas.psi0 - p0)))


def run(args: argparse.Namespace) -> int:
    """Run ``rocknroller atlas`` with the parsed ``args``; returns the exit status."""
    from rocknroller.analysis.atlas import ATLAS_OBSERVABLES, atlas_from_rest, confirm_atlas
    from rocknroller.papers.atlas_plots import plot_atlas, plot_atlas_check
    from rocknroller.papers.output import write_csv

    body = body_from_args(args)
    theta0, psi0 = angle_grid(args.theta0, "--theta0"), angle_grid(args.psi0, "--psi0")
    scheduler, workers = cluster_from_args(args)
    if args.confirm_every < 0:
        raise ValueError(f"--confirm-every must be an integer >= 0, got {args.confirm_every!r}")
    prepare_output_dir(args.out, "--out", args.force, OUTPUTS)
    progress = False if args.quiet else None
    atlas = atlas_from_rest(body, theta0, psi0, args.t_end, progress=progress, build=not args.cached_only,
                            workers=args.processes)
    named = [_nearest(atlas, s) for s in args.confirm]
    check = None
    if args.confirm_every > 0 or named:
        check = confirm_atlas(atlas, body, every=args.confirm_every or None, points=named, scheduler=scheduler,
                              workers=workers, progress=progress)
    where = scheduler or (f"a local dask cluster of {workers} workers" if workers else "this process")
    title = (f"eps={body.epsilon:.3g}, releases from rest, t_end={args.t_end:g}; "
             f"{0 if check is None else len(check.index)} points confirmed by the direct ODE ({where})")
    header = [f"rocknroller atlas: body {body.describe()}", f"theta0 grid {args.theta0}, psi0 grid {args.psi0}, "
              f"t_end {args.t_end:g}", f"direct ODE at 1 point in {args.confirm_every} and {len(named)} named "
              f"points, run in {where}", "reversals per 1000 time units; ode_* and err_* only at confirmed points "
              "(err: map/ODE - 1, or map - ODE for the reversal counts)"]
    TH, PS = np.meshgrid(atlas.theta0, atlas.psi0, indexing="ij")
    cols: dict[str, list] = {"theta0": TH.ravel().tolist(), "psi0": PS.ravel().tolist()}
    for name in ATLAS_OBSERVABLES:
        cols[name] = atlas.values[name].ravel().tolist(fill_value=None)  # undefined: an empty cell
    n_p = atlas.psi0.size
    for prefix, src in (("ode_", None if check is None else check.ode), ("err_", None if check is None else
                                                                          check.rel_error)):
        for name in ATLAS_OBSERVABLES:
            col: list = [None] * TH.size
            if src is not None:
                for (i, j), v in zip(check.index, src[name].tolist(fill_value=None)):
                    col[i * n_p + j] = v
            cols[prefix + name] = col
    written = [write_csv(args.out / "atlas.csv", cols, header)]
    written += plot_atlas(atlas, args.out, title)
    if check is not None:
        written += plot_atlas_check(atlas, check, args.out, title)
    summary: dict[str, Any] = {"n_points": int(TH.size), "n_confirmed": 0 if check is None else len(check.index),
                               "warnings": list(atlas.warnings), "files": [str(p) for p in written]}
    if check is not None:
        summary["max_abs_error"] = {n: (None if np.ma.count(check.rel_error[n]) == 0 else
                                        float(np.ma.max(np.ma.abs(check.rel_error[n])))) for n in ATLAS_OBSERVABLES}
    for msg in atlas.warnings:
        print(f"rocknroller atlas: warning: {msg}", file=sys.stderr)
    if args.json:
        print_json(summary)
    else:
        print(f"atlas of {summary['n_points']} releases from rest, {summary['n_confirmed']} confirmed by the ODE")
        for n, v in (summary.get("max_abs_error") or {}).items():
            print(f"  largest map-ODE {'difference' if n.endswith('reversals') else 'relative error'} of {n}: "
                  f"{'n/a' if v is None else f'{v:.3g}'}")
    for path in written:
        print(f"wrote {path}", file=sys.stderr)
    return 0
