"""The bifurcation diagram writes its figure and its table (issue 23, item 4)."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.papers.bifurcation import bifurcation_data, bifurcation_diagram

THETA0 = 0.95 * math.pi


def test_diagram_writes_png_pdf_csv(tmp_path):
    """PNG, PDF and CSV; the CSV's header records the body, θ0 and ε_pd, its rows hold both maps' orbits; the slow
    map's fixed point is stable below ε_pd and unstable above it, the period-2 branch starts just above it."""
    paths, (d,) = bifurcation_diagram(Body.paper(0.0), tmp_path, [THETA0], n_points=9, exact_fractions=(1.2,))
    assert sorted(p.name for p in paths) == ["bifurcation.csv", "bifurcation.pdf", "bifurcation.png"]
    assert all(p.stat().st_size > 1000 for p in paths)
    text = (tmp_path / "bifurcation.csv").read_text()
    assert "a=0.05" in text and "theta0: 0.95pi" in text and repr(d.eps_pd) in text
    rows = list(csv.DictReader(ln for ln in text.splitlines() if not ln.startswith("#")))
    assert {"slow", "exact"} == {r["map"] for r in rows}
    assert len(rows) == 9 + 9 + 2 * len(d.period2.orbits) + 1 + 2 + 2  # one row per point of every orbit
    fixed = d.fixed
    assert np.all(fixed.stable == (fixed.eps < d.eps_pd))  # ε_pd of the slow map is within 2e-4 of the exact one
    assert d.period2.eps[0] > d.eps_pd and np.all(d.period2.stable)
    (e,), (s,) = d.exact_period2, d.slow_period2
    assert e.eps == s.eps == pytest.approx(1.2 * d.eps_pd) and e.stable and s.stable


def test_bad_input():
    with pytest.raises(ValueError, match="n_points"):
        bifurcation_data(Body.paper(0.0), THETA0, n_points=2)
    with pytest.raises(ValueError, match="theta0"):
        bifurcation_data(Body.paper(0.0), 0.5 * math.pi)


def test_figure_has_a_legend_inside_it(tmp_path):
    """The legend names the three branches (stable-axis rocking, unstable-axis rocking, the period-2 orbit) and the
    line and marker styles, in the colours they are drawn in, and lies inside the figure."""
    from matplotlib.lines import Line2D

    from figure_checks import inside, legend_texts, legends
    from rocknroller.papers.bifurcation import bifurcation_figure

    d = bifurcation_data(Body.paper(0.0), THETA0, n_points=9, exact_fractions=(1.2,))
    fig = bifurcation_figure([d])
    fig.savefig(tmp_path / "bifurcation.png")
    texts = " | ".join(legend_texts(fig))
    for words in ("stable axis", "unstable axis", "period-2", "exact map", "slow map"):
        assert words in texts
    assert all(inside(fig, leg) for leg in legends(fig))
    (leg,) = legends(fig)
    drawn = {line.get_color() for ax in fig.axes for line in ax.get_lines() if line.get_linestyle() != "None"}
    named = {h.get_color() for h, t in zip(leg.legend_handles, leg.get_texts()) if "orbit" in t.get_text()
             or "axis" in t.get_text()}
    assert named == {"C0", "C1", "C2"} and named <= drawn
    assert all(isinstance(h, Line2D) for h in leg.legend_handles)


def test_the_release_tables_of_all_theta0_are_built_at_once(tmp_path, monkeypatch):
    """bifurcation_diagram hands the release tables of all its θ0 to one build_release_tables call on the scheduler
    asked for (threads here), and the diagram's table is the same, byte for byte, as without it."""
    from rocknroller.papers import bifurcation as bif

    calls, real = [], bif.build_release_tables

    def spy(body, theta0, **kw):
        calls.append((list(theta0), kw))
        return real(body, theta0, **kw)

    monkeypatch.setattr(bif, "build_release_tables", spy)
    monkeypatch.setattr(bif, "energy_tables_cached", lambda body: False)  # else no release table is built
    angles = [0.9 * math.pi, THETA0]
    opts = dict(n_points=5, exact_fractions=())
    bifurcation_diagram(Body.paper(0.0), tmp_path / "loop", angles, **opts)
    bifurcation_diagram(Body.paper(0.0), tmp_path / "threads", angles, threads=2, **opts)
    assert [c[0] for c in calls] == [angles, angles]
    assert calls[0][1]["processes"] == 1 and calls[1][1]["threads"] == 2
    assert (tmp_path / "loop" / "bifurcation.csv").read_bytes() == (tmp_path / "threads" / "bifurcation.csv").read_bytes()
    with pytest.raises(ValueError, match="threads must be"):
        bifurcation_diagram(Body.paper(0.0), tmp_path, angles, threads=0, **opts)
