"""``rocknroller hierarchy``: the loaded spheres' integrals and invariant measures, proved and measured (paper fig. 1;
Borisov & Mamaev 2002)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from rocknroller.cli.options import add_force_option, output_path, prepare_output_dir, print_json

#: Files written to --out.
OUTPUTS = ("hierarchy.csv", "hierarchy.png", "hierarchy.pdf")


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``hierarchy`` subcommand and its ``--help`` to ``sub``."""
    from rocknroller.analysis.hierarchy.drift import DRIFT_T_END

    p = sub.add_parser(
        "hierarchy",
        help="the loaded spheres' integrals and invariant measures, proved with sympy and measured on the direct ODE",
        description="Borisov and Mamaev's table of the loaded spheres (the paper's fig. 1): Chaplygin's ball, the "
        "rock'n'roller, Routh's sphere and Chaplygin's top. For each member and each quantity (the energy E, "
        "Jellett's M.r, Routh's Q_R where the mass centre is on the third axis, Chaplygin's M.M and M.gamma, "
        "Borisov and Mamaev's M^2 - 2T r^2 at g = 0 and with gravity), sympy decides whether it is a first "
        "integral, symbolically in all the member's parameters (or gives an exact rational state where dQ/dt != 0), "
        "and the direct ODE measures its drift against the run's round-off bound; for each member, sympy decides "
        "whether an invariant density rho(gamma) exists.",
    )
    p.add_argument("--t-end", type=float, default=DRIFT_T_END,
                   help=f"length of the direct runs that measure the drifts, in [1, 1e4] (default {DRIFT_T_END:g})")
    p.add_argument("--out", type=output_path, default=None, metavar="DIR",
                   help="write hierarchy.csv (one row per member and quantity) and hierarchy.png/.pdf to DIR "
                        "(existing files are not overwritten without --force)")
    add_force_option(p)
    p.add_argument("--json", action="store_true", help="print the table as JSON on stdout")
    p.set_defaults(run=run)


def _summary(rows) -> dict:
    out = []
    for row in rows:
        b = row.body
        quantities = {name: {"conserved": e.proof.conserved, "proof": e.proof.verdict, "drift": e.drift.drift,
                             "round_off_bound": e.drift.bound, "g": e.drift.g, "agrees": e.agrees}
                      for name, e in row.entries.items()}
        out.append({"member": row.member, "body": {"I": [b.I1, b.I2, b.I3], "offset": list(b.offset), "g": b.g},
                    "quantities": quantities, "integrals": list(row.integrals),
                    "invariant_measure": {"exists": row.measure.density_exists, "verdict": row.measure.verdict}})
    return {"members": out, "t_end": rows[0].entries["energy"].drift.t_end,
            "all_agree": all(e.agrees for row in rows for e in row.entries.values())}


def run(args: argparse.Namespace) -> int:
    """Run ``rocknroller hierarchy`` with the parsed ``args``; returns the exit status (1 if a measurement
    contradicts its proof)."""
    from rocknroller.analysis.hierarchy.table import hierarchy_table

    if args.out is not None:
        prepare_output_dir(args.out, "--out", args.force, OUTPUTS)
    rows = hierarchy_table(args.t_end)
    summary = _summary(rows)
    written = _write(rows, args.out) if args.out is not None else []
    if args.json:
        print_json(summary)
    else:
        for row in rows:
            print(f"{row.member}: {row.body.describe()}")
            for name, e in row.entries.items():
                verdict = "conserved" if e.proof.conserved else "not conserved"
                print(f"  {name:18} sympy: {verdict:14} drift {e.drift.drift:8.1e} (bound {e.drift.bound:.1e}, "
                      f"g={e.drift.g:g}){'' if e.agrees else '  DISAGREES'}")
            print(f"  invariant measure: {row.measure.verdict}")
        print(f"every measurement agrees with its proof: {summary['all_agree']}")
    for path in written:
        print(f"wrote {path}", file=sys.stderr)
    return 0 if summary["all_agree"] else 1


def _write(rows, out: Path) -> list[Path]:
    from rocknroller.numerics.provenance import __version__
    from rocknroller.papers.hierarchy_plots import hierarchy_figure
    from rocknroller.papers.output import save_figure, write_csv

    cols: dict[str, list] = {k: [] for k in ("member", "quantity", "conserved", "drift", "round_off_bound", "g",
                                             "agrees", "I1", "I2", "I3", "c1", "c2", "c3")}
    for row in rows:
        for name, e in row.entries.items():
            b = row.body
            for k, v in (("member", row.member), ("quantity", name), ("conserved", e.proof.conserved),
                         ("drift", e.drift.drift), ("round_off_bound", e.drift.bound), ("g", e.drift.g),
                         ("agrees", e.agrees), ("I1", b.I1), ("I2", b.I2), ("I3", b.I3), ("c1", b.offset[0]),
                         ("c2", b.offset[1]), ("c3", b.offset[2])):
                cols[k].append(v)
    header = [f"rocknroller {__version__} hierarchy", f"t_end={rows[0].entries['energy'].drift.t_end!r} "
              "from theta0=0.6pi, psi0=0.4, omega=(0.7, -0.5, 1.3); drift = max|Q(t) - Q(0)|/max|Q| (energy: "
              "/(E + g|c|)); conserved: the sympy proof"]
    written = [write_csv(out / "hierarchy.csv", cols, header)]
    return written + save_figure(hierarchy_figure(rows), out, "hierarchy")
