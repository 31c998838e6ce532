"""The command line in its own words (issue 25, items 14 and 25): help that states the defaults and limits that apply,
errors that name the options (not API parameters, constant names or NumPy reprs), options refused where they do
not apply, and no warning before a clean error."""

from __future__ import annotations

import json
import math
import re
import warnings

import pytest

from rocknroller.analysis.slow.map import table as slow_table
from rocknroller.cli import build_parser, cli_message, main
from rocknroller.cli.options import parse_angle
from rocknroller.numerics.integrate import MAX_DENSE_RADIANS, MAX_GRID_POINTS, MAX_RADIANS, MAX_SAMPLES, MOMENT_RANGE
from rocknroller.papers.animation import MAX_FRAMES

#: A constant's name as the API spells it (MAX_SAMPLES, E_MAX, Q_RANGE): the CLI shows values instead.
CONSTANT = re.compile(r"\b(?:[A-Z0-9]+_)*(?:MAX|MIN|RANGE|LIMIT)(?:_[A-Z0-9]+)*\b")


def _help(command: str) -> str:
    parser = build_parser()
    return next(a for a in parser._actions if a.dest == "command").choices[command].format_help()


def _error(argv, capsys) -> str:
    """The one-line error of a refused command line (exit status 2, no traceback)."""
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


@pytest.fixture
def no_tables(tmp_path, monkeypatch):
    """An empty cache and no tables in memory: --cached-only must refuse."""
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path / "cache"))
    monkeypatch.setattr(slow_table, "_TABLES", {})


# ------------------------------------------------------------------------------------------------ help
def test_diagram_help_states_the_psi0_the_orbit_starts_from(tmp_path, capsys):
    """`diagram --help` said psi0 defaults to 0 while --simulate started at pi/4."""
    default = re.search(r"--psi0 PSI0\s+spin angle \(default ([^)]+)\)", _help("diagram")).group(1)
    assert main(["diagram", "--simulate", "--t-end", "5", "--json", "--out", str(tmp_path)]) == 0
    assert json.loads(capsys.readouterr().out)["initial"]["psi0"] == parse_angle(default) == math.pi / 4


def test_slow_help_states_one_release_range():
    """`slow --help` stated 0 < theta0 <= 0.999pi in its description, [0.75pi, 0.999pi] for a release in the initial
    state's note and [0, pi] at --theta0: every range it gives for a release from rest is now the one
    check_release_theta0 enforces, and the tables' own range is named as theirs only."""
    from rocknroller.analysis.slow.map.limits import THETA0_RANGE, check_release_theta0

    text = " ".join(_help("slow").split())
    hi = f"{THETA0_RANGE[1] / math.pi:g}pi"
    assert f"0 < theta0 <= {hi}" in text and f"--theta0 THETA0 tilt in (0, {hi}] for a release from rest" in text
    assert "theta0 in [" not in text and "tilt in [0, pi] (" not in text
    assert check_release_theta0(THETA0_RANGE[1]) == THETA0_RANGE[1]
    for outside in (0.0, math.nextafter(THETA0_RANGE[1], 4.0)):
        with pytest.raises(ValueError, match="theta0 must lie in"):
            check_release_theta0(outside)


def test_help_shows_limits_by_value():
    """Help texts give the limits' values (simulate's said "MAX_SAMPLES samples, MAX_DENSE_RADIANS with samples")."""
    parser = build_parser()
    for name, sub in next(a for a in parser._actions if a.dest == "command").choices.items():
        assert not CONSTANT.search(sub.format_help()), (name, CONSTANT.findall(sub.format_help()))
    text = " ".join(_help("simulate").split())
    for value in (f"{MAX_SAMPLES:,}", f"{MAX_DENSE_RADIANS:g}", f"{MAX_RADIANS:g}", f"{MAX_GRID_POINTS:g}"):
        assert value in text


def test_workers_and_processes_say_which_is_which():
    """`--workers` is dask's worker processes (atlas); the processes a command runs itself are `--processes`: each
    help names the other."""
    parser = build_parser()
    atlas = next(a for a in parser._actions if a.dest == "command").choices["atlas"]
    helps = {a.option_strings[0]: a.help for a in atlas._actions if a.option_strings}
    assert "dask" in helps["--workers"] and "--processes" in helps["--workers"]
    assert "dask" in helps["--processes"] and "--workers" in helps["--processes"]


# ---------------------------------------------------------------------------------------------- errors
@pytest.mark.parametrize("message, command, argv, expected", [
    ("t_end=1e6 is too long: over the limit MAX_DENSE_RADIANS = 300000; use samples=False (turning points only) or "
     "a shorter t_end", "simulate", ["--t-end", "1e6"],
     "--t-end=1e6 is too long: over the limit 300000; use --turning-points-only or a shorter t_end"),
    ("t_end=1e6 is too long: over the limit MAX_DENSE_RADIANS = 300000; use samples=False (turning points only) or "
     "a shorter t_end", "animate", ["--t-end", "1e6"],
     "--t-end=1e6 is too long: over the limit 300000; use a shorter t_end"),
    ("tables are built on first use: call without build=False / --cached-only", "slow", ["--cached-only"],
     "tables are built on first use: call without --cached-only"),
    ("fps * duration must give 2 to 3000 frames (MAX_FRAMES), got 1", "animate", [],
     "fps * duration must give 2 to 3000 frames, got 1"),
    ("E = inf, beyond E_MAX = 1e+300", "table", [], "E = inf, beyond 1e+300"),
    ("the points stay in reduction.Q_RANGE = (1e-150, 1e+80)", "diagram", [], "the points stay in (1e-150, 1e+80)"),
    ("theta0 must lie in (0, pi), got theta0=array(0.)", "diagram", ["--theta0", "0"],
     "--theta0 must lie in (0, pi), got --theta0=0.0"),
    ("t_end: the run needs more than MAX_DENSE_STEPS = 600000 steps", "simulate", ["--t-end=5"],
     "--t-end: the run needs more than 600000 steps"),
    ("Q_R = 0.5 and Q_J (Q_R) are not constants", "simulate", [], "Q_R = 0.5 and Q_J (Q_R) are not constants"),
])
def test_cli_message(message, command, argv, expected):
    assert cli_message(message, command, argv) == expected


@pytest.mark.parametrize("argv, present, absent", [
    # the sample limit: its value, and the option that keeps no samples (was "MAX_SAMPLES = ...; ... samples=False")
    (["simulate", "--t-end", "1000", "--dt", "1e-4"], [str(MAX_SAMPLES), "--turning-points-only"], ["samples=False"]),
    (["simulate", "--t-end", "1e7"], [f"{MAX_DENSE_RADIANS:g}", "--turning-points-only"], ["samples=False"]),
    # animate keeps samples always: no alternative it does not have
    (["animate", "--t-end", "1e7", "--out", "{tmp}/a.gif"], [f"{MAX_DENSE_RADIANS:g}", "--t-end"],
     ["samples=False", "--turning-points-only"]),
    (["animate", "--fps", "60", "--duration", "100", "--out", "{tmp}/a.gif"], [str(MAX_FRAMES)], []),
    # a NumPy repr (array(3.14159265), fewer digits than pi: it read as inside the interval it was refused from)
    (["diagram", "--simulate", "--critical-line", "pi", "--theta0", "pi", "--out", "{tmp}"],
     ["--theta0=3.141592653589793"], ["array("]),
    (["diagram", "--simulate", "--critical-line", "pi", "--theta0", "0", "--out", "{tmp}"], ["--theta0=0.0"],
     ["array("]),
    # --theta0 banana named no option
    (["simulate", "--theta0", "banana"], ["--theta0: cannot read angle 'banana'"], []),
    (["table", "--theta0", "banana", "--out", "{tmp}/t.csv"], ["--theta0: cannot read angle 'banana'"], []),
    (["diagram", "--simulate", "--psi0", "pie", "--out", "{tmp}"], ["--psi0: cannot read angle 'pie'"], []),
])
def test_errors_in_the_words_of_the_command_line(argv, present, absent, tmp_path, capsys):
    err = _error([a.format(tmp=tmp_path) for a in argv], capsys)
    assert not CONSTANT.search(err), err
    for text in present:
        assert text in err
    for text in absent:
        assert text not in err


@pytest.mark.parametrize("command", ["slow", "atlas"])
def test_cached_only_is_named_as_the_option(command, no_tables, tmp_path, capsys):
    """A missing table said "call without build=False / --cached-only"."""
    extra = ["--psi0", "0.3", "--out", str(tmp_path / "atlas")] if command == "atlas" else []
    err = _error([command, "--theta0", "0.9pi", "--cached-only", *extra], capsys)
    assert "call without --cached-only" in err and "build=False" not in err


def test_parse_angle_refuses_an_integer_beyond_the_floats():
    """10**400 raised OverflowError (not the ValueError the CLI reports)."""
    with pytest.raises(ValueError, match="--theta0: angle must be finite"):
        parse_angle(10 ** 400, "--theta0")
    with pytest.raises(ValueError, match="^angle must be finite"):
        parse_angle(-(10 ** 400))


# ------------------------------------------------------------------------------------ refused, not ignored
@pytest.mark.parametrize("argv, message", [
    (["animate", "--offset", "0.1", "--out", "{tmp}/a.gif"], "--offset needs --critical-line"),
    (["animate", "--offset", "0.1", "--QR", "0.01", "--out", "{tmp}/a.gif"], "--QR and --offset need --critical-line"),
    (["diagram", "--offset", "0.1", "--out", "{tmp}"], "--critical-line, --QR and --offset need --simulate"),
    (["diagram", "--simulate", "--offset", "0.1", "--out", "{tmp}"], "--offset needs --critical-line"),
    (["atlas", "--theta0", "", "--out", "{tmp}/atlas"], "--theta0 must be a value or a grid"),
    (["atlas", "--psi0", "", "--out", "{tmp}/atlas"], "--psi0 must be a value or a grid"),
    (["atlas", "--plane", "rates", "--phi-dot0", "", "--out", "{tmp}/atlas"], "--phi-dot0 must be a value or a grid"),
])
def test_options_that_would_be_ignored_are_refused(argv, message, tmp_path, capsys):
    """--offset without --critical-line was ignored; atlas --theta0 "" took the default grid."""
    assert message in _error([a.format(tmp=tmp_path) for a in argv], capsys)


def test_offset_moves_a_critical_line_start(tmp_path, capsys):
    """With --critical-line, --offset is read (and 0 is its default)."""
    out = {}
    for offset in ([], ["--offset", "0.001"]):
        assert main(["diagram", "--simulate", "--critical-line", "pi", "--psi-dot0", "0.002", "--t-end", "2", "--json",
                     "--out", str(tmp_path), "--force", *offset]) == 0
        out[bool(offset)] = json.loads(capsys.readouterr().out)
    assert out[True]["QJ0"] != out[False]["QJ0"]


# ---------------------------------------------------------------------------------------------- item 25
def test_animate_t_end_inf_is_refused_without_a_warning(tmp_path, capsys):
    """numpy's "invalid value encountered in multiply" was printed before the clean error."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        err = _error(["animate", "--t-end", "inf", "--out", str(tmp_path / "a.gif")], capsys)
    assert "--t-end must be a finite number > 0" in err
    assert not caught, [str(w.message) for w in caught]


@pytest.mark.parametrize("I3", ["1e300", "1e-300", "2000"])
def test_table_takes_the_moments_simulate_takes(I3, tmp_path, capsys):
    """`table --I3 1e300` ran with an overflow warning and left 20 of 25 points unresolved."""
    lo, hi = MOMENT_RANGE
    err = _error(["table", "--I3", I3, "--out", str(tmp_path / "t.csv"), "--quiet"], capsys)
    assert f"--I3 must lie in [{lo:g}, {hi:g}]" in err
    assert not (tmp_path / "t.csv").exists()
