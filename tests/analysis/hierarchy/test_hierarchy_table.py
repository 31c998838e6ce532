"""Borisov and Mamaev's table with its evidence (analysis/hierarchy/table.py, drift.py, members.py), its figure
(papers/hierarchy_plots.py) and ``rocknroller hierarchy`` (api/cli/hierarchy.py)."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest
from figure_checks import draw, inside

from rocknroller.analysis.hierarchy import drift as drift_module
from rocknroller.analysis.hierarchy.conservation import QUANTITIES
from rocknroller.analysis.hierarchy.drift import Drift, member_drifts
from rocknroller.analysis.hierarchy.members import MEMBER_BODIES, VALUES, member_start
from rocknroller.analysis.hierarchy.table import FAR_ABOVE, Entry, hierarchy_table
from rocknroller.analysis.model.body import MEMBERS
from rocknroller.cli import main
from rocknroller.papers.hierarchy_plots import hierarchy_figure


@pytest.fixture(scope="module")
def rows():
    return hierarchy_table(t_end=100.0)


def test_the_representatives_are_the_members_they_stand_for():
    assert [b.kind for b in MEMBER_BODIES.values()] == list(MEMBERS) == list(MEMBER_BODIES)
    assert set(VALUES) == {q.name for q in QUANTITIES}


def test_every_proof_is_confirmed_by_the_direct_ode(rows):
    """Each conserved quantity within the run's round-off bound, each one proved not conserved ≥ FAR_ABOVE past it."""
    assert [row.member for row in rows] == list(MEMBERS)
    for row in rows:
        assert set(row.entries) == {q.name for q in QUANTITIES if q.defined_for(row.member)}
        for name, e in row.entries.items():
            assert e.agrees, (row.member, name, e.proof.conserved, e.drift)


def test_the_table_is_borisov_and_mamaevs(rows):
    """The integrals of each member (Borisov & Mamaev 2002, table 1; Chaplygin 1903 for the ball): the ball E, M·M,
    M·γ (and M·r = M·γ there); Routh's sphere E, Jellett, Routh; the rock'n'roller and the top E alone; with g = 0
    also Borisov and Mamaev's B, and for the ball B with gravity too (no gravity torque at c = 0)."""
    integrals = {row.member: set(row.integrals) for row in rows}
    assert integrals == {
        "Chaplygin's ball": {"energy", "jellett", "momentum_squared", "momentum_vertical", "borisov_mamaev_g0",
                             "borisov_mamaev"},
        "rock'n'roller": {"energy", "borisov_mamaev_g0"},
        "Routh's sphere": {"energy", "jellett", "routh", "borisov_mamaev_g0"},
        "Chaplygin's top": {"energy", "borisov_mamaev_g0"},
    }
    assert [row.measure.density_exists for row in rows] == [True, False, True, False]


def test_agreement_fails_where_the_measurement_contradicts_the_proof(rows):
    e = rows[0].entries["energy"]
    assert not Entry(e.proof, Drift("energy", 10 * e.drift.bound, e.drift.bound, 9.87, 1.0)).agrees
    wrong = rows[1].entries["jellett"]
    assert not Entry(wrong.proof, Drift("jellett", FAR_ABOVE * wrong.drift.bound / 2, wrong.drift.bound, 9.87,
                                        1.0)).agrees


def test_a_drift_is_measured_not_assumed(monkeypatch):
    """Replacing a conserved quantity's formula by one that is not (E without its potential) is caught."""
    energy = VALUES["energy"]
    monkeypatch.setitem(drift_module.VALUES, "energy", lambda body, g, w: energy(body, g, w) - body.g * g[2])
    d = member_drifts("Routh's sphere", t_end=20.0)["energy"]
    assert not d.within_round_off and d.drift > 1e-3


def test_the_drift_is_relative_to_the_quantitys_size():
    body = MEMBER_BODIES["Chaplygin's top"]
    d = drift_module.quantity_drifts(body, member_start(), 20.0, ("jellett",))["jellett"]
    from rocknroller.numerics.integrate import simulate

    traj = simulate(body, member_start(), 20.0, progress=False)
    q = VALUES["jellett"](body, traj.gamma, traj.omega)
    assert d.drift == pytest.approx(np.max(np.abs(q - q[0])) / np.max(np.abs(q)), rel=1e-12)


def test_bad_t_end_is_refused():
    with pytest.raises(ValueError, match=r"t_end must lie in \[1, 1e4\]"):
        hierarchy_table(t_end=0.5)


def test_the_figure_has_its_titles_and_stays_in_the_frame(rows):
    fig = hierarchy_figure(rows)
    renderer = draw(fig)
    titles = [ax.get_title() for ax in fig.axes]
    assert "The loaded spheres (paper fig. 1)" in titles and any("sympy" in t for t in titles)
    assert all(inside(fig, t, renderer) for ax in fig.axes for t in ax.texts)
    assert fig.axes[-1].get_ylabel().startswith(r"$\log_{10}$")  # the colour bar, labelled


def test_the_command_writes_json_csv_and_figures(tmp_path, capsys):
    assert main(["hierarchy", "--t-end", "20", "--json", "--out", str(tmp_path)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert [m["member"] for m in out["members"]] == list(MEMBERS) and out["all_agree"] is True
    top = out["members"][3]
    assert "routh" not in top["quantities"] and top["quantities"]["energy"]["conserved"] is True
    assert top["invariant_measure"]["exists"] is False
    for m in out["members"]:
        for q in m["quantities"].values():
            assert q["agrees"] and (q["drift"] <= q["round_off_bound"]) == q["conserved"]
    with open(tmp_path / "hierarchy.csv") as fh:
        lines = [line for line in fh if not line.startswith("#")]
    table = list(csv.DictReader(lines))
    assert len(table) == sum(len(m["quantities"]) for m in out["members"])
    assert {p.name for p in tmp_path.iterdir()} == {"hierarchy.csv", "hierarchy.png", "hierarchy.pdf"}


def test_the_command_refuses_bad_input_in_one_line(capsys):
    assert main(["hierarchy", "--t-end", "1e9"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--t-end must lie in [1, 1e4]" in err
