"""One order everywhere: ``slow``, ``portrait``, ``bifurcation`` and the statistics share the map's default order
(:func:`rocknroller.analysis.slow.prediction.default_order`); ``atlas`` defaults to order 2 where the tables over energy
cover its rows, else 1 (``atlas_order``), and every output of it names its order;
``portrait --json`` and ``portrait_orbits.csv`` list every orbit's verdict, MEGNO, λ and span."""

from __future__ import annotations

import csv
import json
import math

import pytest

from rocknroller.analysis.slow.atlas import atlas_order
from rocknroller.analysis.slow.ensemble_statistics import StartBall, map_ensemble
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.prediction import default_order
from rocknroller.cli import build_parser, main
from rocknroller.numerics.megno import MEGNO_CHAOTIC


def test_the_commands_default_to_slow_s_order():
    parser = build_parser()
    for command in (["slow"], ["portrait"], ["bifurcation"]):
        assert parser.parse_args(command).order is None  # resolved by default_order, as slow resolves it
    assert default_order(0.95 * math.pi) == 2
    ens = map_ensemble(Body.paper(1e-3), StartBall(0.95 * math.pi, 0.3, 1e-3, 2), 200.0)
    assert ens.order == default_order(0.95 * math.pi)


def test_portrait_lists_every_orbit_at_slow_s_order(tmp_path, capsys):
    out_dir = tmp_path / "p"
    assert main(["portrait", "--Theta", "0.5pi:1.5pi:2", "--p", "-1:1:2", "--t-end", "300", "--out", str(out_dir),
                 "--json", "--quiet"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["order"] == default_order(0.95 * math.pi)
    assert len(out["orbits"]) == out["n_orbits"] == 4
    with open(out_dir / "portrait_orbits.csv") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    assert len(rows) == 4
    for o, row in zip(out["orbits"], rows):
        assert o["verdict"] == ("regular" if o["megno"] <= MEGNO_CHAOTIC else "chaotic") == row["verdict"]
        assert float(row["megno"]) == pytest.approx(o["megno"], rel=1e-12)
        assert o["lyapunov"] >= 0.0 and 0.0 < o["span"] <= 300.0 and o["n_maxima"] >= 8


def test_atlas_names_its_order(tmp_path, capsys):
    """The atlas's order is its default (``atlas_order``: 2 where the tables over energy cover the rows, else 1) or
    the one asked for, named in the JSON and the CSV header."""
    body = Body.paper()
    for given, want in ((None, atlas_order(body, [0.95 * math.pi])), ("1", 1)):
        out_dir = tmp_path / f"a{given}"
        assert main(["atlas", "--theta0", "0.95pi", "--psi0", "0.3:0.4:2", "--t-end", "200", "--confirm-every", "0",
                     "--out", str(out_dir), "--json", "--quiet"] + ([] if given is None else ["--order", given])) == 0
        out = json.loads(capsys.readouterr().out)
        assert out["order"] == want
        header = [line for line in open(out_dir / "atlas.csv") if line.startswith("#")]
        assert any(f"averaged map of order {want} in eps" in line for line in header)


def test_every_api_entry_defaults_to_the_one_order():
    """SlowMap and slow_portrait defaulted to order 1 while predict_slow_motion and slow defaulted to 2 (mixing them
    gave 0.7 % in the Q_R extent): every entry that takes an order now defaults to None, resolved by default_order,
    and a SlowMap made without one is of the prediction's order."""
    import inspect

    import rocknroller as rr
    from rocknroller.analysis.slow.dynamics.periodic_starts import periodic_start
    from rocknroller.papers.bifurcation import bifurcation_data

    entries = (rr.SlowMap, rr.slow_portrait, rr.periodic_orbit, rr.continue_orbit, periodic_start, bifurcation_data,
               rr.predict_slow_motion, rr.map_ensemble)
    for entry in entries:
        assert inspect.signature(entry).parameters["order"].default is None, entry.__name__
    body, theta0 = Body.paper(1e-3), 0.95 * math.pi
    assert rr.SlowMap(body, theta0, 1e-3).order == rr.predict_slow_motion(body, theta0, 0.3, 50.0).order == 2
