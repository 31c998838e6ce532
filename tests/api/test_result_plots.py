"""The result types' quick looks: ``plot()`` draws what its docstring says, inside its figure (issue 32, items 12
and 14), and ``to_dataframe()`` holds the result's numbers."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
import pytest

import rocknroller as rr
from figure_checks import draw, inside, legend_texts, overlapping, tick_labels


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
    assert len(panels) == len(STATISTICS) and all(ax.patches for ax in panels) and _labels_inside(fig)
    fig = cmp.plot()
    fig.savefig(tmp_path / "comparison.png")
    panels = [ax for ax in fig.axes if ax.get_visible()]
    assert len(panels) == len(STATISTICS) and all(len(ax.patches) == 2 for ax in panels) and _labels_inside(fig)
    assert all(("NOT consistent" in ax.get_title()) != cmp[n].consistent for ax, n in zip(panels, STATISTICS))


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
        np.testing.assert_array_equal(ax.get_lines()[0].get_xdata(), atlas.cols / math.pi)
        np.testing.assert_array_equal(ax.get_lines()[0].get_ydata(), np.ma.ravel(atlas.values[name]).filled(np.nan))


def test_every_frame_says_pandas_is_missing(results, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "pandas", None)
    for name in ("statistics", "comparison", "run", "chaos", "orbit", "branch", "portrait", "atlas"):
        with pytest.raises(ImportError, match="pip install pandas"):
            results[name].to_dataframe()
