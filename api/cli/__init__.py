"""The ``rocknroller`` console script: a thin dispatcher over its subcommands, one module each in this package.

Each subcommand lives in ``api/cli/<name>.py`` (``rocknroller.cli.<name>``) and defines
``register(subparsers)`` (adds its parser, with ``--help`` text) and
``run(args) -> int``.  Exit status: 0 success; 1 a computation failed its own
check (``--strict`` accuracy, ``verify``); 2 bad input (a ``ValueError``) or an
output that cannot be written (an ``OSError``), printed as one line without a
traceback.
"""

from __future__ import annotations

import argparse
import importlib
import re
import signal
import sys
import threading
import warnings
from typing import Any

from rocknroller.cli.options import accept_negative_values
from rocknroller.numerics.provenance import __version__

COMMANDS = ("reproduce", "simulate", "animate", "table", "diagram", "slow", "atlas", "bifurcation", "portrait", "verify",
            "cite", "warm", "hierarchy")


def build_parser() -> argparse.ArgumentParser:
    """The ``rocknroller`` argument parser with every subcommand of :data:`COMMANDS`."""
    parser = argparse.ArgumentParser(
        prog="rocknroller",
        description="Routh's sphere and the rock'n'roller: direct ODE, precession quadratures, "
        "critical Jellett lines, epsilon-averaged slow dynamics, and the reproduction of "
        "Lynch & Bustamante, 'Precession and recession of the rock'n'roller'.",
    )
    parser.add_argument("--version", action="version", version=f"rocknroller {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMANDS:
        importlib.import_module(f"rocknroller.cli.{name}").register(sub)
    for p in (parser, *sub.choices.values()):
        accept_negative_values(p)
    return parser


#: API parameter names and the options that set them, for error messages (the user gave the option).
_OPTION_OF = {"t_end": "--t-end", "dt": "--dt", "theta0": "--theta0", "phi0": "--phi0", "psi0": "--psi0",
              "theta_dot": "--theta-dot0", "phi_dot": "--phi-dot0", "psi_dot": "--psi-dot0", "omega": "--omega",
              "epsilon": "--eps", "a": "--a", "I1": "--I1", "I2": "--I2", "I3": "--I3", "g": "--g",
              "QR_max": "--QR-max", "workers": "--workers", "nu": "--nodes", "nv": "--nodes", "fps": "--fps",
              "duration": "--duration", "processes": "--processes", "scheduler": "--scheduler"}
_PARAMETER = re.compile(r"(?<![-\w])(" + "|".join(_OPTION_OF) + r")\b(?=( must|=|:))")  # not inside an option


def option_names(message: str, argv: list[str]) -> str:
    """``message`` with API parameter names (``t_end must ...``, ``theta0=...``) replaced by the options that set
    them, where the user gave that option (a value derived from other options keeps its own name)."""
    given = {a.split("=", 1)[0] for a in argv if a.startswith("--")}
    return _PARAMETER.sub(lambda m: _OPTION_OF[m.group(1)] if _OPTION_OF[m.group(1)] in given else m.group(1),
                          message)


#: API words in library messages and, per command, the option that says the same; in a command without one, the
#: alternative they offer ("use samples=False (turning points only) or a shorter t_end") is dropped.
_API_WORDS = {"samples=False": {"simulate": "--turning-points-only"},
              "build=False": {"slow": "--cached-only", "atlas": "--cached-only", "portrait": "--cached-only",
                              "bifurcation": "--cached-only"},
              "budget=SECONDS": {c: "--budget SECONDS" for c in ("simulate", "atlas", "table", "slow", "portrait",
                                                                 "bifurcation")}}
_API_WORD = re.compile(r"\b(" + "|".join(map(re.escape, _API_WORDS)) + r")( \([^()]*\))?( or )?")
#: The name of a limit (``MAX_SAMPLES``, ``E_MAX``, ``reduction.Q_RANGE``) before its value (``NAME = value``) or after
#: it (``(NAME)``): the command line shows the value only.
_LIMIT_NAME = r"(?:[a-z_]+\.)*(?:[A-Z0-9]+_)*(?:MAX|MIN|RANGE|LIMIT)(?:_[A-Z0-9]+)*\b"
_LIMIT = re.compile(rf"\b{_LIMIT_NAME} = | \({_LIMIT_NAME}\)")
#: A NumPy scalar array's repr, ``array(0.5)``: the number.
_ARRAY = re.compile(r"\barray\(([^()]*)\)")
_SAME_OPTION_TWICE = re.compile(r"(--[\w-]+) / \1\b")
#: API parameters that one command always sets from its options (their defaults included), by the options' names.
_COMMAND_OPTIONS = {"bifurcation": {"n_points": "--points", "exact_fractions": "--exact-at",
                                    "fractions": "--from/--to"}}


def cli_message(message: str, command: str, argv: list[str]) -> str:
    """A library's error ``message`` in the words of ``rocknroller COMMAND``: API words as the options that say the
    same (``samples=False`` is ``--turning-points-only``), limits by their values rather than their constant names,
    NumPy reprs as numbers, and parameter names as the options that set them (:func:`option_names`)."""
    def api_word(m: re.Match) -> str:
        option = _API_WORDS[m.group(1)].get(command)
        if option is None:
            return "" if m.group(3) else m.group(0)
        return option + (m.group(3) or "")  # the option's name says what the gloss said

    message = _SAME_OPTION_TWICE.sub(r"\1", _API_WORD.sub(api_word, message))
    message = _ARRAY.sub(lambda m: _number(m.group(1)), _LIMIT.sub("", message))
    names = _COMMAND_OPTIONS.get(command, {})
    if names:
        message = re.sub(r"(?<![-\w])(" + "|".join(names) + r")\b", lambda m: names[m.group(1)], message)
    return option_names(message, argv)


def _number(text: str) -> str:
    """A number NumPy printed (``0.``, ``3.141592653589793``) as Python prints it; other text as it is."""
    try:
        return repr(float(text))
    except ValueError:
        return text


def main(argv: list[str] | None = None) -> int:
    """Run the console script on ``argv`` (default ``sys.argv[1:]``); returns the exit status (see the module)."""
    parser = build_parser()
    argv = sys.argv[1:] if argv is None else list(argv)
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    import numpy as np

    from rocknroller.cli.options import release_outputs
    from rocknroller.numerics.integrate import AccuracyError

    def show_warning(message: Warning | str, category: type[Warning], filename: str, lineno: int, file: Any = None,
                     line: str | None = None) -> None:
        """Every warning that reaches the user, in one line and one format (not Python's two-line default)."""
        print(f"rocknroller {args.command}: warning: {message}", file=sys.stderr)

    previous = _terminate_by_exception()
    try:
        with np.printoptions(floatmode="unique"), warnings.catch_warnings():  # a number in a message with all digits
            warnings.showwarning = show_warning
            return int(args.run(args) or 0)
    except (KeyboardInterrupt, Terminated) as exc:  # one line, no traceback; the outputs reserved are released below
        signal_name = "SIGTERM" if isinstance(exc, Terminated) else "SIGINT"
        print(f"rocknroller {args.command}: interrupted ({signal_name}); the outputs it had reserved and not yet begun "
              "are removed", file=sys.stderr)
        return 143 if isinstance(exc, Terminated) else 130
    except ValueError as exc:
        print(f"rocknroller {args.command}: error: {cli_message(str(exc), args.command, argv)}", file=sys.stderr)
        return 2
    except AccuracyError as exc:
        print(f"rocknroller {args.command}: check failed: {exc}", file=sys.stderr)
        return 1
    except OSError as exc:
        where = f" {exc.filename!r}" if getattr(exc, "filename", None) else ""
        print(f"rocknroller {args.command}: error: cannot write{where}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    finally:
        release_outputs()  # output files reserved and never written, output directories created and left empty
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


class Terminated(BaseException):
    """Raised in the main thread by SIGTERM while a command runs, so that its cleanup runs (the default action ends
    the process at once and left the reserved, empty output files behind, which made the next run refuse)."""


def _terminate_by_exception() -> Any:
    """Install a SIGTERM handler that raises :class:`Terminated` (in the main thread only, where Python runs signal
    handlers); returns the handler it replaced, or None where none was installed."""
    if threading.current_thread() is not threading.main_thread():
        return None

    def handler(signum: int, frame: Any) -> None:
        raise Terminated()

    return signal.signal(signal.SIGTERM, handler)
