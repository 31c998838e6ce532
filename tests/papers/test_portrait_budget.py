"""The work of a phase portrait (``slow_portrait``, ``rocknroller portrait``) estimated before any of it: the tables
not cached, the orbits with their tangent vectors, the horizon probes; a small budget refused before any table is
built or orbit run."""

from __future__ import annotations

import math

import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map import maps
from rocknroller.analysis.slow.map.second_order import build_second_order_table
from rocknroller.analysis.slow.map.table import build_table
from rocknroller.cli import main
from rocknroller.numerics.budget import RELEASE_TABLE_SECONDS, SECOND_ORDER_TABLE_SECONDS, WorkBudgetError
from rocknroller.papers import portrait
from rocknroller.papers.portrait import slow_portrait
from rocknroller.papers.portrait_limits import portrait_seconds

from budget_checks import mark_cached, no_tables_in_memory  # noqa: F401 (an autouse fixture)
from budget_checks import no_work as no_work_stub

BODY = Body.paper(5e-3)
TH = 0.95 * math.pi


@pytest.fixture
def empty_cache(tmp_path, monkeypatch):
    """An empty ROCKNROLLER_CACHE: every table of the portrait is to be built."""
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path / "empty"))
    return tmp_path / "empty"


def _warm(tmp_path, monkeypatch):
    """A cache folder holding both tables of (BODY, TH)."""
    mark_cached(tmp_path / "warm", monkeypatch, BODY, [(build_table, TH), (build_second_order_table, TH)])


def test_a_small_budget_is_refused_before_any_table_or_orbit(empty_cache, monkeypatch):
    monkeypatch.setattr(portrait, "release_tables", no_work_stub)
    monkeypatch.setattr(maps.SlowMap, "__post_init__", no_work_stub)
    with pytest.raises(WorkBudgetError, match=r"the portrait \(1 release, 0 region and 1 second-order tables to "
                                              r"build, 4 map orbits .* would take about"):
        slow_portrait(BODY, TH, [0.5, 1.5], [0.0, 0.1], 200.0, order=2, budget=1.0)


def test_the_command_refuses_an_uncached_build_within_budget_1(empty_cache, monkeypatch, capsys, tmp_path):
    """``portrait --budget 1`` with no tables cached: the campaign's 16 s build was accepted."""
    monkeypatch.setattr(portrait, "release_tables", no_work_stub)
    monkeypatch.setattr(maps.SlowMap, "__post_init__", no_work_stub)
    status = main(["portrait", "--Theta", "0.5:2.5:2", "--p", "-0.1:0.1:2", "--t-end", "150", "--budget", "1",
                   "--out", str(tmp_path / "out"), "--quiet"])
    err = capsys.readouterr().err
    assert status != 0
    assert "the portrait (1 release, 0 region and 1 second-order tables to build" in err
    assert "horizon probes" in err and "would take about" in err and "--budget SECONDS" in err
    assert not (tmp_path / "out").exists()


def test_the_estimate_counts_the_tables_not_cached(tmp_path, monkeypatch):
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path / "empty"))
    cold = [portrait_seconds(BODY, TH, 90, 2000.0, order=k)[0] for k in (1, 2)]
    _warm(tmp_path, monkeypatch)
    warm = [portrait_seconds(BODY, TH, 90, 2000.0, order=k)[0] for k in (1, 2)]
    assert cold[0] - warm[0] == pytest.approx(RELEASE_TABLE_SECONDS)
    assert cold[1] - warm[1] == pytest.approx(RELEASE_TABLE_SECONDS + SECOND_ORDER_TABLE_SECONDS)


def test_the_estimate_counts_the_chaos_layer_and_the_horizon_probes(tmp_path, monkeypatch):
    _warm(tmp_path, monkeypatch)
    plain = portrait_seconds(BODY, TH, 400, 5000.0, chaos=False)[0]
    chaos = portrait_seconds(BODY, TH, 400, 5000.0, chaos=True)[0]
    probes = portrait_seconds(BODY, TH, 400, 5000.0, chaos=True, horizons=True)[0]
    assert plain < chaos < probes
    monkeypatch.setattr(portrait, "release_tables", no_work_stub)  # the check passed: the work would start
    budget = 0.5 * (plain + chaos)
    with pytest.raises(AssertionError, match="work started"):
        slow_portrait(BODY, TH, [0.5] * 40, [0.0] * 10, 5000.0, chaos=False, budget=budget)
    with pytest.raises(WorkBudgetError, match="with their tangent vectors"):
        slow_portrait(BODY, TH, [0.5] * 40, [0.0] * 10, 5000.0, chaos=True, budget=budget)
