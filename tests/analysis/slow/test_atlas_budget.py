"""The work of a map-made atlas (``atlas_from_rest``, ``rocknroller atlas``) estimated before any of it: the tables
not cached, the runs with the chaos layer's tangent vectors, each point's overhead, and on the command line the
ODE confirmation too; a small budget refused before any table is built or point run."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.atlas import atlas_from_rest, atlas_seconds
from rocknroller.analysis.slow.atlas_check import confirm_seconds
from rocknroller.analysis.slow.map import table as table_module
from rocknroller.analysis.slow.map import tables_at_once
from rocknroller.analysis.slow.map.table import build_table
from rocknroller.cli import main
from rocknroller.numerics.budget import RELEASE_TABLE_SECONDS, WorkBudgetError

from budget_checks import mark_cached, no_tables_in_memory  # noqa: F401 (an autouse fixture)
from budget_checks import no_work as no_work_stub

BODY = Body.paper(1e-3)
TH = [0.9 * math.pi, 0.95 * math.pi]
PSI = np.linspace(0.0, 3.0, 200)


@pytest.fixture
def no_work(monkeypatch):
    for module, name in ((av, "load_or_build_table"), (av, "predict_slow_motion"),
                         (table_module, "cached_table"), (tables_at_once, "release_tables")):
        monkeypatch.setattr(module, name, no_work_stub)


def _warm(tmp_path, monkeypatch):
    """A cache folder holding the release tables of TH."""
    mark_cached(tmp_path / "warm", monkeypatch, BODY, [(build_table, t0) for t0 in TH])


def test_tables_and_runs_are_one_estimate_refused_before_any_work(tmp_path, monkeypatch, no_work):
    """The tables and the runs were checked apart: each within the budget, their sum not."""
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path / "empty"))
    seconds, _ = atlas_seconds(BODY, TH, PSI.size, 1000.0)
    tables = 2 * RELEASE_TABLE_SECONDS
    assert seconds > tables
    with pytest.raises(WorkBudgetError, match=r"the atlas's 400 points \(2 release and 0 region tables to "
                                              r"build; 400 map runs .* tangent vectors"):
        atlas_from_rest(BODY, TH, PSI, 1000.0, budget=0.5 * (seconds + tables))


def test_the_estimate_counts_the_tables_not_cached(tmp_path, monkeypatch):
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path / "empty"))
    cold = atlas_seconds(BODY, TH, PSI.size, 1000.0)[0]
    _warm(tmp_path, monkeypatch)
    warm = atlas_seconds(BODY, TH, PSI.size, 1000.0)[0]
    assert cold - warm == pytest.approx(2 * RELEASE_TABLE_SECONDS)


def test_the_estimate_counts_the_chaos_layer(tmp_path, monkeypatch, no_work):
    """250 000 points "about 2 min" took 812 s of CPU: the chaos layer and each point's overhead were not counted."""
    _warm(tmp_path, monkeypatch)
    plain = atlas_seconds(BODY, TH, PSI.size, 1000.0, chaos=False, build=False)[0]
    chaos = atlas_seconds(BODY, TH, PSI.size, 1000.0, chaos=True, build=False)[0]
    assert chaos > plain
    budget = 0.5 * (plain + chaos)
    with pytest.raises(AssertionError, match="work started"):  # within the budget: the rows would run
        atlas_from_rest(BODY, TH, PSI, 1000.0, chaos=False, budget=budget)
    with pytest.raises(WorkBudgetError, match="the chaos layer"):
        atlas_from_rest(BODY, TH, PSI, 1000.0, chaos=True, budget=budget)


def test_the_command_counts_its_confirmation_before_the_atlas_runs(tmp_path, monkeypatch, no_work, capsys):
    """The atlas and its ODE confirmation were checked apart, the confirmation's only after the atlas was made."""
    _warm(tmp_path, monkeypatch)
    atlas = atlas_seconds(BODY, TH, PSI.size, 1000.0, files=True)[0]
    confirm = confirm_seconds(BODY, TH, PSI, 1000.0, every=50)[0]
    assert confirm > 0.0
    status = main(["atlas", "--eps", "1e-3", "--theta0", "0.9pi:0.95pi:2", "--psi0", "0:3:200", "--t-end", "1000",
                   "--budget", f"{atlas + 0.5 * confirm!r}", "--out", str(tmp_path / "out"), "--quiet"])
    err = capsys.readouterr().err
    assert status != 0 and "work started" not in err
    assert "and the confirmation of 8 points" in err and "--budget SECONDS" in err
