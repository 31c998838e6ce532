"""Command-line options shared by the subcommands: the body, the initial state, angles like ``0.95pi``,
where direct runs execute (this process or a dask cluster), output paths (checked before any computation, never
overwritten unasked) and strict JSON output."""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import sys
import tempfile
from pathlib import Path
from typing import Any, Iterable

from rocknroller.analysis.model.body import PAPER_A, PAPER_G, PAPER_I3, Body, LoadedSphere, float_or_nan, paper_I1
from rocknroller.analysis.model.equations import FIG5_OMEGA0, EulerState
from rocknroller.numerics.run_limits import G_RANGE

__all__ = [
    "parse_angle",
    "add_budget_option",
    "budget_from_args",
    "accept_negative_values",
    "add_body_options",
    "body_from_args",
    "add_offset_option",
    "output_path",
    "sphere_from_args",
    "add_initial_state_options",
    "initial_state_from_args",
    "rates_given",
    "start_with_default_rates",
    "add_critical_line_options",
    "check_critical_line_options",
    "critical_line_state",
    "add_cluster_options",
    "cluster_from_args",
    "add_force_option",
    "prepare_output_dir",
    "prepare_output_file",
    "release_outputs",
    "WRITING_MARKER",
    "finite_or_none",
    "print_json",
]

_ANGLE = re.compile(r"^\s*([-+])?\s*((?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)?\s*\*?\s*(pi|π)?\s*(?:/\s*(\d+\.?\d*))?\s*$")
#: Values that start with a minus sign and are values, not options: -0.5pi, -pi/4, -1e-3, -.5, -0.01:0.01:3, -inf.
_NEGATIVE_VALUE = re.compile(r"^-(\d|\.\d|pi|π|inf|nan)", re.IGNORECASE)


def parse_angle(text: str | float, option: str | None = None) -> float:
    """Parse an angle in radians: ``2.9``, ``0.95pi``, ``pi/4``, ``3pi/8``, ``-0.5*pi``.

    Raises ``ValueError`` for anything else (a number too large for a float included), naming ``option`` (e.g.
    ``"--theta0"``) when given.
    """
    what = f"{option}: " if option else ""
    if isinstance(text, (int, float)):
        try:
            value = float(text)
        except OverflowError:  # an int beyond the float range
            raise ValueError(f"{what}angle must be finite, got an integer of {len(str(abs(text)))} digits") from None
    else:
        m = _ANGLE.match(str(text))
        if not m or (m.group(2) is None and m.group(3) is None):
            raise ValueError(f"{what}cannot read angle {text!r}: use radians (2.9) or multiples of pi (0.95pi, pi/4, "
                             "-3pi/8)")
        value = float(m.group(2)) if m.group(2) is not None else 1.0
        if m.group(1) == "-":
            value = -value
        if m.group(3):
            value *= math.pi
        if m.group(4):
            den = float(m.group(4))
            if den == 0.0:
                raise ValueError(f"{what}cannot read angle {text!r}: division by zero")
            value /= den
    if not math.isfinite(value):
        raise ValueError(f"{what}angle must be finite, got {text!r}")
    return value


def accept_negative_values(parser: argparse.ArgumentParser) -> None:
    """Let values that begin with a minus sign (``--phi0 -0.5pi``, ``--omega 0 -1e-3 0``, ``--QR -0.01:0.01:3``)
    be read as values, as ``--phi0=-0.5pi`` is; no option of this CLI looks like a negative number.

    argparse has no public way to say so: it takes a token as a value only if its private
    ``_negative_number_matcher`` calls it a negative number (bpo-9334 / gh-53580, closed without a public option),
    and its pattern covers plain decimals only (scientific notation from Python 3.14, gh-105712), never ``-pi/4``, a
    range or ``-inf``; the ``=`` form that it documents cannot give the several values of ``--omega``.  So the pattern
    is replaced, on an attribute that ``tests/api/cli/test_options.py`` checks every supported Python still has.
    """
    if not hasattr(parser, "_negative_number_matcher"):  # a future argparse: fail loudly, not silently
        raise RuntimeError("argparse.ArgumentParser has no _negative_number_matcher: negative values such as "
                           "--phi0 -0.5pi cannot be accepted; use the form --phi0=-0.5pi")
    parser._negative_number_matcher = _NEGATIVE_VALUE


def add_body_options(parser: argparse.ArgumentParser, eps_default: float = 0.0, asymmetry: bool = True) -> None:
    """--a --I1 --I2 | --eps --I3 --g, or --polar-cap D (defaults: the paper's body, ε = ``eps_default``).

    ``asymmetry=False`` leaves out --I2 and --eps, for a command whose variable ε is (``bifurcation``): its help then
    lists no option that it would refuse."""
    grp = parser.add_argument_group("body (defaults: the paper's a=0.05, I3=0.4, I1=(1-5a/2)I3, g=9.87)")
    grp.add_argument("--a", type=float, default=None, help=f"mass-centre offset, 0 <= a < 1 (default {PAPER_A})")
    grp.add_argument("--I1", type=float, default=None, help="moment I1 (default (1-5a/2) I3)")
    if asymmetry:
        grp.add_argument("--I2", type=float, default=None, help="moment I2 (default (1+eps) I1); exclusive with --eps")
        grp.add_argument("--eps", type=float, default=None,
                         help=f"asymmetry eps = (I2-I1)/I1 (default {eps_default:g}); exclusive with --I2")
    else:
        parser.set_defaults(I2=None, eps=None)
    grp.add_argument("--I3", type=float, default=None, help=f"moment I3 (default {PAPER_I3})")
    grp.add_argument("--g", type=float, default=None, help=f"gravity (default {PAPER_G})")
    grp.add_argument("--polar-cap", type=float, default=None, metavar="D",
                     help="bowling ball with the polar cap above height D=cos(Theta) removed (paper App. A.1); "
                          "exclusive with --a/--I1/--I3")
    parser.set_defaults(eps_default=eps_default)


def add_offset_option(parser: argparse.ArgumentParser) -> None:
    """--offset C1 C2 C3: the mass centre anywhere (Chaplygin's top; the moments then in any order)."""
    parser.add_argument("--offset", type=float, nargs=3, default=None, metavar=("C1", "C2", "C3"),
                        help="the mass centre relative to the geometric centre in the principal frame, |c| < 1: "
                             "a loaded sphere of the paper's fig. 1 (Chaplygin's top off every principal axis, "
                             "Chaplygin's ball at 0 0 0); the moments --I1 --I2 --I3 (or --eps) then in any order, "
                             "each at most the sum of the other two; exclusive with --a and --polar-cap. The paper's "
                             "Q_R, Q_J are then not reported (they assume c = (0, 0, -a))")
    parser.add_argument("--tilt-axis", type=int, choices=(1, 2, 3), default=3, metavar="K",
                        help="with --offset: follow the tilt of principal axis K (1, 2 or 3; default 3): the axes are "
                             "renamed cyclically so that K is the third, and theta, psi and --omega refer to the "
                             "renamed axes")


def sphere_from_args(args: argparse.Namespace) -> Body | LoadedSphere:
    """The Body of :func:`body_from_args`, or with ``--offset`` (:func:`add_offset_option`) a LoadedSphere with the
    moments the same options give (I3 = 0.4, I1 = (1 - 5a/2) I3 at the paper's a, I2 = (1 + eps) I1 by default)."""
    if getattr(args, "offset", None) is None:
        if getattr(args, "tilt_axis", 3) != 3:
            raise ValueError("--tilt-axis needs --offset (the paper's body follows its symmetry axis, the third)")
        return body_from_args(args)
    if args.a is not None or args.polar_cap is not None:
        raise ValueError("--offset places the mass centre: do not combine it with --a or --polar-cap")
    if args.I2 is not None and args.eps is not None:
        raise ValueError("give either --I2 or --eps, not both")
    I3 = PAPER_I3 if args.I3 is None else args.I3
    I1 = paper_I1(PAPER_A, I3) if args.I1 is None else args.I1
    eps = getattr(args, "eps_default", 0.0) if args.eps is None else args.eps
    I2 = (1.0 + eps) * I1 if args.I2 is None else args.I2
    sphere = LoadedSphere(I1, I2, I3, tuple(args.offset), PAPER_G if args.g is None else args.g)
    return sphere.relabelled(args.tilt_axis)


def body_from_args(args: argparse.Namespace, gravity: bool = False) -> Body:
    """Build the Body from the options of :func:`add_body_options` (ε defaults to ``args.eps_default``).  With
    ``gravity`` (the commands of the slow motion, which rocks under gravity) --g must lie in ``G_RANGE``: g sets only
    the unit of time, and outside that range the rocking period under- or overflows what the tables resolve."""
    if args.I2 is not None and args.eps is not None:
        raise ValueError("give either --I2 or --eps, not both")
    eps = getattr(args, "eps_default", 0.0) if args.eps is None and args.I2 is None else args.eps
    g = PAPER_G if args.g is None else args.g
    if gravity and not G_RANGE[0] <= float_or_nan(g) <= G_RANGE[1]:
        raise ValueError(f"--g must lie in [{G_RANGE[0]:g}, {G_RANGE[1]:g}] for the slow motion (it rocks under "
                         f"gravity; g only sets the unit of time: rescale time to bring it there), got --g {g!r}")
    if args.polar_cap is not None:
        if any(v is not None for v in (args.a, args.I1, args.I3, args.I2)):
            raise ValueError("--polar-cap fixes a, I1 and I3: do not combine it with --a, --I1, --I2 or --I3")
        return Body.from_polar_cap(args.polar_cap, g=g, epsilon=eps)
    a = PAPER_A if args.a is None else args.a
    I3 = PAPER_I3 if args.I3 is None else args.I3
    I1 = paper_I1(a, I3) if args.I1 is None else args.I1
    derived = {}  # how the moments the user did not give were set, for error messages
    if args.I1 is None:
        source = " and ".join(f"{f} {v!r}" for f, v in (("--a", args.a), ("--I3", args.I3)) if v is not None)
        derived["I1"] = f"I1 = (1 - 5a/2) I3 = {I1!r} from {source or 'the defaults'}, since --I1 was not given"
    if args.I2 is None:
        derived["I2"] = f"I2 = (1 + eps) I1 with eps = {eps!r}" + ("" if args.eps is not None else " (the default)")
    try:
        if args.I2 is not None:
            return Body(a=a, I1=I1, I2=args.I2, I3=I3, g=g)
        return Body(a=a, I1=I1, I2=I1, I3=I3, g=g).with_epsilon(eps)
    except ValueError as exc:
        notes = [text for name, text in derived.items() if re.search(rf"\b{name}\b", str(exc))]
        raise ValueError(f"{exc} ({'; '.join(notes)})" if notes else str(exc)) from None


def add_initial_state_options(parser: argparse.ArgumentParser, theta0_default: str = "0.95pi",
                              rates_note: str = "", psi0_default: str = "0",
                              theta0_range: str = "in [0, pi]") -> None:
    """--theta0 --phi0 --psi0 --theta-dot0 --phi-dot0 --psi-dot0, or --omega W1 W2 W3 (body frame).

    The rates default to None ("not given", read as 0) so that a command can tell an explicit 0 from
    an option left out; ``rates_note`` is added to the group's help (e.g. a command-specific default ω);
    ``theta0_range`` is the range of --theta0 the command accepts, in the words of its description.
    """
    grp = parser.add_argument_group(
        "initial state (angles accept 0.95pi, pi/4, -0.5pi, ...)",
        "The Euler rates default to 0" + (f"; {rates_note}" if rates_note else "") + ".")
    grp.add_argument("--theta0", type=str, default=theta0_default, help=f"tilt {theta0_range} (default {theta0_default})")
    grp.add_argument("--phi0", type=str, default="0", help="azimuth (default 0)")
    grp.add_argument("--psi0", type=str, default=psi0_default, help=f"spin angle (default {psi0_default})")
    grp.add_argument("--theta-dot0", type=float, default=None, help="tilt rate (default 0)")
    grp.add_argument("--phi-dot0", type=float, default=None, help="azimuth rate (default 0)")
    grp.add_argument("--psi-dot0", type=float, default=None, help="spin rate (default 0)")
    grp.add_argument("--omega", type=float, nargs=3, default=None, metavar=("W1", "W2", "W3"),
                     help="body-frame angular velocity instead of the Euler rates")


def rates_given(args: argparse.Namespace) -> bool:
    """True if any of --theta-dot0, --phi-dot0, --psi-dot0 or --omega was given (an explicit 0 counts)."""
    return args.omega is not None or any(v is not None for v in (args.theta_dot0, args.phi_dot0, args.psi_dot0))


def _angles(args: argparse.Namespace) -> tuple[float, float, float]:
    """(theta0, phi0, psi0) of the options of :func:`add_initial_state_options`; errors name the option."""
    theta, phi, psi = (parse_angle(getattr(args, name), f"--{name}") for name in ("theta0", "phi0", "psi0"))
    return theta, phi, psi


def initial_state_from_args(args: argparse.Namespace) -> EulerState:
    """Build the EulerState from the options of :func:`add_initial_state_options` (rates not given are 0)."""
    theta, phi, psi = _angles(args)
    if args.omega is not None:
        if any(v is not None for v in (args.theta_dot0, args.phi_dot0, args.psi_dot0)):
            raise ValueError("give either --omega or the Euler rates (--theta-dot0 ...), not both")
        return EulerState.from_omega(theta, phi, psi, args.omega)
    theta_dot, phi_dot, psi_dot = (0.0 if v is None else v for v in (args.theta_dot0, args.phi_dot0, args.psi_dot0))
    return EulerState(theta, phi, psi, theta_dot, phi_dot, psi_dot)


def start_with_default_rates(args: argparse.Namespace, initial: EulerState) -> EulerState:
    """``initial``, or with no rate option given (:func:`rates_given`) the figure-5 body-frame ω at its angles (the
    default start of ``simulate`` and ``animate``), which needs 0 < θ0 < π."""
    if rates_given(args):
        return initial

    if not 0.0 < initial.theta < math.pi:
        raise ValueError(f"--theta0 must satisfy 0 < theta0 < pi when no rates are given (the start then takes the "
                         f"figure-5 omega = {FIG5_OMEGA0}, singular in Euler rates at theta = 0, pi), got "
                         f"--theta0={initial.theta!r}: give the rates (e.g. --psi-dot0 0) to start there")
    return EulerState.from_omega(initial.theta, initial.phi, initial.psi, FIG5_OMEGA0)


def add_critical_line_options(group: Any) -> None:
    """--critical-line {pi,0}, --QR, --offset: a turning-point start on a critical line (paper figs. 8, 9)."""
    group.add_argument("--critical-line", choices=("pi", "0"), default=None,
                       help="start on Q_J,pi^crit or Q_J,0^crit (paper figs. 8, 9): phi_dot0 is computed from "
                            "--theta0 and either --QR or --psi-dot0; theta_dot0 = 0")
    group.add_argument("--QR", type=float, default=None, help="with --critical-line: Routh's quantity of the start")
    group.add_argument("--offset", type=float, default=None,
                       help="with --critical-line: signed distance Q_J - Q_J^crit(Q_R) of the start (default 0)")


def check_critical_line_options(args: argparse.Namespace) -> None:
    """Refuse --QR and --offset without --critical-line: they place a start on a critical line, and nothing else
    reads them."""
    if args.critical_line is None:
        given = [name for name, value in (("--QR", args.QR), ("--offset", args.offset)) if value is not None]
        if given:
            raise ValueError(f"{' and '.join(given)} {'need' if len(given) > 1 else 'needs'} --critical-line")


def critical_line_state(args: argparse.Namespace, body: Body) -> tuple[EulerState, Any]:
    """The initial state of :func:`add_initial_state_options` and :func:`add_critical_line_options`, and the
    ``criticality.CriticalStart`` of a --critical-line start (else None)."""
    from rocknroller.analysis.criticality.starts import critical_start

    if args.critical_line is None:
        check_critical_line_options(args)
        return initial_state_from_args(args), None
    if args.omega is not None or args.phi_dot0 is not None or args.theta_dot0 is not None:
        raise ValueError("--critical-line computes phi_dot0 (theta_dot0 = 0): do not give --omega, --phi-dot0 "
                         "or --theta-dot0")
    theta0, phi0, psi0 = _angles(args)
    kw = {"QR": args.QR} if args.QR is not None else {"psi_dot0": 0.0 if args.psi_dot0 is None else args.psi_dot0}
    start = critical_start(body, theta0, psi0, args.critical_line, offset=args.offset or 0.0, **kw)
    return start.state(phi0), start


# ----------------------------------------------------------------------------- where direct runs execute
def add_cluster_options(parser: argparse.ArgumentParser) -> None:
    """--scheduler ADDRESS | --workers N: run the direct ODE runs on a dask.distributed cluster (an existing one, or a
    local one of N worker processes started for the command); without either they run in this process."""
    from rocknroller.numerics.ensembles.ensemble import DISTRIBUTED_HINT, MAX_WORKERS

    grp = parser.add_argument_group(
        "where the direct runs execute (default: in this process)",
        f"Both need the optional extra: {DISTRIBUTED_HINT}. Results are identical bit for bit wherever they run.")
    where = grp.add_mutually_exclusive_group()
    where.add_argument("--scheduler", type=str, default=None, metavar="ADDRESS",
                       help="address of an existing dask scheduler, e.g. tcp://10.0.0.5:8786 (start one with "
                            "'dask scheduler', and workers with 'dask worker ADDRESS')")
    where.add_argument("--workers", type=int, default=None, metavar="N",
                       help=f"start a local dask cluster of N single-threaded worker processes for the direct runs, "
                            f"1 <= N <= {MAX_WORKERS} (dask's workers, as in 'dask worker'; the processes of this "
                            f"machine that a command runs itself are its --processes)")


def cluster_from_args(args: argparse.Namespace) -> tuple[str | None, int | None]:
    """(scheduler, workers) from the options of :func:`add_cluster_options`, checked (errors name the option); both
    None for the in-process path.  Pass them on to :func:`rocknroller.numerics.ensembles.ensemble.run_ensemble`."""
    from rocknroller.numerics.ensembles.ensemble import check_cluster

    return check_cluster(args.scheduler, args.workers, prefix="--")


# ----------------------------------------------------------------------------- outputs
def output_path(text: str) -> Path:
    """An argparse type for the options that name where outputs go (--out, --csv, --plot, --values): a Path, with
    an empty name refused (``--out ""`` wrote into the current folder, which nobody named)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("an empty name names no file or folder (for the current folder give '.')")
    return Path(text)


def add_force_option(parser: argparse.ArgumentParser) -> None:
    """--force: overwrite existing output files (without it, a command refuses before computing)."""
    parser.add_argument("--force", action="store_true",
                        help="overwrite existing output files (default: refuse, before computing anything)")


def add_budget_option(parser: argparse.ArgumentParser, what: str) -> None:
    """--budget SECONDS: the CPU time ``what`` may take, estimated before any work (``numerics.budget``)."""
    from rocknroller.numerics.budget import WORK_BUDGET_SECONDS

    parser.add_argument("--budget", type=str, default=None, metavar="SECONDS",
                        help=f"CPU seconds {what} may take, estimated before any work from rates measured on this kind "
                             f"of machine; past it the command refuses, naming the estimate (default "
                             f"{WORK_BUDGET_SECONDS:g} = 1 hour; 'inf': no limit)")


def budget_from_args(args: argparse.Namespace) -> float | None:
    """The --budget of :func:`add_budget_option` as the API's ``budget`` (None: no limit)."""
    from rocknroller.numerics.budget import WORK_BUDGET_SECONDS

    if args.budget is None:
        return WORK_BUDGET_SECONDS
    value = float_or_nan(args.budget)
    if value == math.inf:
        return None
    if not value > 0.0:  # also NaN
        raise ValueError(f"--budget must be a number of seconds > 0 or 'inf', got {args.budget!r}")
    return value


#: Name of the marker a command that may write any file (``names=None``) creates in its output directory while it runs.
WRITING_MARKER = ".rocknroller-writing"
#: The empty files and the directories that this process reserved (:func:`prepare_output_dir`), to be removed by
#: :func:`release_outputs` where nothing was written into them.
_RESERVED: list[Path] = []
_CREATED_DIRS: list[Path] = []


def _require_writable(directory: Path, option: str) -> None:
    try:
        missing = [d for d in (directory, *directory.parents) if not d.exists()]
        directory.mkdir(parents=True, exist_ok=True)
        _CREATED_DIRS.extend(missing)  # deepest first
        with tempfile.NamedTemporaryFile(dir=directory):
            pass
    except OSError as exc:
        raise ValueError(f"{option}: cannot write to the directory {str(directory)!r} ({exc.strerror or exc})") from None


def _refuse_existing(option: str, where: str, clash: list[str], note: str = "") -> ValueError:
    shown = ", ".join(clash[:5]) + (", ..." if len(clash) > 5 else "")
    return ValueError(f"{option}: {where} already holds {shown}{note}; pass --force to overwrite, or choose another "
                      f"{option}")


def _reserve(paths: list[Path], option: str, where: str) -> None:
    """Create each of ``paths`` empty and exclusively (``O_CREAT | O_EXCL``: of two runs racing for the same name,
    exactly one creates it), or create none and refuse, naming ``option``, the ones that already exist."""
    made: list[Path] = []
    for path in paths:
        try:
            os.close(os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
        except FileExistsError:
            for p in made:
                p.unlink(missing_ok=True)
            clash = sorted(p.name for p in paths if p.exists() and p not in made)
            raise _refuse_existing(option, where, clash or [path.name], " (another run may be writing it)") from None
        except OSError as exc:
            for p in made:
                p.unlink(missing_ok=True)
            raise ValueError(f"{option}: cannot write {str(path)!r} ({exc.strerror or exc})") from None
        made.append(path)
    _RESERVED.extend(made)


def release_outputs() -> None:
    """Remove what this process reserved and left unwritten: the reserved output files that are still empty (the
    command failed before writing them, or did not need them), the marker ``WRITING_MARKER``, and the directories it
    created that are still empty.  The console script calls it when a command ends, however it ends."""
    while _RESERVED:
        path = _RESERVED.pop()
        try:
            if path.name == WRITING_MARKER or path.stat().st_size == 0:
                path.unlink()
        except OSError:
            pass
    while _CREATED_DIRS:
        try:
            _CREATED_DIRS.pop(0).rmdir()  # deepest first; only if empty
        except OSError:
            pass


def prepare_output_dir(directory: Path, option: str, force: bool, names: Iterable[str] | None = None) -> Path:
    """Create ``directory`` if needed and check, before any computation, that files can be written there and that
    none would be overwritten unasked.

    Without ``force`` the files are reserved: created empty and exclusively (``O_EXCL``), so that of two runs into
    the same directory at once the second refuses rather than overwrite the first's files; with ``names`` None the
    marker ``WRITING_MARKER`` is reserved instead, and the directory must hold nothing else.
    :func:`release_outputs` removes the reservations left empty, and the directories created here left empty.

    Parameters
    ----------
    names : file names the command writes, or None for "any file" (the directory must then be empty or new).

    Raises
    ------
    ValueError
        Naming ``option``: the path is a file, the directory cannot be created or written, or (without
        ``force``) it already holds files the command would overwrite.
    """
    directory = Path(directory)
    if directory.exists() and not directory.is_dir():
        raise ValueError(f"{option}: {str(directory)!r} exists and is not a directory")
    where = repr(str(directory))
    if not force and directory.is_dir():
        clash = sorted(p.name for p in directory.iterdir()) if names is None else \
            sorted(n for n in names if (directory / n).exists())
        if clash:
            raise _refuse_existing(option, where, clash)
    _require_writable(directory, option)
    _refuse_links([directory / n for n in names] if names is not None else [], option)
    if not force:
        if names is None:
            _reserve([directory / WRITING_MARKER], option, where)
            clash = sorted(p.name for p in directory.iterdir() if p.name != WRITING_MARKER)
            if clash:  # written by another run between the check above and the marker
                raise _refuse_existing(option, where, clash, " (another run may be writing it)")
        else:
            _reserve([directory / n for n in dict.fromkeys(names)], option, where)
    return directory


def _refuse_links(paths: list[Path], option: str) -> None:
    """A ValueError naming ``option`` if an output path is a symbolic link: writing through it (--force) would replace
    the file it points to, outside the folder the user named."""
    links = [p for p in paths if p.is_symlink()]
    if links:
        raise ValueError(f"{option}: {str(links[0])!r} is a symbolic link (to {str(links[0].readlink())!r}); the "
                         "outputs are written in the folder named, never through a link: remove the link")


def prepare_output_file(path: Path, option: str, force: bool) -> Path:
    """Like :func:`prepare_output_dir` for one file: its directory writable, the file not overwritten unasked (and,
    without ``force``, reserved: created empty and exclusively)."""
    path = Path(path)
    if path.is_dir():
        raise ValueError(f"{option}: {str(path)!r} is a directory; give a file name")
    if path.exists() and not force:
        raise ValueError(f"{option}: {str(path)!r} already exists; pass --force to overwrite, or choose another {option}")
    _require_writable(path.parent if str(path.parent) else Path("."), option)
    if not force:
        try:
            _reserve([path], option, repr(str(path.parent)))
        except ValueError:
            raise ValueError(f"{option}: {str(path)!r} already exists; pass --force to overwrite, or choose another "
                             f"{option}") from None
    return path


# ----------------------------------------------------------------------------- JSON
def finite_or_none(x: Any) -> Any:
    """A copy of ``x`` (dicts, lists, tuples, numbers) with every non-finite float replaced by None (JSON null):
    JSON has no NaN or Infinity.  Commands report undefined quantities as null on purpose."""
    if isinstance(x, dict):
        return {k: finite_or_none(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [finite_or_none(v) for v in x]
    if isinstance(x, float) and not math.isfinite(x):
        return None
    if hasattr(x, "item") and callable(x.item) and getattr(x, "ndim", None) == 0:  # numpy scalar
        return finite_or_none(x.item())
    return x


def print_json(obj: Any, indent: int | None = None) -> None:
    """Print ``obj`` as strict JSON (no NaN or Infinity: they become null) on stdout; a dict gets the package
    version as ``rocknroller_version``."""
    from rocknroller.numerics.provenance import __version__

    if isinstance(obj, dict):
        obj = {"rocknroller_version": __version__, **obj}
    sys.stdout.write(json.dumps(finite_or_none(obj), allow_nan=False, indent=indent) + "\n")
