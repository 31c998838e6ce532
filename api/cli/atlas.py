"""``rocknroller atlas``: the slow motion over a plane of starts (releases from rest, or initial rates), by the
averaged map confirmed by the direct ODE, or by the direct ODE."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

from rocknroller.cli.options import (accept_negative_values, add_body_options, add_budget_option, add_cluster_options,
                                     add_force_option, body_from_args, budget_from_args, cluster_from_args, output_path,
                                     parse_angle, prepare_output_dir, print_json)

#: Files written to --out.
OUTPUTS = ("atlas.csv", "atlas.png", "atlas.pdf", "atlas_check.png", "atlas_check.pdf")


#: Grid defaults per plane (the rates plane: the paper's reversal starts, figs. 7-11, at theta0 = 0.95pi, psi0 = pi/4).
DEFAULTS = {"release": {"theta0": "0.8pi:0.95pi:16", "psi0": "0.02pi:0.48pi:16", "method": "map"},
            "rates": {"theta0": "0.95pi", "psi0": "pi/4", "phi_dot0": "-0.05:0.45:26", "psi_dot0": "-0.05:0.45:26",
                      "method": "ode"}}
#: Default --confirm-every of a map-made atlas.
CONFIRM_EVERY = 50


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``atlas`` subcommand and its ``--help`` to ``sub``."""
    rel, rat = DEFAULTS["release"], DEFAULTS["rates"]
    p = sub.add_parser(
        "atlas",
        help="map recession over a plane of starts: releases from rest (theta0, psi0) or rates (phi_dot0, psi_dot0)",
        description="Over a grid of starts, the slow period, azimuth span Phi, Q_R and Q_J extents and full-angle / "
        "visible-angle reversals per 1000 time units; heat maps (PNG and PDF) with the paper's starts starred, the "
        "data as CSV. --plane release: releases from rest over (theta0, psi0), by the eps-averaged map (tables built "
        "once per body and theta0 and cached) with the direct ODE at 1 point in --confirm-every (and at the "
        "--confirm points) and the map's errors there, or by the direct ODE everywhere (--method ode). --plane "
        "rates: initial rates (phi_dot0, psi_dot0) at one theta0, psi0 (default the paper's reversal starts, "
        "figs. 7-11), by the direct ODE (each start has its own energy, and the map's tables are per energy), with "
        "the critical lines drawn. The direct runs, and the nodes of the map's tables not yet cached, go in this "
        "process or on a dask cluster (--scheduler / --workers); the numbers do not depend on where.",
    )
    add_body_options(p, eps_default=1e-3)
    accept_negative_values(p)
    p.add_argument("--plane", choices=tuple(DEFAULTS), default="release",
                   help="release: (theta0, psi0) from rest; rates: (phi_dot0, psi_dot0) at fixed theta0, psi0 "
                        "(default release)")
    p.add_argument("--method", choices=("map", "ode"), default=None,
                   help="the averaged map (release plane only; of order 1 in eps, which every output names: order 2 "
                        "would build a second-order table per theta0 of the grid) or the direct ODE at every point "
                        "(default: map for the release plane, ode for the rates plane)")
    p.add_argument("--theta0", type=str, default=None, metavar="LO:HI:N",
                   help="tilts, an inclusive grid of N values (angles like 0.95pi), or one value; 0 < theta0 <= "
                        f"0.999pi (default {rel['theta0']}; with --plane rates one value, default {rat['theta0']})")
    p.add_argument("--psi0", type=str, default=None, metavar="LO:HI:N",
                   help=f"spin angles, as --theta0 (default {rel['psi0']}: psi0 = 0 and pi/2 are the unstable and "
                        f"stable rocking, where a run is the equilibrium and its round-off; with --plane rates one "
                        f"value, default {rat['psi0']})")
    p.add_argument("--phi-dot0", type=str, default=None, metavar="LO:HI:N",
                   help=f"--plane rates: initial precession rates, a grid as --theta0 (default {rat['phi_dot0']})")
    p.add_argument("--psi-dot0", type=str, default=None, metavar="LO:HI:N",
                   help=f"--plane rates: initial spin rates, a grid as --theta0 (default {rat['psi_dot0']})")
    p.add_argument("--t-end", type=float, default=1000.0, help="time span of each run (default 1000)")
    p.add_argument("--confirm-every", type=int, default=None, metavar="K",
                   help=f"the map: run the direct ODE at 1 point in K, row by row from the first (default "
                        f"{CONFIRM_EVERY}; 0: none)")
    p.add_argument("--confirm", action="append", default=[], metavar="THETA0,PSI0",
                   help="the map: also confirm the grid point nearest to THETA0,PSI0 (repeatable)")
    p.add_argument("--processes", type=int, default=2, metavar="N",
                   help="processes of this machine that share the map's rows, and threads that build the map's "
                        "uncached tables (all their nodes at once) or share the direct runs when they run in this "
                        "process (default 2; the numbers do not depend on it). --workers is another thing: dask's "
                        "worker processes, for the map's tables or the direct runs")
    add_cluster_options(p)
    p.add_argument("--out", type=output_path, default=Path("atlas"), metavar="DIR",
                   help="write atlas.csv and the figures to DIR (default ./atlas; created if missing; existing files "
                        "are not overwritten without --force)")
    add_force_option(p)
    add_budget_option(p, "the atlas and its ODE confirmation together (the map's uncached tables, runs and chaos "
                         "layer, the direct and variational runs, the files; or the direct runs of --method ode)")
    p.add_argument("--no-chaos", action="store_true",
                   help="the map: leave out the chaos layer (the map's MEGNO and Lyapunov exponent, ~1.5-1.8x the "
                        "map's own cost, and the direct runs' variational equations at the confirmed points, ~1-3x a "
                        "plain run each); an atlas by the direct ODE has none")
    p.add_argument("--cached-only", action="store_true",
                   help="the map: fail instead of building the averaging tables of a theta0 when none are cached")
    p.add_argument("--order", type=int, choices=(1, 2), default=None,
                   help="the map's order in eps (default: 2 where the tables over energy, rocknroller warm --tables, "
                        "cover every theta0 of the grid, else 1: a second-order table per row would be built; the "
                        "costs: docs/performance.md)")
    p.add_argument("--json", action="store_true", help="print a one-object JSON summary on stdout")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    p.set_defaults(run=run)


def angle_grid(text: str, name: str) -> np.ndarray:
    """``LO:HI:N`` (an inclusive grid of N ≥ 1 values) or one value; angles (and rates) as :func:`parse_angle` reads
    them."""
    from rocknroller.analysis.slow.atlas import MAX_ATLAS_POINTS

    parts = str(text).split(":")
    try:
        if len(parts) == 1:
            return np.array([parse_angle(parts[0])])
        if len(parts) == 3 and parts[2].strip().isdigit() and 1 <= int(parts[2]) <= MAX_ATLAS_POINTS:
            return np.linspace(parse_angle(parts[0]), parse_angle(parts[1]), int(parts[2]))
    except ValueError:
        pass
    raise ValueError(f"{name} must be a value or a grid LO:HI:N with 1 <= N <= {MAX_ATLAS_POINTS} "
                     f"(e.g. 0.8pi:0.95pi:16), got {text!r}")


def _nearest(atlas: Any, text: str) -> tuple[int, int]:
    try:
        t0, p0 = (parse_angle(s) for s in text.split(","))
    except ValueError:
        raise ValueError(f"--confirm must be THETA0,PSI0 (e.g. 0.95pi,pi/4), got {text!r}") from None
    return int(np.argmin(np.abs(atlas.rows - t0))), int(np.argmin(np.abs(atlas.cols - p0)))


def _grids(args: argparse.Namespace) -> tuple[str, dict[str, str]]:
    """The method and the grid texts of the chosen plane (defaults filled), refusing options of the other plane or
    of the other method."""
    d = DEFAULTS[args.plane]
    method = args.method or d["method"]
    if args.plane == "release" and (args.phi_dot0 is not None or args.psi_dot0 is not None):
        raise ValueError("--phi-dot0 and --psi-dot0 set the rates plane: give them with --plane rates")
    if args.plane == "rates" and method == "map":
        raise ValueError("--method map covers the release plane only: each start of the rates plane has its own "
                         "energy, and the map's tables are per energy; use --method ode")
    if method == "ode" and (args.confirm_every is not None or args.confirm or args.cached_only or args.no_chaos):
        raise ValueError("--confirm-every, --confirm, --cached-only and --no-chaos apply to --method map (an atlas "
                         "made by the direct ODE is its own confirmation, and has no chaos layer)")
    texts = {k: d[k] if getattr(args, k) is None else getattr(args, k) for k in d if k != "method"}  # "" is refused
    return method, texts


def _check_map_atlas_work(body: Any, theta0: np.ndarray, psi0: np.ndarray, args: argparse.Namespace,
                          confirm_every: int, budget: float | None) -> None:
    """Refuse a map-made atlas whose work together, the atlas's (its uncached tables, runs and chaos layer, its
    files) and its confirmation's (the direct and variational runs), is estimated over ``budget``, before any of it."""
    from rocknroller.analysis.slow.atlas import MAX_ATLAS_POINTS, atlas_seconds
    from rocknroller.analysis.slow.atlas_check import confirm_seconds
    from rocknroller.numerics.budget import check_work

    if theta0.size * psi0.size > MAX_ATLAS_POINTS:
        return  # atlas_from_rest refuses the grid itself
    chaos = not args.no_chaos
    seconds, what = atlas_seconds(body, theta0, psi0.size, args.t_end, chaos=chaos, build=not args.cached_only,
                                  files=True, order=args.order)
    if confirm_every > 0 or args.confirm:
        from types import SimpleNamespace

        named = [_nearest(SimpleNamespace(rows=theta0, cols=psi0), s) for s in args.confirm]
        more, also = confirm_seconds(body, theta0, psi0, args.t_end, every=confirm_every or None, points=named,
                                     chaos=chaos)
        seconds, what = seconds + more, f"{what} and {also}"
    check_work(seconds, what, budget)


def run(args: argparse.Namespace) -> int:
    """Run ``rocknroller atlas`` with the parsed ``args``; returns the exit status."""
    from rocknroller.analysis.slow.atlas import atlas_from_rest, atlas_of_rates
    from rocknroller.analysis.slow.atlas_check import confirm_atlas
    from rocknroller.papers.atlas_plots import plot_atlas, plot_atlas_check
    from rocknroller.papers.output import write_csv

    body = body_from_args(args, gravity=True)
    method, texts = _grids(args)
    grids = {k: angle_grid(v, "--" + k.replace("_", "-")) for k, v in texts.items()}
    scheduler, workers = cluster_from_args(args)
    threads = args.processes if scheduler is None and workers is None else None
    confirm_every = CONFIRM_EVERY if args.confirm_every is None else args.confirm_every
    if confirm_every < 0:
        raise ValueError(f"--confirm-every must be an integer >= 0, got {confirm_every!r}")
    if args.plane == "rates":
        for name in ("theta0", "psi0"):
            if grids[name].size != 1:
                raise ValueError(f"--{name} must be one value with --plane rates, got {texts[name]!r}")
    prepare_output_dir(args.out, "--out", args.force, OUTPUTS)
    progress = False if args.quiet else None
    budget = budget_from_args(args)
    if args.plane == "rates":
        atlas = atlas_of_rates(body, float(grids["theta0"][0]), float(grids["psi0"][0]), grids["phi_dot0"],
                               grids["psi_dot0"], args.t_end, progress=progress, scheduler=scheduler,
                               workers=workers, threads=threads, budget=budget)
    else:
        if method == "map" and 0.0 < args.t_end < np.inf:  # (else atlas_from_rest refuses t_end itself)
            _check_map_atlas_work(body, grids["theta0"], grids["psi0"], args, confirm_every, budget)
        atlas = atlas_from_rest(body, grids["theta0"], grids["psi0"], args.t_end, method=method, progress=progress,
                                build=not args.cached_only, processes=args.processes, scheduler=scheduler,
                                workers=workers, threads=threads, budget=budget,
                                chaos=method == "map" and not args.no_chaos, order=args.order)
    names = atlas.observables
    named = [_nearest(atlas, s) for s in args.confirm]
    check = None
    if method == "map" and (confirm_every > 0 or named):
        check = confirm_atlas(atlas, body, every=confirm_every or None, points=named, scheduler=scheduler,
                              workers=workers, threads=threads, progress=progress, budget=budget)
    where = scheduler or (f"a local dask cluster of {workers} workers" if workers else "this process")
    starts = ("releases from rest" if atlas.at is None else  # at: (theta0, psi0) of a rates plane, None for release
              f"theta0={atlas.at[0] / np.pi:.4g}pi, psi0={atlas.at[1] / np.pi:.4g}pi, theta_dot0=0")
    if method == "map":
        how = (f"averaged map of order {atlas.order} in eps; {0 if check is None else len(check.index)} points "
               f"confirmed by the direct ODE ({where})")
    else:
        how = f"direct ODE at every point ({where})"
    title = f"eps={body.epsilon:.3g}, {starts}, t_end={args.t_end:g}; {how}"
    header = [f"rocknroller atlas: body {body.describe()}",
              f"plane {args.plane} ({starts}), " + ", ".join(f"{k} grid {v}" for k, v in texts.items())
              + f", t_end {args.t_end:g}", f"method {method}: {how}",
              "reversals per 1000 time units; ode_* and err_* only at confirmed points "
              "(err: map/ODE - 1, or map - ODE for the reversal counts, megno and lyapunov)"]
    if "megno" in names:
        header.append("megno, lyapunov: the map's MEGNO and finite-time Lyapunov exponent per unit time over the span "
                      f"that rocknroller slow uses, max(t_end = {args.t_end:g}, 1000 rocks) (criterion: regular if "
                      "MEGNO <= 3, else chaotic); ode_megno, ode_lyapunov: the direct motion's (variational equations "
                      "over the same span); verdict_agrees: the same regular/chaotic verdict")
    R, C = np.meshgrid(atlas.rows, atlas.cols, indexing="ij")
    cols: dict[str, list] = {atlas.row_name: R.ravel().tolist(), atlas.col_name: C.ravel().tolist()}
    for name in names:
        cols[name] = atlas.values[name].ravel().tolist(fill_value=None)  # undefined: an empty cell
    n_c = atlas.cols.size
    if method == "map":
        for prefix, src in (("ode_", None if check is None else check.ode),
                            ("err_", None if check is None else check.rel_error)):
            for name in names:
                col: list = [None] * R.size
                if check is not None and src is not None:  # src: a table of check
                    for (i, j), v in zip(check.index, src[name].tolist(fill_value=None)):
                        col[i * n_c + j] = v
                cols[prefix + name] = col
        if "megno" in names:
            col = [None] * R.size
            if check is not None:
                for (i, j), v in zip(check.index, check.verdict_agrees.tolist(fill_value=None)):
                    col[i * n_c + j] = None if v is None else str(bool(v)).lower()
            cols["verdict_agrees"] = col
    written = [write_csv(args.out / "atlas.csv", cols, header)]
    written += plot_atlas(atlas, args.out, title, body)
    if check is not None:
        written += plot_atlas_check(atlas, check, args.out, title)
    summary: dict[str, Any] = {"plane": args.plane, "method": method,
                               "order": atlas.order, "n_points": int(R.size),
                               "n_confirmed": 0 if check is None else len(check.index),
                               "warnings": list(atlas.warnings), "files": [str(p) for p in written]}
    if check is not None:
        summary["max_abs_error"] = {n: (None if np.ma.count(check.rel_error[n]) == 0 else
                                        float(np.ma.max(np.ma.abs(check.rel_error[n])))) for n in names}
        if "megno" in names:
            summary["chaos"] = _verdicts(atlas, check)
    if "megno" in names:
        reg = atlas.regular
        summary["map_regular_fraction"] = None if np.ma.count(reg) == 0 else float(np.ma.mean(reg))
    for msg in atlas.warnings:
        print(f"rocknroller atlas: warning: {msg}", file=sys.stderr)
    if args.json:
        print_json(summary)
    else:
        print(f"atlas of {summary['n_points']} starts ({args.plane} plane, {how})")
        for n, v in (summary.get("max_abs_error") or {}).items():
            kind = "difference" if n.endswith("reversals") or n in ("megno", "lyapunov") else "relative error"
            print(f"  largest map-ODE {kind} of {n}: {'n/a' if v is None else f'{v:.3g}'}")
        if summary.get("map_regular_fraction") is not None:
            print(f"  the map calls {summary['map_regular_fraction']:.1%} of the starts regular (MEGNO <= 3)")
        ch = summary.get("chaos")
        if ch is not None:
            print(f"  regular/chaotic verdict: map and ODE agree at {ch['agree']} of {ch['n']} confirmed points"
                  + "".join(f"\n    differs at theta0={d['theta0'] / np.pi:.4g}pi, psi0={d['psi0'] / np.pi:.4g}pi: "
                            f"MEGNO map {d['map_megno']:.3g}, ODE {d['ode_megno']:.3g}" for d in ch["disagreements"]))
    for path in written:
        print(f"wrote {path}", file=sys.stderr)
    return 0


def _verdicts(atlas: Any, check: Any) -> dict[str, Any]:
    """The agreement of the map's regular/chaotic verdict with the ODE's at the confirmed points, and every
    disagreement with both MEGNO values."""
    flags = check.verdict_agrees.tolist(fill_value=None)
    bad = [k for k, v in enumerate(flags) if v is False]
    return {"n": sum(v is not None for v in flags), "agree": sum(v is True for v in flags),
            "fraction": check.verdict_agreement,
            "disagreements": [{"theta0": float(atlas.rows[check.index[k, 0]]),
                               "psi0": float(atlas.cols[check.index[k, 1]]), "map_megno": float(check.map["megno"][k]),
                               "ode_megno": float(check.ode["megno"][k])} for k in bad]}
