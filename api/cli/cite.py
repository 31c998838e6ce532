"""``rocknroller cite``: BibTeX for the package, the paper and the codes a command uses."""

from __future__ import annotations

import argparse


def citable_commands() -> list[str]:
    """The commands ``cite`` takes: every command of the dispatcher's :data:`rocknroller.cli.COMMANDS` but ``cite``."""
    from rocknroller.cli import COMMANDS

    return [c for c in COMMANDS if c != "cite"]


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``cite`` subcommand and its ``--help`` to ``sub``."""
    commands = citable_commands()
    p = sub.add_parser(
        "cite",
        help="print BibTeX for what a command uses (the package, the paper, heyoka, scipy, mpmath)",
        description="Print the BibTeX entries to cite for a run of COMMAND: the package (with its version) and "
        "Lynch & Bustamante's paper always, plus the codes that command uses (heyoka for the direct ODE and the "
        "averaging tables, scipy, mpmath). Without COMMAND: everything the package can use. The package's entry "
        "and the paper's come from the repository's CITATION.cff.",
    )
    p.add_argument("for_command", nargs="?", choices=commands, metavar="COMMAND", default=None,
                   help=f"one of {', '.join(commands)} (default: all)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run ``rocknroller cite`` with the parsed ``args``; returns the exit status."""
    from rocknroller.papers.citation import cite

    print(cite(args.for_command), end="")
    return 0
