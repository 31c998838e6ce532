"""``rocknroller bifurcation``: the diagram and the period-2 orbits of both maps, as JSON; bad input exits 2."""

from __future__ import annotations

import json
import math
import re
import types

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map import table as slow_table
from rocknroller.analysis.slow.dynamics import periodic_orbits
from rocknroller.analysis.slow.dynamics.periodic_orbits import continue_orbit
from rocknroller.cli import build_parser, main


@pytest.mark.slow
def test_command(tmp_path, capsys):
    assert main(["bifurcation", "--theta0", "0.95pi", "--points", "5", "--exact-at", "1.05", "--out", str(tmp_path),
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["order"] == 2  # slow's default for a release in the release tables' range
    (row,) = out["period2"]
    assert row["eps_over_pd"] == pytest.approx(1.05)
    assert abs(row["Theta"]["slow"][0] - row["Theta"]["exact"][0]) < 1e-3
    header = [ln for ln in (tmp_path / "bifurcation.csv").read_text().splitlines() if ln.startswith("#")]
    assert "theta0: 0.95pi" in "\n".join(header)
    assert not any(n in ln for ln in header for n in ("np.float64", "0.35000000000000003"))


def _help() -> str:
    parser = build_parser()
    return next(a for a in parser._actions if a.dest == "command").choices["bifurcation"].format_help()


def _error(argv, capsys) -> str:
    assert main(["bifurcation", *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


def test_help_lists_what_the_command_accepts(capsys):
    """The help listed --eps and --I2, which the command then refused, and had no --quiet or --cached-only."""
    text = _help()
    assert "--eps" not in text and "--I2" not in text
    assert "--quiet" in text and "--cached-only" in text
    with pytest.raises(SystemExit):
        main(["bifurcation", "--eps", "0.01"])
    capsys.readouterr()


def test_points_range_of_the_help_is_the_one_checked(tmp_path, monkeypatch, capsys):
    """--points 1001 passed the command's check (3 to 2000) and failed in the continuation ("eps_values must be 1
    to 1000 values"); the help gave no range."""
    lo, hi = map(int, re.search(r"--points POINTS\s+values of eps on the branches, (\d+) to (\d+)",
                                " ".join(_help().split())).groups())
    assert lo == 3
    err = _error(["--points", str(hi + 1), "--out", str(tmp_path)], capsys)
    assert f"--points must be an integer in [3, {hi}]" in err
    # the continuation takes as many values as the command allows (each orbit replaced by a stand-in: the count only)
    monkeypatch.setattr(periodic_orbits, "periodic_orbit",
                        lambda body, theta0, eps, *a, **k: types.SimpleNamespace(points=np.zeros((1, 3)), eps=eps))
    assert len(continue_orbit(Body.paper(), 0.95 * math.pi, np.linspace(1e-3, 2e-3, hi)).orbits) == hi


@pytest.mark.parametrize("argv, words", [(["--to", "1.3", "--exact-at", "1.4"], "--exact-at must lie in (0, 1.3]"),
                                         (["--to", "0.9"], "--from/--to (lo, hi) of eps_pd must satisfy")])
def test_errors_name_the_options(argv, words, tmp_path, capsys):
    """--to 1.3 named exact_fractions (the default --exact-at went past it); --to 0.9 said "give a start", which only
    the API can."""
    err = _error([*argv, "--theta0", "0.95pi", "--out", str(tmp_path)], capsys)
    assert words in err
    for api in ("exact_fractions", "fractions=", "n_points", "eps_values", "give a start", "eps="):
        assert api not in err


def test_cached_only(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path / "cache"))
    monkeypatch.setattr(slow_table, "_TABLES", {})
    err = _error(["--cached-only", "--theta0", "0.95pi", "--out", str(tmp_path / "out")], capsys)
    assert "call without --cached-only" in err and "build=False" not in err


def test_theta0_range_writes_the_period_doubling_line(tmp_path, capsys):
    """``bifurcation --theta0-range``: ε_pd over the release angles at orders 1 and 2, its three files (the CSV's
    header records the body), and K = ε_pd κ within the second order's correction of 4 (0.08 at 0.8π,
    docs/averaging.md)."""
    import csv

    assert main(["bifurcation", "--theta0-range", "0.9pi:0.95pi:2", "--out", str(tmp_path), "--json", "--quiet"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert sorted(p.split("/")[-1] for p in out["files"]) == ["period_doubling.csv", "period_doubling.pdf",
                                                               "period_doubling.png"]
    lines = open(tmp_path / "period_doubling.csv").read().splitlines()
    assert any(line.startswith("#") and "a=0.05" in line for line in lines)
    rows = list(csv.DictReader(line for line in lines if not line.startswith("#")))
    assert [float(r["theta0_over_pi"]) for r in rows] == pytest.approx([0.9, 0.95], rel=1e-15)
    for r, e1, e2 in zip(rows, out["eps_order1"], out["eps_order2"]):
        assert float(r["eps_order1"]) == e1 and float(r["eps_order2"]) == e2
        assert abs(float(r["K_order2"]) - 4.0) < 0.05 and e2 != e1


@pytest.mark.parametrize("argv, words", [
    (["--theta0-range", "0.9pi:0.95pi:2", "--theta0", "0.9pi"], "not both"),
    (["--theta0-range", "0.9pi:0.95pi"], "--theta0-range must be a value or a grid"),
    (["--theta0-range", "0.5pi:0.9pi:3"], "theta0 must lie in"),
])
def test_theta0_range_refuses_bad_input(argv, words, tmp_path, capsys):
    assert main(["bifurcation", *argv, "--out", str(tmp_path)]) == 2
    assert words in capsys.readouterr().err
