"""The recession atlas: the averaged map over a plane of releases, its ODE confirmation, files and errors."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.slow import atlas as at
from rocknroller.analysis.slow.atlas_check import confirm_atlas
from rocknroller.cli import main
from rocknroller.numerics.ensembles.ensemble import Job, run_ensemble

BODY = Body.paper(1e-3)
THETA0 = (0.9 * math.pi, 0.95 * math.pi)
PSI0 = (0.15 * math.pi, 0.25 * math.pi, 0.4 * math.pi)


@pytest.fixture(scope="module")
def small_atlas():
    return at.atlas_from_rest(BODY, THETA0, PSI0, 400.0, progress=False, order=1)  # whatever tables are cached


def test_atlas_values_are_the_maps(small_atlas):
    """Each point is predict_slow_motion's own diagnostics; the reversals count its crossings per 1000 t.u."""
    from rocknroller.analysis.slow.prediction import predict_slow_motion

    pred = predict_slow_motion(BODY, THETA0[1], PSI0[2], 400.0, order=1)  # the atlas's first-order map
    assert small_atlas.values["Phi"][1, 2] == pred.Phi and small_atlas.values["QR_extent"][1, 2] == pred.QR_extent
    full = sum("QJ0crit" in c[3] for c in pred.crossings) * 1000.0 / 400.0
    assert small_atlas.values["full_reversals"][1, 2] == full


def test_processes_do_not_change_the_atlas(small_atlas):
    two = at.atlas_from_rest(BODY, THETA0, PSI0, 400.0, progress=False, processes=2, order=1)
    for name in at.ATLAS_OBSERVABLES:
        assert np.array_equal(two.values[name].filled(np.nan), small_atlas.values[name].filled(np.nan),
                              equal_nan=True), name
    with pytest.raises(ValueError, match="processes must be"):
        at.atlas_from_rest(BODY, THETA0, PSI0, 400.0, processes=0)


def test_the_maps_tables_are_built_on_the_schedulers_all_rows_at_once(small_atlas, monkeypatch):
    """With threads (or workers, a scheduler) the map's atlas hands the release tables of all its rows (those on
    release tables: not the region tables' angles) to build_release_tables in one call, on that scheduler, and the
    atlas is the same bit for bit (the tables are: tests/analysis/slow/map/test_tables_at_once.py)."""
    from rocknroller.analysis.slow.map import tables_at_once

    calls, real = [], tables_at_once.build_release_tables

    def spy(body, theta0, **kw):
        calls.append((list(theta0), kw["threads"]))
        return real(body, theta0, **kw)

    monkeypatch.setattr(tables_at_once, "build_release_tables", spy)
    monkeypatch.setattr(tables_at_once, "energy_tables_cached", lambda body: False)  # the per-θ0 tables are built
    rows = (0.7 * math.pi, *THETA0)  # 0.7π: on the region tables
    threaded = at.atlas_from_rest(BODY, rows, PSI0, 400.0, progress=False, threads=2, order=1)
    assert calls == [(list(THETA0), 2)]
    ref = at.atlas_from_rest(BODY, THETA0, PSI0, 400.0, progress=False, order=1)  # on the same (per-θ0) tables
    for name in at.ATLAS_OBSERVABLES:
        assert np.array_equal(threaded.values[name][1:].filled(np.nan), ref.values[name].filled(np.nan),
                              equal_nan=True), name
    with pytest.raises(ValueError, match="threads must be"):
        at.atlas_from_rest(BODY, THETA0, PSI0, 400.0, threads=0)


def test_confirmation_agrees_with_the_ode(small_atlas):
    """At ε = 1e-3 the first-order map's slow period, Φ and Q_R extent are within 5e-3 of the ODE (docs/averaging.md,
    releases 0.75π–0.95π: ≤ 3.7e-4 measured) and it counts the same reversals; the ODE's values are those of a
    run_ensemble of the same start, to the bit (a job's lane does not depend on its batch; the lanes' agreement with
    simulate is tests/numerics/ensembles/test_batch.py's)."""
    check = confirm_atlas(small_atlas, BODY, every=2, points=[(1, 1)], progress=False)
    assert check.index.tolist() == [[0, 0], [0, 2], [1, 1]]
    for name in ("slow_period", "Phi", "QR_extent"):
        assert np.ma.max(np.ma.abs(check.rel_error[name])) < 5e-3, name
    for name in ("full_reversals", "visible_reversals"):
        assert np.ma.max(np.ma.abs(check.rel_error[name])) == 0.0, name
    (ref,) = run_ensemble([Job(BODY, EulerState(THETA0[0], 0.0, PSI0[2]), 400.0)], progress=False)
    assert check.ode["Phi"][1] == ref.Phi and check.ode["QR_extent"][1] == ref.QR_extent


def test_confirmation_on_a_dask_cluster_is_identical(small_atlas):
    pytest.importorskip("distributed")
    here = confirm_atlas(small_atlas, BODY, every=3, progress=False)
    there = confirm_atlas(small_atlas, BODY, every=3, workers=2, progress=False)
    for name in at.ATLAS_OBSERVABLES:
        assert np.array_equal(here.ode[name].filled(np.nan), there.ode[name].filled(np.nan), equal_nan=True), name


def test_bad_grids_and_points_are_refused(small_atlas):
    with pytest.raises(ValueError, match="theta0 must be"):
        at.atlas_from_rest(BODY, [0.9999 * math.pi], PSI0)
    with pytest.raises(ValueError, match="psi0 must be"):
        at.atlas_from_rest(BODY, THETA0, [])
    with pytest.raises(ValueError, match="MAX_ATLAS_POINTS"):
        at.atlas_from_rest(BODY, np.linspace(0.8, 0.9, 600) * math.pi, np.linspace(0, 1, 600))
    with pytest.raises(ValueError, match="every must be"):
        confirm_atlas(small_atlas, BODY, every=0)
    with pytest.raises(ValueError, match="points must lie"):
        confirm_atlas(small_atlas, BODY, every=None, points=[(2, 0)])


def test_atlas_command(tmp_path, capsys):
    out = tmp_path / "atlas"
    argv = ["atlas", "--theta0", "0.9pi:0.95pi:2", "--psi0", "0.15pi:0.4pi:3", "--t-end", "400", "--confirm-every",
            "4", "--confirm", "0.9pi,0.4pi", "--out", str(out), "--json", "--quiet", "--processes", "1"]
    assert main(argv) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["n_points"] == 6 and summary["n_confirmed"] == 3  # flat points 0 and 4, and the named (0, 2)
    lines = (out / "atlas.csv").read_text().splitlines()
    header = [ln for ln in lines if ln.startswith("#")]
    assert any("theta0 grid 0.9pi:0.95pi:2" in ln for ln in header) and any("epsilon=" in ln for ln in header)
    rows = [ln.split(",") for ln in lines if not ln.startswith("#")]
    cols = rows[0]
    confirmed = [r for r in rows[1:] if r[cols.index("ode_Phi")] != ""]
    assert len(rows) == 7 and len(confirmed) == 3
    for ext in ("png", "pdf"):
        for name in ("atlas", "atlas_check"):
            assert (out / f"{name}.{ext}").stat().st_size > 1000
    # existing files are not overwritten unasked; bad grids name the option
    assert main(argv) == 2
    assert "--force" in capsys.readouterr().err
    assert main(["atlas", "--theta0", "0.9pi:0.95pi:0", "--out", str(tmp_path / "x")]) == 2
    assert "--theta0 must be" in capsys.readouterr().err


RATES_AT = (0.95 * math.pi, 0.25 * math.pi)
PHI_DOT0 = (-0.002, 0.1, 0.3)
PSI_DOT0 = (0.002, 0.2)


@pytest.fixture(scope="module")
def rates_atlas():
    return at.atlas_of_rates(BODY, *RATES_AT, PHI_DOT0, PSI_DOT0, 200.0, progress=False)


def test_rates_atlas_points_are_their_own_runs(rates_atlas):
    """Rows ψ̇0, columns φ̇0: every point is the direct run from (θ0, ψ0) with those rates (its lane of the batch
    integrator, as run_ensemble runs it), its diagnostics and its crossings of the critical lines counted as for the
    map (a 2 × 3 grid, so a transposed grid cannot pass)."""
    from rocknroller.analysis.model.equations import EulerState
    from rocknroller.analysis.slow.prediction import critical_regions
    from rocknroller.numerics.ensembles.batch import run_batch

    assert rates_atlas.values["Phi"].shape == (2, 3) and (rates_atlas.row_name, rates_atlas.col_name) == (
        "psi_dot0", "phi_dot0")
    for i, sd in enumerate(PSI_DOT0):
        for j, pd in enumerate(PHI_DOT0):
            (run,) = run_batch([(BODY, EulerState(RATES_AT[0], 0.0, RATES_AT[1], 0.0, pd, sd), 200.0)])
            m = run.maxima
            full, visible = at.reversal_counts(critical_regions(m.QR, m.QJ, m.t, BODY.symmetric())[2], 200.0)
            assert rates_atlas.values["Phi"][i, j] == run.Phi and rates_atlas.values["QJ_extent"][i, j] == run.QJ_extent
            assert (rates_atlas.values["full_reversals"][i, j], rates_atlas.values["visible_reversals"][i, j]) == (
                full, visible)


def test_a_start_near_the_visible_line_reverses(rates_atlas):
    """The paper's fig. 8 start (φ̇0 ≈ −0.002, ψ̇0 = 0.002, on Q_J,π^crit) makes visible-angle reversals; the start at
    (0.1, 0.2), far from both lines, makes none of either kind (paper §Recession: reversals are crossings)."""
    assert rates_atlas.values["visible_reversals"][0, 0] > 0
    assert rates_atlas.values["visible_reversals"][1, 1] == 0 and rates_atlas.values["full_reversals"][1, 1] == 0


def test_ode_release_atlas_is_the_confirmation(small_atlas):
    """The release plane by the ODE gives, at every point, what confirm_atlas's ODE gives there (bit for bit)."""
    ode = at.atlas_from_rest(BODY, THETA0, PSI0, 400.0, method="ode", progress=False, threads=2)
    check = confirm_atlas(small_atlas, BODY, every=1, progress=False)
    assert ode.observables == at.ATLAS_OBSERVABLES  # the ODE's atlas has no chaos layer
    for name in at.ATLAS_OBSERVABLES:
        assert np.array_equal(ode.values[name].filled(np.nan).ravel(), check.ode[name].filled(np.nan),
                              equal_nan=True), name
    with pytest.raises(ValueError, match="atlas.method must be 'map'"):
        confirm_atlas(ode, BODY, every=1)


def test_rates_plane_refusals():
    with pytest.raises(ValueError, match="method must be 'ode'"):
        at.atlas_of_rates(BODY, *RATES_AT, PHI_DOT0, PSI_DOT0, method="map")
    with pytest.raises(ValueError, match="method must be one of"):
        at.atlas_from_rest(BODY, THETA0, PSI0, method="quad")
    with pytest.raises(ValueError, match="theta0 must be"):
        at.atlas_of_rates(BODY, math.pi, 0.0, PHI_DOT0, PSI_DOT0)
    with pytest.raises(ValueError, match="phi_dot0 must be"):
        at.atlas_of_rates(BODY, *RATES_AT, [np.nan], PSI_DOT0)
    with pytest.raises(ValueError, match="MAX_ODE_ATLAS_POINTS"):
        at.atlas_of_rates(BODY, *RATES_AT, np.linspace(0, 1, 200), np.linspace(0, 1, 101))


def test_atlas_command_rates_plane(tmp_path, capsys):
    out = tmp_path / "rates"
    argv = ["atlas", "--plane", "rates", "--phi-dot0", "-0.002:0.3:3", "--psi-dot0", "0.002:0.2:2", "--t-end", "200",
            "--out", str(out), "--json", "--quiet"]
    assert main(argv) == 0
    summary = json.loads(capsys.readouterr().out)
    assert (summary["plane"], summary["method"], summary["n_points"], summary["n_confirmed"]) == ("rates", "ode", 6, 0)
    lines = (out / "atlas.csv").read_text().splitlines()
    assert any("plane rates (theta0=0.95pi, psi0=0.25pi" in ln for ln in lines if ln.startswith("#"))
    cols = [ln for ln in lines if not ln.startswith("#")][0].split(",")
    assert cols[:2] == ["psi_dot0", "phi_dot0"] and "ode_Phi" not in cols
    for ext in ("png", "pdf"):
        assert (out / f"atlas.{ext}").stat().st_size > 1000
    for bad, msg in ((["--method", "map"], "--method map covers the release plane only"),
                     (["--theta0", "0.9pi:0.95pi:2"], "--theta0 must be one value"),
                     (["--confirm-every", "3"], "apply to --method map")):
        assert main(argv[:-4] + bad + ["--out", str(tmp_path / "x"), "--quiet"]) == 2
        assert msg in capsys.readouterr().err
    assert main(["atlas", "--phi-dot0", "0:0.1:2", "--out", str(tmp_path / "y")]) == 2
    assert "give them with --plane rates" in capsys.readouterr().err


# --- the chaos layer (issue 23, item 6) ---

CHAOS_BODY = Body.paper(1e-2)
#: θ0 = 0.95π, ε = 1e-2 (issue 23's table): ψ0 = 0.05 in the chaotic layer along the separatrix (two direct runs 1e-10
#: apart separate to 3e-3 in 100 rocks), ψ0 = π/4 regular (1.6e-10).
CHAOS_PSI0 = (0.05, 0.25 * math.pi)


@pytest.fixture(scope="module")
def chaos_atlas():
    return at.atlas_from_rest(CHAOS_BODY, [0.95 * math.pi], CHAOS_PSI0, 1000.0, progress=False, order=1)


def test_chaos_layer_is_the_maps_indicators(small_atlas):
    """Each point's MEGNO and λ are predict_slow_motion's (order 1) over its own span, max(t_end, 1000 rocks), to the
    bit, and its verdict MEGNO <= 3; without the layer (chaos=False: no tangent vector) the other observables are the
    same to the bit."""
    from rocknroller.analysis.slow.prediction import predict_slow_motion

    assert small_atlas.observables == at.ATLAS_OBSERVABLES + at.CHAOS_OBSERVABLES
    pred = predict_slow_motion(BODY, THETA0[1], PSI0[2], 400.0, order=1)
    assert pred.chaos.span > 10 * 400.0  # 1000 rocks
    assert small_atlas.values["megno"][1, 2] == pred.chaos.megno
    assert small_atlas.values["lyapunov"][1, 2] == pred.chaos.lyapunov
    assert small_atlas.regular[1, 2] == pred.chaos.regular
    plain = at.atlas_from_rest(BODY, THETA0, PSI0, 400.0, progress=False, chaos=False, order=1)
    assert plain.observables == at.ATLAS_OBSERVABLES and "megno" not in plain.values
    for name in at.ATLAS_OBSERVABLES:
        assert np.array_equal(plain.values[name].filled(np.nan), small_atlas.values[name].filled(np.nan),
                              equal_nan=True), name
    with pytest.raises(ValueError, match="no chaos layer"):
        plain.regular
    with pytest.raises(ValueError, match="chaos=True needs method='map'"):
        at.atlas_from_rest(BODY, THETA0, PSI0, 400.0, method="ode", chaos=True)
    with pytest.raises(ValueError, match="chaos must be True, False or None"):
        at.atlas_from_rest(BODY, THETA0, PSI0, 400.0, chaos="yes")
    with pytest.raises(ValueError, match="chaos must be None, False, or True"):
        confirm_atlas(plain, BODY, every=1, chaos=True)
    check = confirm_atlas(plain, BODY, every=5, progress=False)  # no layer, nothing to confirm of it
    assert "megno" not in check.ode
    with pytest.raises(ValueError, match="no chaos layer"):
        check.verdict_agrees


def test_chaos_layer_confirmed_by_the_odes_megno(chaos_atlas):
    """At ε = 1e-2, θ0 = 0.95π the map calls ψ0 = 0.05 chaotic and ψ0 = π/4 regular, and so does the direct motion's
    MEGNO over the same span (1000 rocks); the ODE's values are direct_chaos_indicators' of the same start over it to
    the bit (whichever thread ran them)."""
    from rocknroller.analysis.slow.atlas_check import chaos_span
    from rocknroller.numerics.variational import direct_chaos_indicators

    assert chaos_atlas.regular.tolist() == [[False, True]]
    check = confirm_atlas(chaos_atlas, CHAOS_BODY, every=1, progress=False, threads=2)
    assert check.verdict_agrees.tolist() == [True, True] and check.verdict_agreement == 1.0
    assert check.ode["megno"][0] > 3.0 >= check.ode["megno"][1]
    ref = direct_chaos_indicators(CHAOS_BODY, chaos_atlas.state(0, 0), chaos_span(CHAOS_BODY, 0.95 * math.pi,
                                                                                  1000.0)).indicators
    assert check.ode["megno"][0] == ref.megno and check.ode["lyapunov"][0] == ref.lyapunov
    assert check.rel_error["megno"][0] == chaos_atlas.values["megno"][0, 0] - ref.megno
    assert check.map["megno"][1] == chaos_atlas.values["megno"][0, 1]
    with pytest.raises(ValueError, match="variational runs"):
        confirm_atlas(chaos_atlas, CHAOS_BODY, every=1, progress=False, budget=1e-4)


def test_atlas_command_chaos_layer(tmp_path, capsys):
    """The CSV carries the map's megno and lyapunov at every point and the ODE's and the verdict at the confirmed
    ones; the JSON the agreement; --no-chaos leaves them out, and is refused with --method ode."""
    out = tmp_path / "atlas"
    argv = ["atlas", "--eps", "1e-2", "--theta0", "0.95pi", "--psi0", "0.05:0.25pi:2", "--t-end", "1000",
            "--confirm-every", "1", "--out", str(out), "--json", "--quiet", "--processes", "1"]
    assert main(argv) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["chaos"]["n"] == 2 and summary["chaos"]["agree"] == 2 and summary["chaos"]["disagreements"] == []
    assert summary["map_regular_fraction"] == 0.5
    rows = [ln.split(",") for ln in (out / "atlas.csv").read_text().splitlines() if not ln.startswith("#")]
    cols = rows[0]
    for name in ("megno", "lyapunov", "ode_megno", "err_megno", "verdict_agrees"):
        assert name in cols, name
    assert [r[cols.index("verdict_agrees")] for r in rows[1:]] == ["true", "true"]
    assert float(rows[1][cols.index("megno")]) > 3.0 >= float(rows[2][cols.index("megno")])
    for name in ("atlas.png", "atlas.pdf", "atlas_check.png", "atlas_check.pdf"):
        assert (out / name).stat().st_size > 1000, name
    assert main(argv + ["--force", "--no-chaos"]) == 0
    assert "chaos" not in json.loads(capsys.readouterr().out)
    cols = [ln for ln in (out / "atlas.csv").read_text().splitlines() if not ln.startswith("#")][0].split(",")
    assert not [c for c in cols if "megno" in c or "lyapunov" in c or "verdict" in c]
    assert main(["atlas", "--method", "ode", "--no-chaos", "--out", str(tmp_path / "x")]) == 2
    assert "--no-chaos apply to --method map" in capsys.readouterr().err
