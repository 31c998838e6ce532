"""``rocknroller bifurcation``: the diagram and the period-2 orbits of both maps, as JSON; bad input exits 2."""

from __future__ import annotations

import json

import pytest

from rocknroller.cli import main


@pytest.mark.slow
def test_command(tmp_path, capsys):
    assert main(["bifurcation", "--theta0", "0.95pi", "--points", "5", "--exact-at", "1.05", "--out", str(tmp_path),
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["order"] == 2  # slow's default for a release in the release tables' range
    (row,) = out["period2"]
    assert row["eps_over_pd"] == pytest.approx(1.05)
    assert abs(row["Theta"]["slow"][0] - row["Theta"]["exact"][0]) < 1e-3
    capsys.readouterr()
    assert main(["bifurcation", "--eps", "0.01", "--out", str(tmp_path)]) == 2
    assert "--eps and --I2 are the diagram's variable" in capsys.readouterr().err
