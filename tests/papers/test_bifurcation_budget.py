"""The work of a bifurcation diagram (``bifurcation_diagram``, ``rocknroller bifurcation``) estimated before any of
it: the release and second-order tables not cached, ε_pd, the orbits; ``--budget 1`` refused before any table is
built (the campaign's refused only after 13.9 s)."""

from __future__ import annotations

import math

import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map import second_order, table, tables_at_once
from rocknroller.analysis.slow.map.second_order import build_second_order_table
from rocknroller.analysis.slow.map.table import build_table
from rocknroller.cli import main
from rocknroller.numerics.budget import RELEASE_TABLE_SECONDS, SECOND_ORDER_TABLE_SECONDS, WorkBudgetError
from rocknroller.papers import bifurcation
from rocknroller.papers.bifurcation import bifurcation_diagram, bifurcation_seconds

from budget_checks import mark_cached, no_tables_in_memory  # noqa: F401 (an autouse fixture)
from budget_checks import no_work as no_work_stub

BODY = Body.paper()
TH = 0.95 * math.pi


@pytest.fixture
def no_work(monkeypatch):
    for module, name in ((table, "load_or_build_table"), (second_order, "load_or_build_second_order_table"),
                         (bifurcation, "build_release_tables"), (bifurcation, "period_doubling"),
                         (bifurcation, "continue_orbit"), (tables_at_once, "release_tables"),
                         (tables_at_once, "load_or_build_table")):
        monkeypatch.setattr(module, name, no_work_stub)


@pytest.mark.parametrize("order", ["1", "2"])
def test_budget_1_is_refused_before_any_table_is_built(tmp_path, monkeypatch, no_work, capsys, order):
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path / "empty"))
    status = main(["bifurcation", "--theta0", "0.95pi", "--order", order, "--budget", "1",
                   "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert status != 0 and "work started" not in err
    assert "a bifurcation diagram at 1 theta0 (per theta0 the exact map's eps_pd" in err
    assert "would take about" in err and "--budget SECONDS" in err
    assert not (tmp_path / "out").exists()


def test_the_api_counts_order_2_s_table_before_any_work(tmp_path, monkeypatch, no_work):
    """At order 2 the second-order table (~14 s to build) was not counted."""
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path / "empty"))
    budget = bifurcation_seconds(BODY, [TH], order=1) + 0.5 * SECOND_ORDER_TABLE_SECONDS
    with pytest.raises(WorkBudgetError, match="a bifurcation diagram at 1 theta0 .* of order 2"):
        bifurcation_diagram(BODY, tmp_path / "out", [TH], budget=budget, order=2)


def test_the_estimate_counts_the_second_order_table_not_cached(tmp_path, monkeypatch):
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path / "empty"))
    cold = [bifurcation_seconds(BODY, [TH], order=k) for k in (1, 2)]
    mark_cached(tmp_path / "warm", monkeypatch, BODY, [(build_table, TH), (build_second_order_table, TH)])
    warm = [bifurcation_seconds(BODY, [TH], order=k) for k in (1, 2)]
    assert warm[0] == warm[1] == bifurcation_seconds(BODY, [TH], build=False)
    assert cold[0] - warm[0] == pytest.approx(RELEASE_TABLE_SECONDS)
    assert cold[1] - warm[1] == pytest.approx(RELEASE_TABLE_SECONDS + SECOND_ORDER_TABLE_SECONDS)
