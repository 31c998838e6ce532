"""``rocknroller slow`` from a start on a periodic orbit of the map (pure rocking): reported as that orbit with its
residue and stability, without indicators, horizon or relative errors against zero extents
(:mod:`rocknroller.cli.slow_periodic`, :func:`rocknroller.analysis.slow.dynamics.periodic_starts.periodic_start`)."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map.limits import stable_rocking_psi
from rocknroller.analysis.slow.dynamics.periodic_orbits import periodic_orbit
from rocknroller.analysis.slow.dynamics.periodic_starts import periodic_start
from rocknroller.analysis.slow.map.table import load_or_build_table
from rocknroller.cli import main

THETA0, EPS = 0.93 * math.pi, 5e-3


def test_pure_rocking_about_the_stable_axis_json(capsys):
    assert main(["slow", "--theta0", "0.93pi", "--eps", "5e-3", "--psi0", "pi/2", "--t-end", "300", "--json",
                 "--check", "--quiet"]) == 0
    out = json.loads(capsys.readouterr().out)
    po = out["periodic_orbit"]
    assert po["kind"] == "pure rocking" and po["period"] == 1 and po["order"] == 2
    kappa = load_or_build_table(Body.paper(EPS), THETA0).kappa
    assert po["psi"] == [pytest.approx(stable_rocking_psi(kappa))]  # pi/2 mod pi: the stable axis for kappa > 0
    # the residue of the fixed point found by Newton's method from the default start, on the same map
    ref = periodic_orbit(Body.paper(EPS), THETA0, EPS, 1, order=2)
    assert po["residue"] == pytest.approx(ref.residue, abs=1e-6) and 0.0 < po["residue"] < 1.0 and po["stable"]
    lam = np.array([complex(*m) for m in po["multipliers"]])
    np.testing.assert_allclose(np.abs(lam), 1.0, atol=1e-6)  # elliptic: on the unit circle
    assert po["residual"] <= po["residual_bound"]
    assert out["chaos"] is None and out["horizon"] is None and out["beyond_horizon"] is None
    assert out["QR_extent"] == out["QJ_extent"] == out["Phi"] == 0.0 and out["slow_period"] is None
    assert all(v is None for v in out["rel_error"].values())  # no relative error against the ODE's zero extents
    assert out["statistics"] is None


def test_pure_rocking_about_the_unstable_axis_text(capsys):
    assert main(["slow", "--theta0", "0.93pi", "--eps", "5e-3", "--psi0", "0", "--t-end", "300", "--quiet"]) == 0
    text = capsys.readouterr().out
    found = re.search(r"periodic orbit: pure rocking \(psi = (\S+) mod pi\)", text)
    assert found and abs(float(found.group(1))) < 1e-15  # Newton's fixed point: 0, or its round-off on other tables
    assert "unstable (hyperbolic: R < 0" in text
    assert "CHAOTIC" not in text and "predictability horizon: t =" not in text


def test_other_starts_are_not_periodic(capsys):
    assert main(["slow", "--theta0", "0.93pi", "--eps", "5e-3", "--psi0", "pi/4", "--t-end", "300", "--json",
                 "--quiet"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["periodic_orbit"] is None and out["chaos"] is not None


def test_periodic_start_checks_and_limits():
    assert periodic_start(Body.paper(0.0), THETA0, 0.5 * math.pi) is None  # eps = 0: pure rocking, no map to linearise
    po = periodic_start(Body.paper(EPS), THETA0, 0.0, order=1)
    assert po is not None and po.period == 1 and po.residue < 0.0 and not po.stable
    with pytest.raises(ValueError, match="psi0"):
        periodic_start(Body.paper(EPS), THETA0, math.nan)
    with pytest.raises(ValueError, match="theta0"):
        periodic_start(Body.paper(EPS), 0.5 * math.pi, 0.0)


def test_pure_rocking_is_found_where_the_second_order_map_moves_it_by_its_tables_error():
    """At 0.85pi, K = 3.9, order 2, one step of the map from Q = 0, Theta = pi moves it by 1e-11 in Theta (the
    harmonics of k2 cancel at Q = 0 to the tables' accuracy only): the start is pure rocking by symmetry, and its
    fixed point of the map is found nearby by Newton's method, to the residual periodic_orbit solves to."""
    from rocknroller.analysis.slow.dynamics.periodic_starts import on_rocking_axis

    assert on_rocking_axis(0.0) and on_rocking_axis(0.5 * math.pi) and on_rocking_axis(math.pi)
    assert on_rocking_axis(-1.5 * math.pi) and not on_rocking_axis(1e-9) and not on_rocking_axis(0.25 * math.pi)
    theta0 = 0.85 * math.pi
    eps = 3.9 / load_or_build_table(Body.paper(0.0), theta0).kappa
    po = periodic_start(Body.paper(eps), theta0, 0.5 * math.pi, order=2)
    assert po.period == 1 and po.residual <= po.residual_bound and po.stable
    assert np.max(np.abs(po.Q)) < 1e-9


def test_a_start_whose_first_step_leaves_the_release_tables_is_not_periodic():
    theta0 = 0.85 * math.pi
    eps = 3.9 / load_or_build_table(Body.paper(0.0), theta0).kappa
    assert periodic_start(Body.paper(eps), theta0, math.pi / 16, order=2) is None
