"""The public namespace ``import rocknroller as rr``: what it exports, tables as DataFrames, plots on given axes."""

from __future__ import annotations

import math
import sys

import numpy as np
import pandas as pd
import pytest
from matplotlib.figure import Figure

import rocknroller as rr


def test_namespace_exports_what_a_researcher_uses():
    assert len(rr.__all__) == len(set(rr.__all__))
    for name in rr.__all__:
        assert getattr(rr, name) is not None, name
    for name in ("Body", "EulerState", "simulate", "F", "turning_points", "precession", "QJ_crit_0", "QJ_crit_pi",
                 "region", "cos_theta_z", "delta_of", "delta_bound_coefficients", "laurent_function",
                 "predict_slow_motion", "pendulum_constants", "cite"):
        assert name in rr.__all__, name


def test_precession_table_as_dataframe_keeps_missing_values_missing():
    """A point without motion is a missing value in the frame, not NaN, and the others equal the arrays."""
    body = rr.Body.paper(0.0)
    tp = rr.solve_turning_points(np.array([1.0, 0.0]), np.array([0.01, 0.0]), np.array([0.02, 0.0]), body)
    pr, _ = rr.precession_from_turning_point(np.array([0.9 * math.pi, 0.9 * math.pi]), np.array([0.01, 0.02]),
                                             np.array([0.02, 0.0]), body)
    frame = pr.to_dataframe()
    assert list(frame["Q_R"]) == [0.01, 0.02] and frame.shape[0] == 2
    np.testing.assert_array_equal(frame["T_theta"].to_numpy(float), np.ma.getdata(pr.T_theta))
    assert set(frame["status_text"]) <= set(rr.analysis.routh.quadrature.QUADRATURE_STATUS_TEXT.values())
    tpf = tp.to_dataframe()
    assert tpf["theta_X"].dtype == "Float64" and tpf["theta_X"].isna().tolist() == list(np.ma.getmaskarray(tp.theta_X))
    assert not np.isnan(tpf["theta_X"].to_numpy(float, na_value=0.0)).any()


def test_trajectory_tables_and_plots(fig5_initial):
    traj = rr.simulate(rr.Body.paper(1e-3), fig5_initial, 60.0)
    frame = traj.to_dataframe()
    assert frame.shape == (traj.t.size, 9)
    np.testing.assert_array_equal(frame["Q_J"].to_numpy(), traj.QJ)
    tps = traj.turning_points_dataframe()
    assert len(tps) == len(traj.maxima) + len(traj.minima) and tps["t"].is_monotonic_increasing
    assert set(tps["kind"]) == {"max", "min"}
    run = rr.simulate(rr.Body.paper(1e-3), fig5_initial, 60.0, samples=False)
    pd.testing.assert_frame_equal(run.to_dataframe(), tps)  # the same turning points, bit for bit
    fig = Figure()
    for kind in ("orbit", "phi", "track"):
        ax = fig.add_subplot()
        assert traj.plot(ax=ax, kind=kind) is ax and ax.lines
    with pytest.raises(ValueError, match="kind must be one of"):
        run.plot(ax=fig.add_subplot(), kind="track")  # no samples, no contact track


def test_slow_prediction_table_and_plot():
    pred = rr.predict_slow_motion(rr.Body.paper(1e-3), 0.95 * math.pi, math.pi / 4, 200.0, order=1)
    frame = pred.to_dataframe()
    assert list(frame.columns) == ["t", "Q_R", "Q_J", "Theta", "phi", "region"]
    np.testing.assert_array_equal(frame["Q_R"].to_numpy(), pred.series.QR)
    fig = Figure()
    assert pred.plot(fig) is fig and fig.axes[0].lines[0].get_xdata().size == pred.series.t.size


def test_to_dataframe_says_pandas_is_missing(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match="pip install pandas"):
        rr.precession_from_turning_point(0.9 * math.pi, 0.01, 0.02, rr.Body.paper(0.0))[0].to_dataframe()


#: The public namespace, as it stood before the package was laid out by subject (issue 22): the restructuring moved
#: modules, not names.  A name added to ``rr`` on purpose is added here too.
PUBLIC_NAMES = [
    "AccuracyError", "AccuracyWarning", "Atlas", "AtlasCheck", "Body", "CriticalStart", "EulerState", "F", "Job",
    # issue 25, item 13: the critical-line diagram and the ODE check of a prediction
    "DiagramData", "PredictionCheck", "check_prediction", "region_diagram",
    # issue 23, item 2: the direct motion's chaos indicators
    "DirectChaos", "direct_chaos_indicators",
    "NoMotionError", "PendulumConstants", "PeriodDoubling", "Precession", "QJ_crit", "QJ_crit_0", "QJ_crit_pi",
    "RunSummary", "SlowPrediction", "SteadyRollingError", "Trajectory", "TurningPointRun", "TurningPoints", "V_phi",
    "V_psi", "atlas_from_rest", "atlas_of_rates", "azimuth_span", "cite", "confirm_atlas", "cos_theta_z",
    "critical_start", "delta_bound_coefficients", "delta_of", "effective_potential", "invariants_from_euler",
    "laurent_coefficients", "laurent_function", "laurent_series", "pendulum_constants", "pendulum_prediction",
    "period_doubling", "precession", "precession_from_turning_point", "precession_mp", "predict_slow_motion", "region",
    "reversal_analysis", "run_ensemble", "simulate", "solve_turning_points", "state_from_turning_point", "theta_e",
    "theta_z", "theta_z_expansion", "turning_points",
    # the family of loaded spheres: a body with its mass centre anywhere, and Borisov and Mamaev's table
    "LoadedSphere", "hierarchy_table",
    # issue 23, item 4: periodic orbits near the period doubling and their diagram
    "Branch", "PeriodicOrbit", "bifurcation_diagram", "continue_orbit", "periodic_orbit",
    # issue 23: statistics where the slow motion is chaotic, and the phase portrait
    "StartBall", "map_ensemble", "ode_ensemble", "compare_ensembles", "EnsembleStatistics", "EnsembleComparison",
    "slow_portrait", "write_portrait", "SlowPortrait",
    # issue 32, item 20: the slow map and the exact map as objects
    "SlowMap", "ExactMap", "build_release_tables",
    # every energy from one build: the tables over energy, and the period doubling over θ0
    "build_energy_tables", "load_energy_tables", "EnergyTables", "period_doubling_line", "period_doubling_plot",
    "PeriodDoublingLine",
    # issue 32, item 14: the region fractions of a run's maxima (run_ensemble's summaries)
    "region_fractions",
]


def test_public_namespace_is_the_stated_list():
    """``dir(rocknroller)`` after a fresh import: the stated names (each also in ``__all__``, with ``__version__``),
    and as modules only the three folders the front door imports from."""
    import json
    import subprocess

    code = ("import inspect, json, rocknroller as rr; d = [n for n in dir(rr) if not n.startswith('_')]; "
            "print(json.dumps([sorted(n for n in d if not inspect.ismodule(getattr(rr, n))), "
            "sorted(n for n in d if inspect.ismodule(getattr(rr, n))), rr.__all__]))")
    names, modules, exported = json.loads(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                                                         check=True).stdout)
    assert names == sorted(PUBLIC_NAMES)
    assert sorted(exported) == sorted(PUBLIC_NAMES + ["__version__"])
    assert modules == ["analysis", "numerics", "papers"]


def test_import_loads_no_heavy_dependency():
    """``import rocknroller`` took ~0.8 s because sympy and scipy.optimize loaded eagerly (the Laurent expansions, the
    symbolic checks of θ_z, θ_e's root finder; also scipy.special for the pendulum's elliptic functions).  They load
    where they are used; a fresh import now takes ~0.25 s on this machine (a timing, so not asserted here)."""
    import subprocess

    heavy = ("sympy", "scipy.optimize", "scipy.special", "heyoka", "matplotlib", "pandas")
    code = f"import sys, rocknroller; print([m for m in {heavy!r} if m in sys.modules])"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
    assert callable(rr.laurent_series) and "laurent_series" in dir(rr)  # loaded on first use


BIG = 10**400  # an int beyond the floats: float() raises OverflowError on it


@pytest.mark.parametrize("call", [
    lambda: rr.Body(BIG, 0.35, 0.35, 0.4, 9.87),
    lambda: rr.Body.paper(BIG),
    lambda: rr.EulerState(BIG, 0.0, 0.0),
    lambda: rr.simulate(rr.Body.paper(), rr.EulerState(1.0, 0.0, 0.0), BIG),
    lambda: rr.Job(rr.Body.paper(), rr.EulerState(1.0, 0.0, 0.0), BIG),
    lambda: rr.precession(BIG, 0.01, 0.02, rr.Body.paper()),
    lambda: rr.turning_points(1.0, BIG, 0.0, rr.Body.paper()),
    lambda: rr.F(BIG, 1.0, 0.0, 0.0, rr.Body.paper()),
    lambda: rr.predict_slow_motion(rr.Body.paper(1e-3), BIG, 0.1),
    lambda: rr.predict_slow_motion(rr.Body.paper(1e-3), 0.95 * math.pi, BIG),
    lambda: rr.predict_slow_motion(rr.Body.paper(1e-3), 0.95 * math.pi, 0.1, BIG),
    lambda: rr.pendulum_constants(rr.Body.paper(1e-3), BIG),
    lambda: rr.precession(1.0, 0.01, 0.02, rr.Body.paper(), rtol=BIG),
    lambda: rr.simulate(rr.Body.paper(), rr.EulerState(1.0, 0.0, 0.0), 1.0, budget=BIG * -1),
], ids=["Body", "Body.paper", "EulerState", "simulate", "Job", "precession", "turning_points", "F",
        "predict theta0", "predict psi0", "predict t_end", "pendulum_constants", "precession rtol", "simulate budget"])
def test_an_int_beyond_the_floats_is_a_value_error(call):
    """``10**400`` as a number raised OverflowError (from ``float`` or numpy) at every entry point; it is bad input
    like any other: a ValueError naming the parameter."""
    with pytest.raises(ValueError, match="must"):
        call()


def test_csv_files_and_dataframes_name_columns_alike(tmp_path):
    """One column naming (issue 25, item 13: ``Q_R`` in the CSV files, ``QR`` in ``to_dataframe()``): the files of
    ``rocknroller simulate`` read back with pandas have the columns of the run's own DataFrames."""
    from rocknroller.cli import main

    assert main(["simulate", "--t-end", "30", "--out", str(tmp_path), "--quiet"]) == 0
    traj = rr.simulate(rr.Body.paper(1e-3), rr.analysis.model.equations.fig5_start(), 30.0)
    samples = pd.read_csv(tmp_path / "samples.csv", comment="#")
    turning = pd.read_csv(tmp_path / "turning_points.csv", comment="#")
    assert set(traj.to_dataframe().columns) <= set(samples.columns)
    assert set(traj.turning_points_dataframe().columns) <= set(turning.columns)
    frames = [traj.to_dataframe(), traj.maxima.to_dataframe(), rr.solve_turning_points(1.0, 0.01, 0.02, rr.Body.paper(0.0)).to_dataframe(),
              rr.predict_slow_motion(rr.Body.paper(1e-3), 0.95 * math.pi, 0.5, 100.0, order=1).to_dataframe()]
    for frame in frames:
        assert {"Q_R", "Q_J"} <= set(frame.columns) and not {"QR", "QJ"} & set(frame.columns)
