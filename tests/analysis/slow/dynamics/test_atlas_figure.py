"""The atlas figure, ``Atlas.plot()``'s and ``rocknroller atlas``'s: a plane of starts as heat maps, a one-θ0 atlas as
lines along ψ0 (issue 32, item 10); titles in words, colour bars (or y axes) labelled with units, MEGNO on the fixed
scale [0, MEGNO_CLIP]."""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.collections import QuadMesh  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from figure_checks import draw  # noqa: E402
from rocknroller.analysis.model.body import Body  # noqa: E402
from rocknroller.analysis.slow.atlas import atlas_from_rest  # noqa: E402
from rocknroller.analysis.slow.dynamics.atlas_figure import (TITLES, UNIT_LABELS, atlas_check_figure,  # noqa: E402
                                                             atlas_figsize, atlas_figure)
from rocknroller.numerics.megno import MEGNO_CLIP  # noqa: E402

BODY = Body.paper(1e-3)
PSI0 = np.linspace(0.05, 0.5, 10) * math.pi


@pytest.fixture(scope="module")
def line_atlas():
    return atlas_from_rest(BODY, [0.95 * math.pi], PSI0, 400.0, progress=False)


def test_one_theta0_atlas_is_drawn_as_lines_along_psi0(line_atlas, tmp_path):
    """No heat map over an invented θ0 range: every panel is a line over the ψ0 of the atlas, with its values (the
    masked ones left out), ψ0 along x, and θ0 = 0.95π in the title."""
    fig = atlas_figure(line_atlas, Figure(figsize=atlas_figsize(line_atlas), layout="constrained"),
                       "one release angle")
    fig.savefig(tmp_path / "atlas.png")
    draw(fig)
    panels = {ax.get_title(): ax for ax in fig.axes if ax.get_title()}
    assert set(panels) == {TITLES[n] for n in line_atlas.observables}
    assert "0.95π" in fig.get_suptitle()
    for name in line_atlas.observables:
        ax = panels[TITLES[name]]
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
    fig = atlas_figure(plane, Figure(), "plane")
    assert all(any(isinstance(c, QuadMesh) for c in ax.collections) for ax in fig.axes if ax.get_title() in
               {TITLES[n] for n in plane.observables})


def test_one_theta0_check_is_drawn_along_psi0(line_atlas, tmp_path):
    """The ODE's check of a one-θ0 atlas: the largest error at each confirmed ψ0 on a log scale, not points over an
    invented θ0 range."""
    from rocknroller.analysis.slow.atlas_check import confirm_atlas

    check = confirm_atlas(line_atlas, BODY, every=3, progress=False)
    fig = atlas_check_figure(line_atlas, check, "check", Figure(layout="constrained"))
    fig.savefig(tmp_path / "atlas_check.png")
    (ax,) = fig.axes
    assert ax.get_yscale() == "log" and ax.get_xlabel() == "$\\psi_0/\\pi$" and "0.95π" in ax.get_title()
    line = ax.get_lines()[0]
    np.testing.assert_array_equal(line.get_xdata(), PSI0[check.index[:, 1]] / math.pi)
    worst = np.ma.max(np.ma.vstack([np.ma.abs(check.rel_error[n]) for n in ("slow_period", "Phi", "QR_extent",
                                                                              "QJ_extent")]), axis=0)
    np.testing.assert_array_equal(line.get_ydata(), worst.filled(np.nan))


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _meshes(fig):
    """Each titled panel's heat map, by title."""
    return {ax.get_title(): next(c for c in ax.collections if isinstance(c, QuadMesh)) for ax in fig.axes
            if ax.get_title()}


def test_the_api_plot_of_a_plane_has_titles_in_words_labelled_colour_bars_and_megno_on_a_fixed_scale():
    """``Atlas.plot()`` (the quick look showed the code names as titles, unlabelled colour bars and MEGNO
    auto-scaled, so that regular starts, MEGNO ≈ 2, looked hottest): every panel titled in words, its colour bar
    labelled with its unit, MEGNO's colours on [0, MEGNO_CLIP] whatever the values, every label inside the figure."""
    from figure_checks import inside

    plane = atlas_from_rest(BODY, [0.9 * math.pi, 0.95 * math.pi], PSI0[:3], 400.0, progress=False)
    assert "megno" in plane.observables and float(np.ma.max(plane.values["megno"])) < 3.0  # all regular
    fig = plane.plot()
    meshes = _meshes(fig)
    assert set(meshes) == {TITLES[n] for n in plane.observables}
    for name in plane.observables:
        assert meshes[TITLES[name]].colorbar.ax.get_ylabel() == UNIT_LABELS[name]
    assert meshes[TITLES["megno"]].get_clim() == (0.0, MEGNO_CLIP)
    assert UNIT_LABELS["full_reversals"] == "per 1000 time units"
    renderer = draw(fig)
    assert all(inside(fig, t, renderer) for ax in fig.axes for t in (ax.title, ax.xaxis.label, ax.yaxis.label)
               if t.get_text())


def test_the_api_plot_of_a_line_labels_its_y_axes_with_units(line_atlas):
    """A one-θ0 atlas by ``Atlas.plot()``: the command's panels, each y axis labelled with the observable's unit,
    MEGNO on the fixed range [0, 1.08 MEGNO_CLIP] with the line MEGNO = 3."""
    fig = line_atlas.plot()
    panels = {ax.get_title(): ax for ax in fig.axes if ax.get_title()}
    assert set(panels) == {TITLES[n] for n in line_atlas.observables}
    for name in line_atlas.observables:
        assert panels[TITLES[name]].get_ylabel() == UNIT_LABELS[name]
    megno = panels[TITLES["megno"]]
    assert megno.get_ylim() == pytest.approx((0.0, 1.08 * MEGNO_CLIP))
    assert any(list(line.get_ydata()) == [3.0, 3.0] for line in megno.get_lines())
