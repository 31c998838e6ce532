"""``rocknroller portrait``: the phase portrait of the slow motion, the averaged map's orbits from a grid of starts in the
(Θ, p) plane of the standard map and in the (Q_R, Q_J) plane over the critical lines, with the direct ODE's θ-maxima
of chosen starts overlaid (:mod:`rocknroller.papers.portrait`)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from rocknroller.cli.options import (add_body_options, add_budget_option, add_force_option, body_from_args,
                                     budget_from_args, output_path, parse_angle, prepare_output_dir, print_json)

#: Files written to --out.
OUTPUTS = ("portrait.png", "portrait.pdf", "portrait.csv", "portrait_orbits.csv")
#: Default asymmetry: K = eps kappa = 2.1 at theta0 = 0.95pi, a mixed phase space (islands and a chaotic sea).
EPS_DEFAULT = 5e-3
#: Default grid of Theta = 2 psi.
THETA_DEFAULT = "0.05pi:1.95pi:12"
#: Largest --values file read (bytes): one number a line for at most MAX_PORTRAIT_ORBITS = 10 000 orbits at up to
#: 25 characters each is 250 kB.
MAX_VALUES_BYTES = 1_000_000


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``portrait`` subcommand and its ``--help`` to ``sub``."""
    p = sub.add_parser(
        "portrait",
        help="phase portrait of the slow motion: the averaged map's orbits in the (Theta, p) and (Q_R, Q_J) planes",
        description="At (body, theta0 or E, eps), iterate the eps-averaged slow map from a grid of starts in the "
        "(Theta, p) plane of the standard map (Theta = 2 psi at a maximum of theta, p = gradW(0).Q; the start's Q lies "
        "on the kick direction of the release tables, with the energy of the release from rest at theta0) and draw "
        "every orbit at its maxima in the (Theta mod 2pi, p) plane and in the (Q_R, Q_J) plane over the critical "
        "lines, coloured by one value per orbit (--values, else the orbit's MEGNO: the map's tangent vector along "
        "the orbit, colours clipped at 5, above 3 chaotic, grey for an orbit of fewer than 8 maxima), with the "
        "releases from rest "
        "marked (the line p = 0, the point Q = 0) and the direct ODE's maxima from the --ode-start starts overlaid. "
        "Writes portrait.png, portrait.pdf, portrait.csv (every sample, header with the parameters) and "
        "portrait_orbits.csv (every orbit: its start, verdict, MEGNO, Lyapunov exponent, the span they are "
        "measured over, and its predictability horizon with the method that found it, from a direct run of 40 rocks "
        "per orbit as for rocknroller slow); --json lists the same per orbit.",
    )
    add_body_options(p, eps_default=EPS_DEFAULT)
    p.add_argument("--theta0", type=str, default=None,
                   help="release angle of the tables, in [0.75pi, 0.999pi] (default 0.95pi); exclusive with --E")
    p.add_argument("--E", type=float, default=None,
                   help="energy instead of --theta0: that of the release from rest at the theta0 with U(theta0) = E")
    p.add_argument("--Theta", type=str, default=THETA_DEFAULT, metavar="LO:HI:N",
                   help=f"grid of Theta = 2 psi, in [-2pi, 2pi] (default {THETA_DEFAULT})")
    p.add_argument("--p", type=str, default=None, metavar="LO:HI:N",
                   help="grid of p = gradW(0).Q, within the tables (default: 9 values over +-1.5 times the half-width "
                        "2 sqrt(K) of the main resonance)")
    p.add_argument("--t-end", type=float, default=2000.0,
                   help="time span of each orbit (default 2000); every orbit is kept, drawn and written whole, so the "
                        "theta-maxima of all orbits and direct runs (about t_end/T_theta(0) each) are limited: past "
                        "the limit the command refuses before any work, naming it and the memory and CSV size they "
                        "would take")
    p.add_argument("--order", type=int, choices=(1, 2), default=None,
                   help="order of the map in eps (default 2, as rocknroller slow's for a release in the release "
                        "tables' range: the second-order tables are built once per body and theta0, then cached)")
    p.add_argument("--ode-start", action="append", default=[], metavar="THETA,P",
                   help="overlay the direct ODE's maxima from this start (Theta, p), e.g. 0.2,0 for the release from "
                        "rest at psi0 = 0.1; repeat for more (default: none)")
    p.add_argument("--ode-t-end", type=float, default=None, help="time span of the direct runs (default --t-end)")
    p.add_argument("--values", type=output_path, default=None, metavar="FILE",
                   help="colour the orbits by the numbers in FILE, one per orbit in grid order (Theta outer, p inner; "
                        f"numpy.loadtxt; a regular file of at most {MAX_VALUES_BYTES:,} bytes); default: the orbit's "
                        "MEGNO")
    p.add_argument("--out", type=output_path, default=Path("portrait"), metavar="DIR",
                   help="write portrait.png, .pdf and .csv to DIR (default ./portrait; existing files are not "
                        "overwritten without --force)")
    add_force_option(p)
    add_budget_option(p, "the portrait (its uncached tables, orbits, direct runs, horizon probes and files)")
    p.add_argument("--cached-only", action="store_true",
                   help="fail instead of building the averaging tables when none are cached for this body/theta0")
    p.add_argument("--json", action="store_true", help="print a one-object JSON summary on stdout")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    p.set_defaults(run=run)


def _grid(text: str, option: str) -> np.ndarray:
    """``LO:HI:N`` or one value, as ``rocknroller atlas`` reads its grids."""
    from rocknroller.cli.atlas import angle_grid

    return angle_grid(text, option)


def _ode_start(text: str) -> tuple[float, float]:
    try:
        Th, p = text.split(",")
        return parse_angle(Th), float(p)
    except ValueError:
        raise ValueError(f"--ode-start must be THETA,P (e.g. 0.2,0 or pi/2,1.5), got {text!r}") from None


def read_values(path: Path, n_orbits: int) -> np.ndarray:
    """The ``n_orbits`` numbers of the --values file at ``path``, or a ValueError naming --values: anything but a
    regular file of at most ``MAX_VALUES_BYTES`` is refused before it is read (a FIFO is opened without waiting for a
    writer, a device such as /dev/zero is never read)."""
    import io
    import os
    import stat

    def refuse(why: str) -> ValueError:
        return ValueError(f"--values must be a regular file of at most {MAX_VALUES_BYTES:,} bytes (numbers, one per "
                          f"orbit), got {str(path)!r}: {why}")

    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as exc:
        raise refuse(exc.strerror or str(exc)) from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise refuse("not a regular file")
        if info.st_size > MAX_VALUES_BYTES:
            raise refuse(f"{info.st_size:,} bytes")
        with os.fdopen(fd, "rb", closefd=False) as fh:
            data = fh.read(MAX_VALUES_BYTES + 1)
    finally:
        os.close(fd)
    if len(data) > MAX_VALUES_BYTES:  # it grew while being read
        raise refuse(f"more than {MAX_VALUES_BYTES:,} bytes")
    try:
        values = np.atleast_1d(np.loadtxt(io.StringIO(data.decode("utf-8")), dtype=float))
    except (UnicodeDecodeError, ValueError) as exc:
        raise ValueError(f"--values: cannot read numbers from {str(path)!r} ({exc})") from None
    if values.shape != (n_orbits,) or not np.all(np.isfinite(values)):
        raise ValueError(f"--values must hold {n_orbits} finite numbers, one per orbit of the grid (Theta outer, p "
                         f"inner), got {values.size} numbers ({int(np.sum(~np.isfinite(values)))} not finite) in "
                         f"{str(path)!r}")
    return values


def run(args: argparse.Namespace) -> int:
    """Run ``rocknroller portrait`` with the parsed ``args``; returns the exit status."""
    from rocknroller.numerics.megno import MEGNO_CHAOTIC
    from rocknroller.analysis.slow.prediction import default_order
    from rocknroller.papers.portrait import N_P_DEFAULT, slow_portrait, theta0_of_energy
    from rocknroller.papers.portrait_limits import MAX_PORTRAIT_ORBITS
    from rocknroller.analysis.slow.dynamics.chaos import CRITERION
    from rocknroller.numerics.budget import check_work
    from rocknroller.papers.portrait_limits import check_portrait_size, portrait_seconds
    from rocknroller.papers.portrait_output import orbit_rows, write_portrait

    body = body_from_args(args, gravity=True)
    if args.E is not None and args.theta0 is not None:
        raise ValueError("give either --theta0 or --E, not both")
    theta0 = theta0_of_energy(body, args.E) if args.E is not None else parse_angle(args.theta0 or "0.95pi",
                                                                                     "--theta0")
    Theta = _grid(args.Theta, "--Theta")
    p = None if args.p is None else _grid(args.p, "--p")
    starts = [_ode_start(s) for s in args.ode_start]
    n_orbits = Theta.size * (N_P_DEFAULT if p is None else p.size)
    values = None
    if args.values is not None:
        values = read_values(args.values, n_orbits)
    order = default_order(theta0) if args.order is None else args.order
    ode_t_end = args.t_end if args.ode_t_end is None else args.ode_t_end
    if n_orbits <= MAX_PORTRAIT_ORBITS and 0.0 < args.t_end < np.inf and 0.0 < ode_t_end < np.inf:
        # (else slow_portrait refuses them itself, naming them)
        from rocknroller.analysis.slow.map.limits import check_map_theta0

        check_portrait_size(body, check_map_theta0(theta0), n_orbits, args.t_end,
                            [ode_t_end] * len(starts))  # memory first
        seconds, what = portrait_seconds(body, theta0, n_orbits, args.t_end, order=order,
                                         ode_t_ends=[ode_t_end] * len(starts), horizons=True, files=True)
        check_work(seconds, what, budget_from_args(args))  # all of the command's work, before any of it
    prepare_output_dir(args.out, "--out", args.force, OUTPUTS)
    progress = False if args.quiet else None
    portrait = slow_portrait(body, theta0, Theta, p, args.t_end, order=order, ode_starts=starts,
                             ode_t_end=args.ode_t_end, build=not args.cached_only, progress=progress,
                             budget=budget_from_args(args))
    # each orbit's verdict and horizon (a short direct run each; their cost checked above), once for CSV and JSON
    rows = orbit_rows(portrait, budget=None)
    paths = write_portrait(portrait, args.out, values=values, rows=rows)
    summary: dict[str, Any] = {
        "body": body.describe(), "theta0": portrait.theta0, "E": portrait.E, "K": portrait.K,
        "order": portrait.order, "t_end": portrait.t_end, "n_orbits": len(portrait.orbits),
        "left_tables": list(portrait.left), "n_ode": len(portrait.ode), "files": [str(q) for q in paths]}
    megno = portrait.megno
    measured = megno[np.isfinite(megno)]
    summary.update(n_megno=int(measured.size), n_chaotic=int(np.sum(measured > MEGNO_CHAOTIC)),
                   verdicts={v: rows["verdict"].count(v) for v in ("regular", "chaotic", "undecided")},
                   criterion=CRITERION, span="each orbit's run, from its start to its last maximum before t_end",
                   megno_range=[float(measured.min()), float(measured.max())] if measured.size else None,
                   orbits=[dict(zip(rows, r)) for r in zip(*rows.values())])
    if args.json:
        print_json(summary)
    else:
        print(f"body: {body.describe()}; theta0 = {theta0 / np.pi:.6g} pi (E = {portrait.E:.6g}), "
              f"K = eps kappa = {portrait.K:.4g}, map order {portrait.order}, t_end = {portrait.t_end:g}")
        print(f"{len(portrait.orbits)} orbits of the map, {len(portrait.ode)} direct runs; {summary['n_chaotic']} of "
              f"the {summary['n_megno']} orbits with a MEGNO are chaotic (MEGNO > {MEGNO_CHAOTIC:g})")
        if portrait.left:
            print(f"{len(portrait.left)} orbits left the tables before t_end (drawn up to there): "
                  f"{list(portrait.left)}")
        for q in paths:
            print(f"wrote {q}")
    return 0
