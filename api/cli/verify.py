"""``rocknroller verify``: check every formula against its reference and print the table."""

from __future__ import annotations

import argparse
import sys

from rocknroller.cli.options import print_json


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``verify`` subcommand and its ``--help`` to ``sub``."""
    p = sub.add_parser(
        "verify",
        help="check every formula against an independent reference (exit 1 on any failure)",
        description="Verification table: each formula (equations of motion, F and turning points, tau, "
        "delta_phi, delta_psi, critical lines, Laurent expansions, cos(theta_z), the delta bound, the averaged "
        "slow motion) against its reference (mpmath, a second formulation, or the direct ODE), with the "
        "measured error, the bound it must meet (<= the tolerance; > it for the paper's misprinted cos(theta_z), "
        "a row that shows a formula wrong) and pass/fail. Exits with status 1 if any check fails.",
    )
    p.add_argument("--json", action="store_true", help="emit the table as JSON on stdout")
    p.add_argument("--quiet", action="store_true", help="no progress messages")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run ``rocknroller verify`` with the parsed ``args``; returns the exit status."""
    from rocknroller.papers.verification import run_checks

    def progress(name: str) -> None:
        if not args.quiet:
            print(f"running {name} ...", file=sys.stderr)

    rows = run_checks(progress)
    if args.json:
        print_json([r.as_dict() for r in rows], indent=1)
    else:
        print(f"{'result':6s} {'error':>9s} {'bound':<10s}  check (reference)")
        for r in rows:
            print(f"{'PASS' if r.passed else 'FAIL':6s} {r.error:9.2e} {r.bound:<10s}  "
                  f"{r.group}: {r.name} ({r.reference})")
        n_fail = sum(not r.passed for r in rows)
        print(f"{len(rows) - n_fail} passed, {n_fail} failed")
    return 1 if any(not r.passed for r in rows) else 0
