"""The helpers researchers asked for in ``rr`` (issue 25, item 13): the critical-line diagram, whose legend a plain
``savefig`` kept, and the direct-ODE check of a slow prediction behind ``rocknroller slow --check``."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg

import rocknroller as rr
from rocknroller.papers.averaging_check import ode_slow_summary, relative_errors, sample_errors

BODY = rr.Body.paper(1e-3)


def _legends_inside(fig) -> list[bool]:
    FigureCanvasAgg(fig).draw()
    renderer, box = fig.canvas.get_renderer(), fig.bbox
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None] + list(fig.legends)
    assert legends
    return [box.x0 <= e.x0 and box.y0 <= e.y0 and e.x1 <= box.x1 and e.y1 <= box.y1
            for e in (leg.get_window_extent(renderer) for leg in legends)]


@pytest.mark.parametrize("with_orbit", [False, True])
def test_region_diagram_keeps_its_legend_inside_the_figure(with_orbit, tmp_path):
    """With an orbit the legend hung below the figure (y0 = -60 px): ``fig.savefig(path)`` without
    ``bbox_inches="tight"`` cut it off.  Both layouts now hold it inside the figure."""
    start = rr.critical_start(BODY, 0.95 * math.pi, math.pi / 4, "pi", psi_dot0=0.002)
    traj = rr.simulate(BODY, start.state(), 60.0) if with_orbit else None
    fig, data = rr.region_diagram(BODY, traj=traj)
    assert isinstance(data, rr.DiagramData) and all(_legends_inside(fig))
    fig.savefig(tmp_path / "diagram.png")


@pytest.mark.parametrize("kind", ["release", "state"])
def test_check_prediction_is_the_cli_check(kind):
    """``rr.check_prediction`` runs the direct ODE from the prediction's own start over its span and compares, as
    ``slow --check`` does (the same functions: the observables relative to the ODE's, the samples maximum by
    maximum)."""
    if kind == "release":
        pred = rr.predict_slow_motion(BODY, 0.95 * math.pi, math.pi / 4, 300.0, order=1)
        ode = ode_slow_summary(BODY, 0.95 * math.pi, math.pi / 4, 300.0)
    else:
        start = dataclasses.replace(rr.EulerState(0.95 * math.pi, 0.0, math.pi / 4), theta_dot=1e-3)
        from rocknroller.analysis.slow.map.family import first_maximum
        from rocknroller.analysis.slow.map.region import load_or_build_region_table

        with pytest.warns(rr.analysis.slow.map.limits.AveragingValidityWarning):  # a coarse table, to be quick
            table = load_or_build_region_table(BODY, first_maximum(BODY, start).E, nu=16, nv=8)
            pred = rr.predict_slow_motion(BODY, start, t_end=300.0, order=1, table=table)
        ode = ode_slow_summary(BODY, start, None, 300.0)
    check = rr.check_prediction(BODY, pred)
    assert isinstance(check, rr.PredictionCheck) and check.prediction is pred
    np.testing.assert_array_equal(check.ode.t, ode.t)
    np.testing.assert_array_equal(check.ode.QR, ode.QR)
    assert check.rel_errors == relative_errors(pred, ode)
    assert check.sample_errors == sample_errors(pred.series, ode)
    if kind == "release":  # first order at ε = 1e-3: every observable within a few ε of the ODE's
        assert all(abs(v) < 10 * BODY.epsilon for k, v in check.rel_errors.items()
                   if v is not None and k != "line_slope")


def test_check_prediction_of_pure_rocking_and_a_wrong_body():
    pred = rr.predict_slow_motion(rr.Body.paper(0.0), 0.95 * math.pi, 0.3, 50.0, order=1)
    check = rr.check_prediction(rr.Body.paper(0.0), pred)
    assert set(check.rel_errors.values()) == {None} and check.sample_errors is None
    with pytest.raises(ValueError, match="the prediction is for eps=0.0"):
        rr.check_prediction(BODY, pred)
