"""`rocknroller simulate`: JSON summary, output files, and bad input (message, no traceback, status 2)."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import pytest

from rocknroller.cli import main
from rocknroller.options import parse_angle


def test_parse_angle():
    assert parse_angle("0.95pi") == pytest.approx(0.95 * math.pi)
    assert parse_angle("pi/4") == pytest.approx(math.pi / 4)
    assert parse_angle("3pi/8") == pytest.approx(3 * math.pi / 8)
    assert parse_angle("-0.5*pi") == pytest.approx(-0.5 * math.pi)
    assert parse_angle("2.9") == 2.9
    for bad in ("", "pie", "1/0pi", "pi/0", "abc"):
        with pytest.raises(ValueError, match="angle"):
            parse_angle(bad)


def test_json_summary(capsys):
    assert main(["simulate", "--t-end", "50", "--json", "--quiet"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"energy_rel_error", "n_maxima", "n_minima", "Phi", "t_end"}
    assert out["t_end"] == 50 and out["n_maxima"] >= 3 and out["energy_rel_error"] < 1e-13


def test_outputs_written(tmp_path, capsys):
    assert main(["simulate", "--t-end", "30", "--quiet", "--out", str(tmp_path), "--eps", "0.01",
                 "--theta0", "0.9pi", "--psi0", "pi/4"]) == 0
    for name in ("samples.csv", "turning_points.csv", "contact_track.png", "contact_track.pdf",
                 "phi_at_maxima.png", "phi_at_maxima.pdf", "QR_QJ_orbit.png", "QR_QJ_orbit.pdf"):
        assert (tmp_path / name).stat().st_size > 0, name
    head = (tmp_path / "samples.csv").read_text().splitlines()[:4]
    assert head[0].startswith("# rocknroller simulate") and "epsilon=0.01" in head[1]


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["--a", "1.2"], "a must satisfy 0 <= a < 1"),
        (["--I1", "-1"], "I1 must be > 0"),
        (["--I1", "0.1", "--I2", "0.1"], "triangle inequality"),
        (["--eps", "0.01", "--I2", "0.36"], "either --I2 or --eps"),
        (["--theta0", "4", "--theta-dot0", "1"], "0 <= theta0 <= pi"),
        (["--t-end", "-1"], "t_end must be"),
        (["--theta0", "nan"], "angle"),
    ],
)
def test_bad_input_exits_2_without_traceback(argv, fragment):
    proc = subprocess.run([sys.executable, "-m", "rocknroller.cli", "simulate", "--quiet", *argv],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert fragment in proc.stderr and "Traceback" not in proc.stderr


def test_every_command_has_help():
    from rocknroller.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    assert "simulate" in sub.choices
    for name, p in sub.choices.items():
        assert p.format_help().strip(), name
