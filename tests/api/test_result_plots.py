"""The result types' quick looks: ``plot()`` draws what its docstring says, inside its figure (issue 32, items 12
and 14), and ``to_dataframe()`` holds the result's numbers."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
import pytest

import rocknroller as rr
from figure_checks import inside, legend_texts


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def test_slow_prediction_plot_draws_the_critical_lines_and_keeps_its_labels(tmp_path):
    """The docstring's critical lines are drawn (gids of :func:`draw_critical_lines`, the body's own lines), the axes
    keep the samples' range, and without axes the new figure holds both axis labels whole (the y-label was cut off at
    the left edge)."""
    body = rr.Body.paper(1e-3)
    pred = rr.predict_slow_motion(body, 0.95 * math.pi, math.pi / 4, 400.0, order=1)
    ax = pred.plot()
    fig = ax.figure
    fig.savefig(tmp_path / "prediction.png")
    lines = {line.get_gid(): line for line in ax.get_lines() if line.get_gid()}
    assert set(lines) == {"QJ0crit", "QJpicrit"}
    x = lines["QJ0crit"].get_xdata()
    np.testing.assert_array_equal(lines["QJ0crit"].get_ydata(), rr.QJ_crit_0(x, body.symmetric()))
    np.testing.assert_array_equal(lines["QJpicrit"].get_ydata(), rr.QJ_crit_pi(x, body.symmetric()))
    lo, hi = ax.get_xlim()
    assert lo <= pred.series.QR.min() and pred.series.QR.max() <= hi and hi - lo < 2 * np.ptp(pred.series.QR)
    assert inside(fig, ax.yaxis.label) and inside(fig, ax.xaxis.label)
    assert any("crit" in t for t in legend_texts(fig))
