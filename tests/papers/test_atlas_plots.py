"""The atlas figure: a plane of starts as heat maps, a one-θ0 atlas as lines along ψ0 (issue 32, item 10)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from matplotlib.collections import QuadMesh

from figure_checks import draw
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.atlas import atlas_from_rest
from rocknroller.papers.atlas_plots import LABELS, atlas_figure

BODY = Body.paper(1e-3)
PSI0 = np.linspace(0.05, 0.5, 10) * math.pi


@pytest.fixture(scope="module")
def line_atlas():
    return atlas_from_rest(BODY, [0.95 * math.pi], PSI0, 400.0, progress=False)


def test_one_theta0_atlas_is_drawn_as_lines_along_psi0(line_atlas, tmp_path):
    """No heat map over an invented θ0 range: every panel is a line over the ψ0 of the atlas, with its values (the
    masked ones left out), ψ0 along x, and θ0 = 0.95π in the title."""
    fig = atlas_figure(line_atlas, "one release angle")
    fig.savefig(tmp_path / "atlas.png")
    draw(fig)
    panels = {ax.get_title(): ax for ax in fig.axes if ax.get_title()}
    assert set(panels) == {LABELS[n] for n in line_atlas.observables}
    assert "0.95π" in fig.get_suptitle()
    for name in line_atlas.observables:
        ax = panels[LABELS[name]]
        assert not [c for c in ax.collections if isinstance(c, QuadMesh)]
        assert ax.get_xlabel() == "$\\psi_0/\\pi$" and "theta" not in ax.get_ylabel()
        lo, hi = ax.get_xlim()
        x0, x1 = PSI0[0] / math.pi, PSI0[-1] / math.pi
        assert lo < x0 and x1 < hi and hi - lo < 1.1 * (x1 - x0)
        line = ax.get_lines()[0]
        y = np.ma.ravel(line_atlas.values[name])
        if name == "megno":
            y = np.ma.minimum(y, 5.0)
        np.testing.assert_array_equal(line.get_xdata(), PSI0 / math.pi)
        np.testing.assert_array_equal(line.get_ydata(), y.filled(np.nan))


def test_a_plane_is_still_drawn_as_heat_maps(line_atlas):
    """Two θ0 rows: heat maps over the plane."""
    plane = atlas_from_rest(BODY, [0.9 * math.pi, 0.95 * math.pi], PSI0[:3], 400.0, progress=False)
    fig = atlas_figure(plane, "plane")
    assert all(any(isinstance(c, QuadMesh) for c in ax.collections) for ax in fig.axes if ax.get_title() in
               {LABELS[n] for n in plane.observables})


def test_one_theta0_check_is_drawn_along_psi0(line_atlas, tmp_path):
    """The ODE's check of a one-θ0 atlas: the largest error at each confirmed ψ0 on a log scale, not points over an
    invented θ0 range."""
    from rocknroller.analysis.slow.atlas_check import confirm_atlas
    from rocknroller.papers.atlas_plots import atlas_check_figure

    check = confirm_atlas(line_atlas, BODY, every=3, progress=False)
    fig = atlas_check_figure(line_atlas, check, "check")
    fig.savefig(tmp_path / "atlas_check.png")
    (ax,) = fig.axes
    assert ax.get_yscale() == "log" and ax.get_xlabel() == "$\\psi_0/\\pi$" and "0.95π" in ax.get_title()
    line = ax.get_lines()[0]
    np.testing.assert_array_equal(line.get_xdata(), PSI0[check.index[:, 1]] / math.pi)
    worst = np.ma.max(np.ma.vstack([np.ma.abs(check.rel_error[n]) for n in ("slow_period", "Phi", "QR_extent",
                                                                              "QJ_extent")]), axis=0)
    np.testing.assert_array_equal(line.get_ydata(), worst.filled(np.nan))
