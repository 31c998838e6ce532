"""The result types' quick looks: ``plot()`` draws what its docstring says, inside its figure (issue 32, items 12
and 14), and ``to_dataframe()`` holds the result's numbers."""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import rocknroller as rr  # noqa: E402
from figure_checks import draw, inside, legend_texts, overlapping, tick_labels  # noqa: E402


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
    fig = pred.plot()
    ax = fig.axes[0]
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


def test_slow_prediction_plot_has_the_commands_title_and_marks_its_horizon():
    """A chaotic release (ε = 5e-3, ψ0 = 0.05, horizon ≈ 140 t.u. < t_end = 400), as ``rocknroller slow --plot``
    draws it: the title names the body, ε, θ0, ψ0 and the map's order; the ψ panel has a labelled vertical line at
    the horizon and the span past it shaded, both in its legend, and labelled axes with units; a regular release
    over a t_end before its horizon names the horizon in the legend only."""
    body = rr.Body.paper(5e-3)
    pred = rr.predict_slow_motion(body, 0.95 * math.pi, 0.05, 400.0, order=1)
    t_h = pred.horizon()
    assert 0.0 < t_h < 400.0
    fig = pred.plot()
    title = fig.get_suptitle()
    assert all(part in title for part in ("order 1", "ε = 0.005", "θ0 = 0.95π", "ψ0 = 0.01592π", body.describe()))
    ax_q, ax_t = fig.axes[:2]
    marks = [line for line in ax_t.get_lines() if list(line.get_xdata()) == [t_h, t_h]]
    assert len(marks) == 1 and marks[0].get_label() == f"predictability horizon t = {t_h:.4g}"
    (span,) = ax_t.patches
    assert (span.get_x(), span.get_x() + span.get_width()) == pytest.approx((t_h, 400.0), rel=1e-12)
    assert {"predictability horizon t = " + f"{t_h:.4g}", "past it: statistical only"} <= set(legend_texts(fig))
    assert ax_t.get_xlabel() == "t (time units)" and ax_t.get_ylabel() == "$\\psi$ mod $\\pi$ at the maxima (rad)"
    assert {line.get_gid() for line in ax_q.get_lines()} >= {"QJ0crit", "QJpicrit"} and _labels_inside(fig)
    regular = rr.predict_slow_motion(rr.Body.paper(1e-3), 0.95 * math.pi, math.pi / 4, 200.0, order=1)
    t_r = regular.horizon()
    ax_r = regular.plot().axes[1]
    assert t_r > 200.0 and not ax_r.patches
    assert f"predictability horizon t = {t_r:.4g} (after t_end)" in [t.get_text() for t in ax_r.get_legend().get_texts()]


BODY = rr.Body.paper(1e-3)
THETA0 = 0.95 * math.pi


@pytest.fixture(scope="module")
def results():
    """One small result of each of the eight types (a few seconds together on warm caches)."""
    ball = rr.StartBall(THETA0, 0.4, 0.05, 4, seed=1)
    a, b = rr.map_ensemble(BODY, ball, 300.0, order=1), rr.ode_ensemble(BODY, ball, 300.0, progress=False)
    runs = rr.run_ensemble([rr.Job(BODY, rr.EulerState(THETA0, psi=p), 300.0) for p in (0.1, 0.7)], progress=False)
    branch = rr.continue_orbit(rr.Body.paper(0.0), THETA0, np.linspace(5e-3, 1.2e-2, 4), 1)
    return dict(
        statistics=a, comparison=rr.compare_ensembles(a, b), run=runs[0], runs=runs,
        chaos=rr.direct_chaos_indicators(BODY, rr.EulerState(THETA0, psi=0.4), 300.0),
        orbit=branch.orbits[-1], branch=branch,
        portrait=rr.slow_portrait(rr.Body.paper(5e-3), THETA0, [0.1, 3.0], [0.0, 0.5], 300.0, ode_starts=[(0.1, 0.0)],
                                  progress=False),
        atlas=rr.atlas_from_rest(BODY, [THETA0], [0.1 * math.pi, 0.25 * math.pi, 0.4 * math.pi], 300.0,
                                 progress=False))


def _labels_inside(fig) -> bool:
    """Every title and axis label inside the figure, and no two tick labels of an axis overlapping."""
    shown, renderer = [ax for ax in fig.axes if ax.get_visible()], draw(fig)
    return (all(inside(fig, t, renderer) for ax in shown for t in (ax.title, ax.xaxis.label, ax.yaxis.label)
                if t.get_text())
            and not any(overlapping(fig, tick_labels(axis), renderer) for ax in shown for axis in (ax.xaxis, ax.yaxis)))


def test_run_summary_frame_plot_and_region_fractions(results, tmp_path):
    """A run_ensemble summary: its maxima as a frame, its (Q_R, Q_J) and φ plots; rr.region_fractions of its maxima is
    the fraction of rr.region's labels, and agrees with the ensembles' own count (member_statistics, by the crossings
    of the lines)."""
    from rocknroller.analysis.slow.ensemble_statistics import member_statistics

    run = results["run"]
    frame = run.to_dataframe()
    assert list(frame.columns) == ["t", "theta", "phi", "psi", "Q_R", "Q_J"] and len(frame) == run.n_maxima
    np.testing.assert_array_equal(frame["Q_J"].to_numpy(), run.maxima.QJ)
    ax = run.plot()
    np.testing.assert_array_equal(ax.get_lines()[0].get_xdata(), run.maxima.QR)
    assert run.plot(kind="phi").get_lines()[0].get_xdata().size == run.n_maxima
    with pytest.raises(ValueError, match="kind must be one of"):
        run.plot(kind="track")
    for r in results["runs"]:
        fractions = rr.region_fractions(r.maxima.QR, r.maxima.QJ, BODY)
        labels = rr.region(r.maxima.QR, r.maxima.QJ, BODY)
        assert fractions == {lab: np.count_nonzero(labels == lab) / labels.size for lab in fractions}
        assert sum(fractions.values()) == pytest.approx(1.0, abs=1e-15) and len(fractions) == 7
        by_crossings = member_statistics(BODY, r.maxima.t, r.maxima.QR, r.maxima.QJ, 300.0)
        assert {k: fractions[k] for k in ("I", "II", "III", "IV")} == {
            k: by_crossings[f"fraction_{k}"] for k in ("I", "II", "III", "IV")}
    assert any(0.0 < v < 1.0 for r in results["runs"] for v in rr.region_fractions(r.maxima.QR, r.maxima.QJ,
                                                                                        BODY).values())
    with pytest.raises(ValueError, match="QR and QJ"):
        rr.region_fractions([], [], BODY)


def test_direct_chaos_frame_and_plot(results):
    """The samples at the maxima as a frame; the plot is the running MEGNO with the line 3."""
    ch = results["chaos"]
    frame = ch.to_dataframe()
    assert list(frame.columns) == ["t", "theta", "log_growth", "mean_megno"] and len(frame) == ch.t_maxima.size
    np.testing.assert_array_equal(frame["mean_megno"].to_numpy(), ch.indicators.mean_megno)
    ax = ch.plot()
    megno, line = ax.get_lines()
    np.testing.assert_array_equal(megno.get_ydata(), ch.indicators.mean_megno)
    assert list(line.get_ydata()) == [3.0, 3.0] and _labels_inside(ax.figure)


def test_ensemble_statistics_and_comparison_frames_and_plots(results, tmp_path):
    """Members as rows (ψ0, rocks, the eight statistics); the comparison one row per statistic; the plots one
    histogram panel per statistic (both ensembles in the comparison's), every title and label inside the figure."""
    from rocknroller.analysis.slow.ensemble_statistics import STATISTICS

    a, cmp = results["statistics"], results["comparison"]
    frame = a.to_dataframe()
    assert list(frame.columns) == ["psi0", "rocks", *STATISTICS] and len(frame) == 4
    np.testing.assert_array_equal(frame["psi0"].to_numpy(), a.ball.psi0_values())
    np.testing.assert_array_equal(frame["QR_extent"].to_numpy(), a.values["QR_extent"])
    table = cmp.to_dataframe()
    assert list(table["name"]) == list(STATISTICS)
    assert table["consistent"].tolist() == [cmp[n].consistent for n in STATISTICS]
    fig = a.plot()
    fig.savefig(tmp_path / "statistics.png")
    panels = [ax for ax in fig.axes if ax.get_visible()]
    drawn = [bool(np.any(a.values[n])) for n in STATISTICS]  # a statistic 0 for every member is not drawn
    assert len(panels) == len(STATISTICS) and [bool(ax.patches) for ax in panels] == drawn and _labels_inside(fig)
    fig = cmp.plot()
    fig.savefig(tmp_path / "comparison.png")
    panels = [ax for ax in fig.axes if ax.get_visible()]
    drawn = [bool(np.any(a.values[n]) or np.any(cmp.b.values[n])) for n in STATISTICS]
    assert len(panels) == len(STATISTICS) and _labels_inside(fig)
    assert [len(ax.patches) for ax in panels] == [2 if d else 0 for d in drawn]
    assert all(("NOT consistent" in ax.get_title()) != cmp[n].consistent for ax, n in zip(panels, STATISTICS))


def test_ensemble_statistics_plot_labels_its_axes_with_units_and_draws_no_bar_for_zero():
    """A ball whose rocks never enter regions II and IV (fractions 0 for every member) and whose members all reverse
    as often: the zero fractions draw nothing but say "none" (they were drawn as a bar across the whole axis), the
    fractions lie on [0, 1], the constant reversal count is a narrow bar, every x axis is labelled in words with its
    unit (reversals per 1000 time units, ``STATISTIC_UNITS``)."""
    from rocknroller.analysis.slow.ensemble_statistics import STATISTIC_UNITS, STATISTICS

    ens = rr.map_ensemble(BODY, rr.StartBall(THETA0, math.pi / 4, 0.1, 8, seed=1), 300.0, order=1)
    zero = [n for n in STATISTICS if not np.any(ens.values[n])]
    assert {"fraction_II", "fraction_IV"} <= set(zero) and np.ptp(ens.values["full_reversals"]) == 0
    fig = ens.plot()
    panels = dict(zip(STATISTICS, [ax for ax in fig.axes if ax.get_visible()]))
    for name in zero:
        assert not panels[name].patches and [t.get_text() for t in panels[name].texts] == ["none: 0 for every member"]
    for name in STATISTICS:
        ax = panels[name]
        assert ax.get_xlabel() and ax.get_ylabel() == "members"
        if name.startswith("fraction_"):
            assert ax.get_xlim() == (0.0, 1.0) and ax.get_xlabel() == f"fraction of the rocks in region {name[9:]}"
    assert panels["full_reversals"].get_xlabel() == f"full-angle reversals ({STATISTIC_UNITS['full_reversals']})"
    assert STATISTIC_UNITS["visible_reversals"] in panels["visible_reversals"].get_xlabel()
    (bar,) = panels["full_reversals"].patches
    lo, hi = panels["full_reversals"].get_xlim()
    assert bar.get_window_extent().width < 0.2 * panels["full_reversals"].get_window_extent().width and lo < hi
    assert _labels_inside(fig)


def test_periodic_orbit_and_branch_frames_and_plots(results):
    """One row per point (per orbit, in the order of ε); the branch's residue and kick phase drawn against ε."""
    orbit, branch = results["orbit"], results["branch"]
    frame = orbit.to_dataframe()
    assert len(frame) == orbit.period and frame["residue"].tolist() == [orbit.residue] * orbit.period
    np.testing.assert_array_equal(frame["kick_phase"].to_numpy(), orbit.kick_phase)
    table = branch.to_dataframe()
    assert len(table) == sum(o.period for o in branch.orbits)
    np.testing.assert_array_equal(table["eps"].to_numpy(), branch.eps)
    ax = branch.plot(kind="residue")
    x = np.concatenate([line.get_xdata()[:-1] for line in ax.get_lines()] + [ax.get_lines()[-1].get_xdata()[-1:]])
    y = np.concatenate([line.get_ydata()[:-1] for line in ax.get_lines()] + [ax.get_lines()[-1].get_ydata()[-1:]])
    np.testing.assert_array_equal(x, branch.eps)
    np.testing.assert_array_equal(y, branch.residue)
    assert {line.get_linestyle() for line in ax.get_lines()} == ({"-", "--"} if len(set(branch.stable)) == 2
                                                                  else {"-" if branch.stable[0] else "--"})
    with pytest.raises(ValueError, match="kind must be one of"):
        branch.plot(kind="phase")
    ax = orbit.plot()
    np.testing.assert_array_equal(ax.get_lines()[0].get_xdata(), orbit.Q[:, 0])


def test_portrait_frame_and_plot(results):
    """The map's maxima, then the ODE's, with the CSV's columns; MEGNO missing for the ODE."""
    P = results["portrait"]
    frame = P.to_dataframe()
    n_map, n_ode = sum(s.t.size for s in P.orbits), sum(len(m) for m in P.ode)
    assert len(frame) == n_map + n_ode and list(frame["source"].unique()) == ["map", "ode"]
    assert list(frame.columns) == ["source", "orbit", "Theta0", "p0", "megno", "t", "Theta", "p", "Q_R", "Q_J"]
    np.testing.assert_array_equal(frame["Q_R"].to_numpy()[:n_map], np.concatenate([s.QR for s in P.orbits]))
    first = frame[frame["orbit"] == 0].iloc[0]
    assert first["megno"] == P.megno[0] and frame["megno"][n_map:].isna().all()
    fig = P.plot()
    assert len(fig.axes) == 3 and fig.axes[-1].get_ylabel().startswith("MEGNO")


def test_atlas_frame_and_plot(results, tmp_path):
    """One row per grid point (θ0, ψ0, the observables); the one-θ0 atlas's quick look draws lines along ψ0."""
    from rocknroller.numerics.megno import MEGNO_CLIP

    atlas = results["atlas"]
    frame = atlas.to_dataframe()
    assert list(frame.columns) == ["theta0", "psi0", *atlas.observables] and len(frame) == 3
    np.testing.assert_array_equal(frame["psi0"].to_numpy(), atlas.cols)
    np.testing.assert_array_equal(frame["Phi"].to_numpy(), np.ma.ravel(atlas.values["Phi"]))
    fig = atlas.plot()
    fig.savefig(tmp_path / "atlas.png")
    panels = [ax for ax in fig.axes if ax.get_visible()]
    assert len(panels) == len(atlas.observables) and _labels_inside(fig)
    for ax, name in zip(panels, atlas.observables):
        y = np.ma.ravel(atlas.values[name])
        y = np.ma.minimum(y, MEGNO_CLIP) if name == "megno" else y  # MEGNO on the fixed scale, as the command's
        np.testing.assert_array_equal(ax.get_lines()[0].get_xdata(), atlas.cols / math.pi)
        np.testing.assert_array_equal(ax.get_lines()[0].get_ydata(), y.filled(np.nan))


def test_every_frame_says_pandas_is_missing(results, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "pandas", None)
    for name in ("statistics", "comparison", "run", "chaos", "orbit", "branch", "portrait", "atlas"):
        with pytest.raises(ImportError, match="pip install pandas"):
            results[name].to_dataframe()
