"""Shared option handling of the command line (``api/cli/options.py``): negative values, which argparse has no public
way to accept in the forms this CLI takes (issue 25, item 16: the private hook is kept, and checked here)."""

from __future__ import annotations

import argparse
import signal
import subprocess
import sys
import time

import pytest

from rocknroller.cli import main
from rocknroller.cli.options import accept_negative_values


def test_argparse_still_has_the_hook():
    """The attribute replaced by ``accept_negative_values`` exists on this Python's ArgumentParser: if a future
    argparse drops it, this fails (and the CLI raises rather than silently refusing negative values)."""
    assert hasattr(argparse.ArgumentParser(), "_negative_number_matcher")


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(exit_on_error=False)
    p.add_argument("--phi0")
    p.add_argument("--omega", nargs=3)
    p.add_argument("--QR")
    return p


@pytest.mark.parametrize("argv, expected", [
    (["--phi0", "-0.5pi"], {"phi0": "-0.5pi"}), (["--phi0", "-pi/4"], {"phi0": "-pi/4"}),
    (["--phi0", "-inf"], {"phi0": "-inf"}), (["--omega", "0", "-1e-3", "0"], {"omega": ["0", "-1e-3", "0"]}),
    (["--QR", "-0.01:0.01:3"], {"QR": "-0.01:0.01:3"}), (["--phi0", "-.5"], {"phi0": "-.5"}),
])
def test_negative_values_are_values(argv, expected):
    p = _parser()
    accept_negative_values(p)
    args = vars(p.parse_args(argv))
    assert {k: args[k] for k in expected} == expected


@pytest.mark.parametrize("value", ["-0.5pi", "-pi/4", "-0.01:0.01:3"])
def test_argparse_alone_refuses_them(value):
    """Why the hook is needed: without it argparse takes these values for unknown options."""
    with pytest.raises((argparse.ArgumentError, SystemExit)):
        _parser().parse_args(["--phi0", value])


def test_a_missing_hook_is_an_error_not_silence(monkeypatch):
    p = argparse.ArgumentParser()
    del p._negative_number_matcher
    with pytest.raises(RuntimeError, match="--phi0=-0.5pi"):
        accept_negative_values(p)


@pytest.mark.parametrize("argv", [["simulate", "--out", ""], ["diagram", "--out", " "], ["slow", "--csv", ""],
                                  ["table", "--out", ""], ["hierarchy", "--out", ""]])
def test_an_empty_output_name_is_refused(argv, capsys, tmp_path, monkeypatch):
    """--out "" wrote into the current folder, which nobody named."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as stop:
        main([*argv, "--t-end", "1"] if argv[0] in ("simulate", "hierarchy") else argv)
    assert stop.value.code == 2 and "an empty name names no file or folder" in capsys.readouterr().err
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize("sig, status, name", [(signal.SIGTERM, 143, "SIGTERM"), (signal.SIGINT, 130, "SIGINT")])
def test_an_interrupted_run_says_so_in_one_line_and_leaves_no_empty_reservation(sig, status, name, tmp_path):
    """SIGTERM left the reserved, empty output files (the next run was refused); Ctrl-C printed a 10-line
    traceback.  The child gets SIGINT's default disposition: a suite started in the background by a shell without
    job control inherits SIGINT ignored, and Python then installs no KeyboardInterrupt handler (as for any program
    that Ctrl-C cannot reach)."""
    out = tmp_path / "run"
    proc = subprocess.Popen([sys.executable, "-m", "rocknroller", "simulate", "--t-end", "1.3e6",
                             "--turning-points-only", "--out", str(out), "--quiet"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 120.0
    while not ((out / "turning_points.csv").exists() and (out / "turning_points.csv").stat().st_size > 1000):
        assert proc.poll() is None and time.monotonic() < deadline, proc.communicate()
        time.sleep(0.05)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == status
    assert err.strip().splitlines() == [f"rocknroller simulate: interrupted ({name}); the outputs it had reserved and "
                                        "not yet begun are removed"]
    assert sorted(p.name for p in out.iterdir()) == ["turning_points.csv"]  # the stream written so far; no empties


@pytest.mark.parametrize("command", ["slow", "portrait", "atlas", "bifurcation"])
@pytest.mark.parametrize("g", ["0", "1e-300", "1e300"])
def test_the_slow_motions_commands_check_gravity_as_simulate_does(command, g, capsys):
    """portrait --g 0 reported a 'double root ... at theta=1.4e-65', --g 1e-300 heyoka's error, atlas --g 1e300 a
    290-digit estimate: each is refused before any work, in one line naming --g and its range."""
    assert main([command, "--g", g]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--g must lie in [1e-12, 1e+12]" in err


def test_force_never_writes_through_a_link_out_of_the_folder(tmp_path, capsys):
    """--force followed a symlinked output file out of --out and overwrote what it pointed to."""
    precious = tmp_path / "precious.txt"
    precious.write_text("precious\n")
    out = tmp_path / "out"
    out.mkdir()
    (out / "samples.csv").symlink_to(precious)
    assert main(["simulate", "--t-end", "5", "--out", str(out), "--force", "--quiet"]) == 2
    assert "is a symbolic link" in capsys.readouterr().err and precious.read_text() == "precious\n"
