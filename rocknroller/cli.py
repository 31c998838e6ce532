"""The ``rocknroller`` console script: a thin dispatcher over ``rocknroller.commands``.

Each subcommand lives in ``rocknroller/commands/<name>.py`` and defines
``register(subparsers)`` (adds its parser, with ``--help`` text) and
``run(args) -> int``.  Bad input (``ValueError``) is printed without a
traceback and exits with status 2.
"""

from __future__ import annotations

import argparse
import importlib
import sys

COMMANDS = ("reproduce", "simulate", "table", "diagram", "slow", "verify")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="rocknroller",
        description="Routh's sphere and the rock'n'roller: direct ODE, precession quadratures, "
        "critical Jellett lines, epsilon-averaged slow dynamics, and the reproduction of "
        "Lynch & Bustamante, 'Precession and recession of the rock'n'roller'.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMANDS:
        importlib.import_module(f"rocknroller.commands.{name}").register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    try:
        return int(args.run(args) or 0)
    except ValueError as exc:
        print(f"rocknroller {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
