"""The direct ODE under hard conditions: starts at rest near θ = 0, turning points only, limits, accuracy
ranges, the energy check, and the compiled-integrator cache (nothing is loaded from it but heyoka's own)."""

from __future__ import annotations

import hashlib
import inspect
import json
import math
import os
import subprocess
import sys
import time

import numpy as np
import pytest
import roundoff as ro

import rocknroller.numerics.backends as backends
import rocknroller.numerics.integrate as integ
from rocknroller.analysis.model import equations
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState, turning_point_function
from rocknroller.analysis.model.invariants import energy
from rocknroller.numerics.integrate import AccuracyError, AccuracyWarning, simulate
from rocknroller.numerics.run_limits import energy_scale
from rocknroller.numerics.trajectory import TurningPointRun

BODY = Body.paper(1e-3)
U = np.finfo(float).eps


def _sign_changes(traj, t_end: float, n: int = 600_001) -> int:
    """Sign changes of dγ3/dt on a fine grid of the dense output (the turning points, counted independently)."""
    t = np.linspace(1e-9, t_end - 1e-9, n)
    g = turning_point_function(traj.state_at(t).T)
    return int(np.count_nonzero(np.sign(g[1:]) != np.sign(g[:-1])))


@pytest.mark.parametrize("theta0", [1e-3, 1e-5, 1e-6, 1e-7, 1e-8])
def test_every_turning_point_from_rest_near_the_pole(theta0):
    """Pure rocking from rest at θ0 → 0: 12 minima (pole passages, the first at t ≈ T/4 ≈ 2.50) and 11 maxima
    in 60 time units, as many as a fine sign-change scan and scipy's DOP853 find.  heyoka reported the first
    minimum at t = 0 for θ0 ≤ 1e-5 (its first step then holds both roots, one exactly at the start)."""
    traj = simulate(BODY, EulerState(theta0), 60.0)
    ref = simulate(BODY, EulerState(theta0), 60.0, method="scipy")
    assert (len(traj.maxima), len(traj.minima)) == (11, 12) == (len(ref.maxima), len(ref.minima))
    assert _sign_changes(traj, 60.0) == 23
    period = 2.0 * traj.maxima_spacing  # two maxima per physical rocking period
    assert traj.minima.t[0] == pytest.approx(period / 4, rel=1e-3)
    # the state pins the tilt only to ~u absolute (γ3 ≈ 1 carries the unit norm), i.e. θ to u/θ0 relative; over
    # N ≈ 30 steps these phase errors add up to ≲ N·u/θ0 of the period T ≈ 10: δt ≲ 300 u/θ0, here with 10× margin
    np.testing.assert_allclose(traj.minima.t, ref.minima.t, rtol=0, atol=1e-9 + 3000 * U / theta0)
    kinds = np.isin(np.sort(np.concatenate([traj.maxima.t, traj.minima.t])), traj.maxima.t)
    assert np.all(kinds[1:] != kinds[:-1])


def test_energy_error_is_measured_against_a_scale_that_does_not_vanish():
    """At θ0 = 1e-6 from rest E ≈ g a θ0²/2 = 2.5e-13 is itself at the round-off of g a (1 − cos θ): the
    error is measured against E + g a, where it is a few u (it was 3e-4 relative to E)."""
    traj = simulate(BODY, EulerState(1e-6), 60.0)
    E0 = float(traj.E[0])
    assert energy_scale(BODY, E0) == E0 + BODY.g * BODY.a
    # n_steps × ε × κ_E (``roundoff.integration_bound``; κ_E = Σ|yᵢ ∂E/∂yᵢ| ≈ g a here, from γ3 ≈ 1) plus the
    # rounding of two evaluations of E (≤ 25 operations on terms whose size κ_E measures), × 4 (margin)
    kappa = float(ro.relative_condition(lambda Z: energy(BODY, Z[:, 0:3].T, Z[:, 3:6].T), traj.states[:, 0:6]).max())
    scale = energy_scale(BODY, E0)
    bound = 4 * (ro.integration_bound(traj.n_steps, traj.tolerance, kappa) + 2 * ro.gamma(25) * kappa) / scale
    assert traj.energy_rel_error >= 0.0
    ro.assert_within(traj.energy_rel_error, bound, "energy", 1.0)  # ≈ 1e-14 (relative to E it was 3e-4)
    assert np.isfinite(traj.energy_rel_error)


def test_turning_points_only_equals_the_full_run(fig5_initial):
    """samples=False over one stretch is the same computation as samples=True: identical turning points."""
    full = simulate(BODY, fig5_initial, 300.0)
    tp = simulate(BODY, fig5_initial, 300.0, samples=False)
    assert isinstance(tp, TurningPointRun)
    for name in ("t", "theta", "phi", "psi", "QR", "QJ"):
        assert np.array_equal(getattr(tp.maxima, name), getattr(full.maxima, name)), name
        assert np.array_equal(getattr(tp.minima, name), getattr(full.minima, name)), name
    assert tp.Phi == full.Phi and tp.n_steps == full.n_steps


def test_turning_points_only_in_stretches(fig5_initial, monkeypatch):
    """Many short stretches (each ends with a shortened step, so the step sequence differs): the same turning
    points to the integrator's accuracy (heyoka against DOP853 differ by ≤ 1e-9 over 100 t.u., test_integrate),
    φ continuous across the joins, every stretch streamed in time order."""
    full = simulate(BODY, fig5_initial, 100.0)
    monkeypatch.setattr(integ, "CHUNK_RADIANS", 7.0)  # ≈ 2.4 time units per stretch
    parts = []
    tp = simulate(BODY, fig5_initial, 100.0, samples=False, on_turning_points=lambda mx, mn: parts.append((mx, mn)))
    assert len(parts) > 30
    assert len(tp.maxima) == len(full.maxima) and len(tp.minima) == len(full.minima)
    for name in ("t", "phi", "psi", "QR", "QJ"):
        np.testing.assert_allclose(getattr(tp.maxima, name), getattr(full.maxima, name), rtol=0, atol=1e-9)
    streamed = np.concatenate([mx.t for mx, _ in parts])
    assert np.array_equal(streamed, tp.maxima.t) and np.all(np.diff(streamed) > 0)
    assert tp.energy_rel_error <= tp.energy_tolerance


@pytest.mark.parametrize(
    "kwargs, fragment",
    [
        (dict(t_end=1e300), r"t_end=1e\+300 is too long"),
        (dict(t_end=1e6), "MAX_DENSE_RADIANS"),  # samples kept: ~3e6 radians
        (dict(t_end=1e300, samples=False), "MAX_RADIANS"),
        (dict(t_end=100.0, dt=1e-8), "MAX_SAMPLES"),
        (dict(t_end=1e4, dt=1e-5, samples=False), "MAX_GRID_POINTS"),
        (dict(t_end=float("nan")), "t_end must be"),
        (dict(t_end="x"), "t_end must be"),
        (dict(t_end=10.0, dt=0.0), "dt must be"),
        (dict(t_end=10.0, precision="quad"), "precision must be"),
        (dict(t_end=10.0, method="scipy", rtol=0.0), "rtol must lie"),
    ],
)
def test_sizes_are_refused_up_front(kwargs, fragment):
    t0 = time.perf_counter()
    t_end = kwargs.pop("t_end")
    with pytest.raises(ValueError, match=fragment):
        simulate(BODY, EulerState(0.95 * math.pi), t_end, **kwargs)
    assert time.perf_counter() - t0 < 5.0  # refused before integrating (a generous bound: no timing assertion)


@pytest.mark.parametrize(
    "body, initial, fragment",
    [
        (Body(a=0.05, I1=0.35e-300, I2=0.35e-300, I3=0.4e-300, g=9.87), EulerState(1.0), "I3 must lie in"),
        (Body(a=0.05, I1=0.35e300, I2=0.35e300, I3=0.4e300, g=9.87), EulerState(1.0), "I3 must lie in"),
        (Body(a=0.05, I1=0.35, I2=0.35, I3=0.4, g=1e300), EulerState(1.0), "g must be 0 or lie in"),
        (Body(a=0.05, I1=0.35, I2=0.35, I3=0.4, g=1e-300), EulerState(1.0), "g must be 0 or lie in"),
        (Body(a=0.05, I1=0.35, I2=0.35, I3=0.4, g=0.0), EulerState(1.0), "no motion"),  # at rest, no potential
        (Body(a=0.05, I1=0.35, I2=0.35, I3=0.4, g=0.0), EulerState(1.0, phi_dot=1e-8), "without gravity"),
        (Body(a=0.05, I1=0.35, I2=0.35, I3=0.4, g=0.0), EulerState(1.0, phi_dot=1e7), "without gravity"),
        (BODY, EulerState(1.0, phi_dot=1e100), "rates are too large"),
        (BODY, EulerState.from_omega(1.0, 0.0, 0.0, (1e100, 0.0, 0.0)), "rates are too large"),
        (Body(a=0.0, I1=0.35, I2=0.35, I3=0.4, g=9.87), EulerState(1.0), "no motion"),
        (BODY, EulerState(0.0), "no motion"),
        (BODY, EulerState(math.pi), "no motion"),
    ],
)
def test_parameters_outside_the_accurate_ranges_are_refused(body, initial, fragment):
    with pytest.raises(ValueError, match=fragment):
        simulate(body, initial, 10.0)


def test_energy_check_warns_or_fails(fig5_initial, monkeypatch):
    """A run whose energy error exceeds energy_error_bound warns (AccuracyWarning), or raises with strict=True.
    The bound is made impossibly tight here to exercise the check; the real runs stay far below it."""
    traj = simulate(BODY, fig5_initial, 50.0)
    assert traj.energy_rel_error <= traj.energy_tolerance / 100
    monkeypatch.setattr("rocknroller.numerics.run_limits.ENERGY_SLACK", 1e-30)
    with pytest.warns(AccuracyWarning, match="energy error"):
        simulate(BODY, fig5_initial, 50.0)
    with pytest.raises(AccuracyError, match="energy error"):
        simulate(BODY, fig5_initial, 50.0, strict=True)


def test_dense_step_cap_is_enforced_while_integrating(fig5_initial, monkeypatch):
    monkeypatch.setattr(integ, "MAX_DENSE_STEPS", 50)
    with pytest.raises(ValueError, match="MAX_DENSE_STEPS"):
        simulate(BODY, fig5_initial, 100.0)


def _old_cache_path(cache: str) -> str:
    """Where the previous version loaded a pickled integrator from (the key computed as it did)."""
    import heyoka as hy

    source = inspect.getsource(equations) + inspect.getsource(backends._EventLog)
    key = hashlib.sha256(f"{hy.__version__}|{sys.version}|double|{source}".encode()).hexdigest()[:16]
    return os.path.join(cache, f"taylor-double-{key}.pickle")


def test_nothing_planted_in_the_cache_runs(tmp_path):
    """A pickle planted where the integrator used to be cached would run code when loaded: the package loads
    no pickles (heyoka keeps its own compiled-code cache), so the marker is never written."""
    cache, marker = tmp_path / "cache", tmp_path / "pwned"
    cache.mkdir()
    payload = (b"cos\nsystem\n(S'touch " + str(marker).encode() + b"'\ntR.")  # protocol-0 pickle of os.system
    for path in (_old_cache_path(str(cache)), str(cache / "taylor-double-0000000000000000.pickle")):
        with open(path, "wb") as fh:
            fh.write(payload)
    env = {**os.environ, "ROCKNROLLER_CACHE": str(cache)}
    code = ("import math; from rocknroller.analysis.model.body import Body; from rocknroller.analysis.model.equations import EulerState; "
            "from rocknroller.numerics.integrate import simulate; "
            "print(len(simulate(Body.paper(1e-3), EulerState(0.95 * math.pi), 20.0).maxima))")
    proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert int(proc.stdout) >= 1
    assert not marker.exists()


def test_unwritable_heyoka_cache_gives_a_warning(tmp_path):
    """HEYOKA_CACHE_DIR under a plain file cannot be created (as any user, root included): a CacheWarning
    naming the directory and the fix, and the run still works (the process compiles, ~6 s)."""
    blocker = tmp_path / "file"
    blocker.write_text("")
    env = {**os.environ, "HEYOKA_CACHE_DIR": str(blocker / "sub")}
    code = ("import warnings; warnings.simplefilter('always'); from rocknroller.analysis.model.body import Body; "
            "from rocknroller.analysis.model.equations import EulerState; from rocknroller.numerics.integrate import simulate; "
            "print(len(simulate(Body.paper(), EulerState(1.0), 5.0).maxima))")
    proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr.count("CacheWarning") == 1
    assert str(blocker / "sub") in proc.stderr and "HEYOKA_CACHE_DIR" in proc.stderr


def test_energy_evaluation_matches_the_scale():
    """energy_scale bounds every term of E within a factor 3 (T ≤ E, V ≤ 2 g a) on a spinning start too."""
    y = EulerState(2.0, 0.0, 0.3, 0.4, 1.5, -2.0).to_body_state()
    E = float(energy(BODY, y[0:3], y[3:6]))
    V = BODY.g * BODY.a * (1 - y[2])
    assert E - V <= energy_scale(BODY, E) and V <= 2 * energy_scale(BODY, E)


def test_subnormal_dt_and_tiny_t_end():
    """Fuzzing found an OverflowError for dt = 5e-324 (t_end/dt = inf) and a one-sample grid for t_end = 5e-324:
    the first is refused with the limit named, the second keeps both ends of [0, t_end]."""
    state = EulerState(0.95 * math.pi, 0.0, 0.4)
    with pytest.raises(ValueError, match="dt=5e-324 gives inf samples"):
        simulate(Body.paper(1e-3), state, 1.0, dt=5e-324)
    run = simulate(Body.paper(1e-3), state, 5e-324)
    assert run.t.tolist() == [0.0, 5e-324]


def test_a_start_whose_energy_underflows_is_refused():
    """Issue 25, item 20: without gravity (a = 0) and with rates so small that ½ ωᵀKω underflows to 0, Λ = 0 and
    default_dt divided by it (ZeroDivisionError).  Refused up front, naming the start, for simulate and a Job; the
    threshold |ω| ≈ √(2⁻¹⁰⁷⁴/I_min) ≈ 4e-162 lies between the rates 1e-200 (refused) and 1e-150 (E = 2e-301 > 0:
    a run, too slow to turn θ within 20 time units)."""
    from rocknroller.numerics.ensembles.ensemble import Job

    centred = Body(a=0.0, I1=0.35, I2=0.36, I3=0.4, g=9.87)
    start = EulerState(1.0, psi_dot=1e-200)
    for make in (lambda: simulate(centred, start, 20.0), lambda: Job(centred, start, 20.0)):
        with pytest.raises(ValueError, match=r"no motion to resolve: EulerState\(theta=1.0.*psi_dot=1e-200.*below "
                                             r"about 3.8e-162"):
            make()
    run = simulate(centred, EulerState(1.0, psi_dot=1e-150), 20.0)
    assert integ.rate_bound(centred, run.states[0]) > 0.0 and len(run.maxima) == len(run.minima) == 0


@pytest.mark.parametrize("where", ["a file", "garbage cache.db"])
def test_an_unusable_heyoka_cache_keeps_stdout_clean(tmp_path, where):
    """Issue 25, item 22: heyoka logged `[warning]` lines on stdout at every lookup in a cache it cannot use (a
    HEYOKA_CACHE_DIR that is a file; a cache.db that is not a database), ahead of anything the program printed.
    The cache is now switched off for the process and one CacheWarning names it on stderr; stdout holds only the
    program's own output."""
    if where == "a file":
        cache = tmp_path / "afile"
        cache.write_text("not a directory")
    else:
        cache = tmp_path / "hy"
        cache.mkdir()
        (cache / "cache.db").write_bytes(bytes(range(256)) * 20)
    env = {**os.environ, "HEYOKA_CACHE_DIR": str(cache)}
    code = ("import json, warnings; warnings.simplefilter('always'); from rocknroller.analysis.model.body import Body; "
            "from rocknroller.analysis.model.equations import EulerState; "
            "from rocknroller.numerics.integrate import simulate; "
            "print(json.dumps({'n': len(simulate(Body.paper(), EulerState(1.0), 10.0).maxima)}))")
    proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["n"] == 1  # the whole of stdout is the program's JSON (the maximum at t = 5.39)
    assert proc.stderr.count("CacheWarning") == 1 and str(cache) in proc.stderr and "switched off" in proc.stderr
    assert "[warning]" not in proc.stdout + proc.stderr


def test_turning_points_only_samples_a_fine_grid_in_bounded_pieces(fig5_initial, monkeypatch):
    """Issue 25, item 19: with samples=False the unwrapping grid of a stretch was sampled whole (t_end = 1000,
    dt = 1e-5: 10⁸ points, > 5 GB, then a MemoryError).  Sampled in pieces of GRID_CHUNK_POINTS, the arrays alive
    (tracemalloc: numpy's allocations) grow by at most GRID_CHUNK_POINTS × GRID_BYTES_PER_POINT over those of the
    same run on a grid that fits one piece; pieces of 4096 points here, a grid of 2·10⁵ points (old: ≈ 90 MB)."""
    import tracemalloc

    monkeypatch.setattr(integ, "GRID_CHUNK_POINTS", 4096, raising=False)
    simulate(BODY, fig5_initial, 20.0, samples=False)  # compiled, imported: only the run itself is measured

    def traced(dt: float) -> tuple[TurningPointRun, int]:
        tracemalloc.start()
        try:
            return simulate(BODY, fig5_initial, 20.0, dt=dt, samples=False), tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()

    _, coarse_peak = traced(20.0 / 1000)
    fine, fine_peak = traced(1e-4)
    assert fine_peak <= coarse_peak + integ.GRID_CHUNK_POINTS * integ.GRID_BYTES_PER_POINT
    # the pieces share their end points and continue each other's angles: the same results as one piece, to the bit
    monkeypatch.setattr(integ, "GRID_CHUNK_POINTS", 2**30)
    whole = simulate(BODY, fig5_initial, 20.0, dt=1e-4, samples=False)
    for name in ("t", "theta", "phi", "psi", "QR", "QJ"):
        assert np.array_equal(getattr(fine.maxima, name), getattr(whole.maxima, name)), name
        assert np.array_equal(getattr(fine.minima, name), getattr(whole.minima, name)), name
    assert fine.energy_rel_error == whole.energy_rel_error


class _Recording:
    """A heyoka integrator that records the keyword arguments of each propagate_until."""

    def __init__(self, ta, calls):
        object.__setattr__(self, "_ta", ta)
        object.__setattr__(self, "_calls", calls)

    def __getattr__(self, name):
        return getattr(self._ta, name)

    def __setattr__(self, name, value):
        setattr(self._ta, name, value)

    def propagate_until(self, t, **kwargs):
        self._calls.append(kwargs)
        return self._ta.propagate_until(t, **kwargs)


@pytest.mark.parametrize("samples", [True, False])
def test_no_python_call_per_step_without_a_bar(fig5_initial, monkeypatch, samples):
    """Issue 25, item 18: a run that shows no bar made a Python call per step (7 % of its time) to count steps
    against the dense-output cap; the cap is heyoka's own ``max_steps`` now, and a callback only moves a shown
    bar.  The cap still stops a run at exactly one step past it."""
    real, calls = integ.heyoka_integrator, []
    monkeypatch.setattr(backends, "heyoka_integrator", lambda *a, **k: _Recording(real(*a, **k), calls))
    run = simulate(BODY, fig5_initial, 30.0, samples=samples, progress=False)
    assert calls and all(c.get("callback") is None for c in calls)
    assert [c["max_steps"] for c in calls][:1] == ([integ.MAX_DENSE_STEPS + 1] if samples else [0])
    steps = run.n_steps
    calls.clear()
    simulate(BODY, fig5_initial, 30.0, progress=True)  # a bar shown: moved by a callback
    assert all(callable(c.get("callback")) for c in calls)
    monkeypatch.setattr(integ, "MAX_DENSE_STEPS", steps)  # exactly enough steps: runs
    assert simulate(BODY, fig5_initial, 30.0).n_steps == steps
    monkeypatch.setattr(integ, "MAX_DENSE_STEPS", steps - 1)  # one too few: refused
    with pytest.raises(ValueError, match="MAX_DENSE_STEPS"):
        simulate(BODY, fig5_initial, 30.0)
