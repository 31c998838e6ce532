"""``rocknroller table``: precession table of Routh's sphere over a grid of (Q_R, Q_J) or (E, Q_R, Q_J)."""

from __future__ import annotations

import argparse
import sys
import time
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np

from rocknroller.analysis.routh.quadrature import DEFAULT_RTOL, RTOL_RANGE, check_rtol
from rocknroller.cli.options import (add_body_options, add_budget_option, add_force_option, body_from_args,
                                     budget_from_args, output_path, parse_angle, prepare_output_dir,
                                     prepare_output_file, print_json)
from rocknroller.numerics.budget import check_work, mp_point_seconds

COLUMNS = ("Q_R", "Q_J", "E", "theta_N", "theta_X", "T_theta", "tau", "delta_phi", "delta_psi", "visible_phi",
           "region", "status")

#: Status values written to the CSV (explained in its header).
STATUS_LEGEND = {
    "ok": "rocking between theta_N and theta_X",
    "theta0_is_theta_N": "theta0 is the LOWER turning point here (U'(theta0) < 0); the row describes that motion",
    "no_motion": "E < min U(theta): F(theta) < 0 on all of (0, pi), no motion; numeric cells empty",
    "steady_rolling": "double root theta_N = theta_X (steady circular rolling), not integrated; cells empty",
    "unresolved": "not resolved to full accuracy in double precision (near-steady rolling); rerun with --dps",
}
_CHUNK = 2048
#: Largest grid (number of points) in double precision (≈ 40 µs and ≈ 0.5 kB per point) and with --dps (≈ 0.4 s each).
MAX_POINTS = 500_000
MAX_POINTS_MP = 2_000
#: The figure's files, written to --plot DIR.
FIGURES = ("precession_table.png", "precession_table.pdf")


def parse_grid(text: str, name: str) -> np.ndarray:
    """``start:stop:count`` (inclusive linspace, count ≥ 1) or a single number."""
    parts = str(text).split(":")
    try:
        if len(parts) == 1:
            values = np.array([float(parts[0])])
        elif len(parts) == 3:
            count = int(parts[2])
            if count < 1 or str(count) != parts[2].strip():
                raise ValueError
            if count > MAX_POINTS:
                raise OverflowError
            start, stop = float(parts[0]), float(parts[1])
            if not (np.isfinite(start) and np.isfinite(stop)):
                raise ValueError
            values = np.linspace(start, stop, count)
        else:
            raise ValueError
    except OverflowError:
        raise ValueError(f"{name}: COUNT must be at most {MAX_POINTS} (the largest table), got {text!r}") from None
    except ValueError:
        raise ValueError(f"{name} must be a number or a grid START:STOP:COUNT with integer COUNT >= 1 "
                         f"(e.g. -0.01:0.01:201), got {text!r}") from None
    if not np.all(np.isfinite(values)):
        raise ValueError(f"{name} must be finite, got {text!r}")
    return values


def check_moments(body: Any) -> None:
    """Refuse moments outside ``rocknroller.numerics.integrate.MOMENT_RANGE``, the range ``simulate`` accepts: far
    outside it the quadrature's sums overflow (I3 = 1e300 left 20 of 25 points unresolved)."""
    from rocknroller.numerics.integrate import MOMENT_RANGE

    lo, hi = MOMENT_RANGE
    for name in ("I3", "I1", "I2"):  # I3 first: I1 (and I2) derive from it by default
        value = getattr(body, name)
        if not lo <= value <= hi:
            raise ValueError(f"{name} must lie in [{lo:g}, {hi:g}] (units of m R^2, the range simulate accepts), "
                             f"got {name}={value!r}")


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``table`` subcommand and its ``--help`` to ``sub``."""
    p = sub.add_parser(
        "table",
        help="precession table of Routh's sphere (T_theta, tau, delta_phi, delta_psi) over a (Q_R, Q_J) grid",
        description="Rocking period and precession angles of Routh's sphere (I1 = I2) by quadrature "
        "(paper eq. (22)), over a grid of Routh's and Jellett's quantities with the turning point "
        "theta_X = theta0 fixed (default), or over a grid of (E, Q_R, Q_J). T_theta is the time between "
        "successive maxima of theta; the paper's tau = 2 T_theta. Grid points without motion are kept "
        "with an explanatory status and empty cells.",
    )
    add_body_options(p)
    p.add_argument("--QR", default="-0.01:0.01:21", metavar="GRID",
                   help=f"Routh's quantity: START:STOP:COUNT or a number (default -0.01:0.01:21); the whole grid has "
                        f"at most {MAX_POINTS} points")
    p.add_argument("--QJ", default="-0.01:0.01:21", metavar="GRID",
                   help="Jellett's quantity: START:STOP:COUNT or a number (default -0.01:0.01:21)")
    p.add_argument("--theta0", default=None,
                   help="turning point theta_X = theta0 held fixed, in (0, pi); accepts 0.95pi (default 0.95pi)")
    p.add_argument("--E", default=None, metavar="GRID",
                   help="energy grid instead of --theta0: tabulate over (E, Q_R, Q_J)")
    p.add_argument("--per", choices=("T_theta", "tau"), default="T_theta",
                   help="delta_phi, delta_psi, visible_phi per T_theta (between successive maxima, default) "
                        "or per tau = 2 T_theta (the paper's)")
    p.add_argument("--dps", type=int, default=None, metavar="N",
                   help=f"use the mpmath reference at N digits, 15 <= N <= 1000 (slow: at most {MAX_POINTS_MP} points) "
                        "instead of double precision")
    p.add_argument("--rtol", type=float, default=DEFAULT_RTOL,
                   help=f"double backend: tolerance on the change between n/2 and n nodes, in [{RTOL_RANGE[0]:g}, "
                        f"{RTOL_RANGE[1]:g}] (default {DEFAULT_RTOL:g})")
    p.add_argument("--out", type=output_path, default=Path("precession_table.csv"), metavar="FILE",
                   help="CSV output (default precession_table.csv; an existing file is not overwritten without --force)")
    p.add_argument("--plot", type=output_path, default=None, metavar="DIR",
                   help="also draw the table over the (Q_R, Q_J) plane: the period and delta_phi, delta_psi per it, "
                        "with labelled colour bars, as precession_table.png and .pdf in DIR (created if missing; "
                        "existing files are not overwritten without --force); with --E, one energy")
    add_force_option(p)
    add_budget_option(p, "the table")
    p.add_argument("--json", action="store_true", help="print a one-object JSON summary on stdout")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(run=run)


def _cell(v: Any, dps: int | None) -> Any:
    if v is None:
        return None
    if dps is not None:
        import mpmath

        return mpmath.nstr(v, dps, strip_zeros=False)
    return float(v)


def run(args: argparse.Namespace) -> int:
    """Run ``rocknroller table`` with the parsed ``args``; returns the exit status."""
    from rocknroller.analysis.routh.quadrature import OK, STEADY, UNRESOLVED, precession, precession_from_turning_point
    from rocknroller.analysis.routh.reduction import NO_MOTION

    body = body_from_args(args)
    body.require_symmetric("rocknroller table (Routh's sphere quadratures)")
    check_moments(body)
    if args.E is not None and args.theta0 is not None:
        raise ValueError("give either --theta0 (theta_X fixed) or --E (an energy grid), not both")
    if args.dps is not None and not 15 <= args.dps <= 1000:
        raise ValueError(f"--dps must be an integer in [15, 1000], got {args.dps}")
    check_rtol(args.rtol, "--rtol")
    QR_axis, QJ_axis = parse_grid(args.QR, "--QR"), parse_grid(args.QJ, "--QJ")
    E_axis = parse_grid(args.E, "--E") if args.E is not None else np.ones(1)
    n = QR_axis.size * QJ_axis.size * E_axis.size
    limit = MAX_POINTS if args.dps is None else MAX_POINTS_MP
    if n > limit:
        raise ValueError(f"--QR, --QJ{', --E' if args.E is not None else ''}: the grid has {n} points, over the limit "
                         f"{limit}{' with --dps' if args.dps is not None else ''}; use fewer points")
    if args.dps is not None:  # the double backend's points are bounded by MAX_POINTS (~40 µs each)
        check_work(n * mp_point_seconds(args.dps), f"a table of {n} mpmath points at {args.dps} digits",
                   budget_from_args(args))
    if args.plot is not None and E_axis.size > 1:
        raise ValueError(f"--plot draws the (Q_R, Q_J) plane at one energy: give one --E value, got --E {args.E}")
    prepare_output_file(args.out, "--out", args.force)
    if args.plot is not None:
        prepare_output_dir(args.plot, "--plot", args.force, FIGURES)
    if args.E is not None:
        E, QR, QJ = (a.ravel() for a in np.meshgrid(E_axis, QR_axis, QJ_axis, indexing="ij"))
        theta0 = None
    else:
        theta0 = parse_angle(args.theta0 if args.theta0 is not None else "0.95pi", "--theta0")
        if not 0.0 < theta0 < np.pi:
            raise ValueError(f"--theta0 must lie in the open interval (0, pi), got {theta0!r}")
        QR, QJ = (a.ravel() for a in np.meshgrid(QR_axis, QJ_axis, indexing="ij"))
        E = None
    n = QR.size
    from tqdm import tqdm

    t_start = time.perf_counter()
    factor = 2.0 if args.per == "tau" else 1.0
    rows: dict[str, list] = {c: [None] * n for c in COLUMNS}
    rows["Q_R"], rows["Q_J"] = list(QR), list(QJ)
    status_name = {OK: "ok", NO_MOTION: "no_motion", STEADY: "steady_rolling", UNRESOLVED: "unresolved"}
    step = _CHUNK if args.dps is None else 1
    with tqdm(total=n, desc="table", unit="pt", file=sys.stderr, disable=True if args.quiet else None) as bar:
        for lo in range(0, n, step):
            sl = slice(lo, min(n, lo + step))
            if theta0 is None:
                pr = precession(E[sl], QR[sl], QJ[sl], body, rtol=args.rtol)
                upper = np.ones(pr.status.shape, dtype=bool)
            else:
                pr, upper = precession_from_turning_point(theta0, QR[sl], QJ[sl], body, rtol=args.rtol)
            status = np.asarray(pr.status)
            names = [status_name[int(st)] for st in status]
            names = ["theta0_is_theta_N" if (nm == "ok" and not up) else nm for nm, up in zip(names, upper)]
            rows["status"][sl] = names
            rows["E"][sl] = [float(v) for v in pr.E]
            if args.dps is not None:
                if status[0] in (OK, UNRESOLVED):
                    _fill_mp(rows, sl.start, pr, 0, body, args.dps, theta0, factor)
                    rows["status"][sl.start] = "ok" if upper[0] else "theta0_is_theta_N"
            else:
                _fill_double(rows, sl, pr, status == OK, factor)
            bar.update(sl.stop - sl.start)
    from rocknroller.analysis.criticality.lines import region

    rows["region"] = [str(v) for v in np.asarray(region(QR, QJ, body)).ravel()]
    written = [] if args.plot is None else _plot(args, rows, body, theta0, E_axis)
    if args.dps is not None:
        for c in COLUMNS[2:10]:
            rows[c] = [_cell(v, args.dps) for v in rows[c]]
    elapsed = time.perf_counter() - t_start

    from rocknroller.papers.output import write_csv

    mode = (f"turning point theta_X = theta0 = {theta0!r} fixed, E = U(theta0; Q_R, Q_J)" if theta0 is not None
            else "grid of (E, Q_R, Q_J)")
    header = [
        "rocknroller table: precession of Routh's sphere (paper section 2.5, eq. (22))",
        f"body: {body.describe()}",
        f"theta0: {theta0!r}" if theta0 is not None else "theta0: none (energy grid)",
        f"mode: {mode}",
        f"grid: QR={args.QR} QJ={args.QJ}" + (f" E={args.E}" if args.E is not None else ""),
        f"backend: {'mpmath dps=' + str(args.dps) if args.dps else 'double precision, rtol=' + repr(args.rtol)}",
        "T_theta: time between successive maxima of theta; tau = 2 T_theta (the paper's tau = 4 integral)",
        f"delta_phi, delta_psi: full unwrapped increments per {args.per}; visible_phi = delta_phi mod 2pi in (-pi, pi]",
        "region: I-IV from rocknroller.analysis.criticality.lines.region (or on a critical line)",
        *(f"status {k}: {v}" for k, v in STATUS_LEGEND.items()),
    ]
    write_csv(args.out, rows, header)
    counts = dict(Counter(rows["status"]))
    summary = {"out": str(args.out), "figures": [str(p) for p in written], "n_points": n, "status_counts": counts,
               "mode": "theta0" if theta0 is not None else "E", "theta0": theta0, "per": args.per, "backend": "mpmath" if args.dps else "double",
               "dps": args.dps, "body": {k: getattr(body, k) for k in ("a", "I1", "I2", "I3", "g")},
               "elapsed_s": elapsed}
    if args.json:
        print_json(summary)
    else:
        print(f"body: {body.describe()}")
        print(f"{n} points ({mode}) in {elapsed:.3g} s: " + ", ".join(f"{k}={v}" for k, v in sorted(counts.items())))
    for path in [args.out, *written]:
        print(f"wrote {path}", file=sys.stderr)
    return 0


def _plot(args: argparse.Namespace, rows: dict, body: Any, theta0: float | None, E_axis: np.ndarray) -> list[Path]:
    """The table over the (Q_R, Q_J) plane (:func:`rocknroller.analysis.routh.precession_plots.precession_figure`,
    the figure of ``Precession.plot``), per ``--per``, as PNG and PDF in ``--plot``."""
    from rocknroller.analysis.routh.precession_plots import precession_figure
    from rocknroller.papers.output import angle_text, new_figure, save_figure

    where = f"theta_X = theta0 = {angle_text(theta0)} fixed" if theta0 is not None else f"E = {E_axis[0]!r}"
    title = f"precession table of Routh's sphere, {where}\nbody {body.describe()}"
    fig = precession_figure(rows["Q_R"], rows["Q_J"], rows[args.per], rows["delta_phi"], rows["delta_psi"],
                            per=args.per, fig=new_figure(figsize=(13, 4.4), layout="constrained"), title=title)
    return save_figure(fig, args.plot, "precession_table")


def _fill_double(rows: dict, sl: slice, pr: Any, ok: np.ndarray, factor: float) -> None:
    """Numeric cells of the rows in ``sl``; None (an empty cell) where there is no motion."""
    from rocknroller.analysis.model.diagnostics import wrap_angle

    values = {
        "theta_N": pr.theta_N, "theta_X": pr.theta_X, "T_theta": pr.T_theta, "tau": pr.tau,
        "delta_phi": factor * pr.delta_phi, "delta_psi": factor * pr.delta_psi,
        "visible_phi": pr.visible_phi if factor == 1.0 else wrap_angle(factor * pr.delta_phi),
    }
    for name, v in values.items():
        rows[name][sl] = [float(x) if good else None for x, good in zip(np.asarray(v, float), ok)]


def _fill_mp(rows: dict, i: int, pr: Any, j: int, body: Any, dps: int, theta0: float | None, factor: float) -> None:
    import mpmath

    from rocknroller.analysis.model.diagnostics import wrap_angle
    from rocknroller.analysis.routh.quadrature_mp import precession_mp

    ref = precession_mp(None if theta0 is not None else float(pr.E[j]), float(pr.QR[j]), float(pr.QJ[j]), body,
                        dps=dps, theta0=theta0)
    with mpmath.workdps(dps):
        rows["E"][i] = ref.E
        rows["theta_N"][i], rows["theta_X"][i] = ref.theta_N, ref.theta_X
        rows["T_theta"][i], rows["tau"][i] = ref.T_theta, ref.tau
        rows["delta_phi"][i] = factor * ref.delta_phi
        rows["delta_psi"][i] = factor * ref.delta_psi
        rows["visible_phi"][i] = ref.visible_phi if factor == 1 else wrap_angle(factor * ref.delta_phi)
