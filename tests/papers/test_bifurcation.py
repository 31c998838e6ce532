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
