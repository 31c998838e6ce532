"""``rocknroller slow``: JSON keys, --check against the ODE, warnings and errors outside the valid regime."""

from __future__ import annotations

import json
import math

import pytest

from analysis import averaging as av
from analysis.body import Body
from analysis.slow_pendulum import pendulum_constants
from rocknroller.cli import main


@pytest.fixture(scope="module")
def fresh_cache(tmp_path_factory):
    """An empty cache directory (shared by this module): the command must build its tables itself."""
    path = tmp_path_factory.mktemp("cache")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("ROCKNROLLER_CACHE", str(path))
        mp.setattr(av, "_TABLES", {})
        yield path


def test_json_and_check(fresh_cache, capsys):
    assert main(["slow", "--eps", "1e-3", "--psi0", "3pi/8", "--t-end", "400", "--json", "--check"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("slow_period", "QR_extent", "QJ_extent", "Phi", "pendulum", "ode", "rel_error"):
        assert key in out
    for key in ("slow_period", "QR_extent", "QJ_extent", "Phi", "kappa", "eps_period_doubling"):
        assert key in out["pendulum"]
    # first-order map at eps = 1e-3: relative errors O(eps) (docs/averaging.md)
    for q in ("slow_period", "QR_extent", "Phi"):
        assert abs(out["rel_error"][q]) < 5e-3, (q, out["rel_error"][q])
    assert out["rocks_per_region"] == out["ode"]["rocks_per_region"]
    assert out["warnings"] == []
    # the tables were built and cached
    assert list((fresh_cache / "averaging").glob("slowmap-*.npz"))


def test_plain_output_and_plot(fresh_cache, tmp_path, capsys):
    assert main(["slow", "--t-end", "200", "--plot", str(tmp_path / "fig")]) == 0
    captured = capsys.readouterr()
    assert "slow_period" in captured.out and "period doubling" in captured.out
    for ext in ("png", "pdf"):
        f = tmp_path / "fig" / f"slow_orbit.{ext}"
        assert f.exists() and f.stat().st_size > 1000


def test_outside_valid_regime(fresh_cache, capsys):
    assert main(["slow", "--eps=-1e-3"]) == 2
    assert "eps" in capsys.readouterr().err
    assert main(["slow", "--theta0", "1.2pi"]) == 2
    assert "theta0" in capsys.readouterr().err
    assert main(["slow", "--theta0", "0.9pi", "--cached-only"]) == 2
    assert "no averaging tables" in capsys.readouterr().err
    assert main(["slow", "--eps", "1.1e-2", "--t-end", "100", "--json"]) == 0
    captured = capsys.readouterr()
    eps_pd = pendulum_constants(Body.paper(1.1e-2), 0.95 * math.pi).eps_period_doubling
    assert "K = eps*kappa" in captured.err and f"eps < {eps_pd:.4g} " in captured.err
    assert json.loads(captured.out)["warnings"]
