"""heyoka vs scipy DOP853 vs a compiled DOP853 (CyRK) on form (i), side by side in one process.

The paper's figure-5 run: ε = 1e-3, 1500 time units, 113 maxima and 114 minima of θ.

Run:  python benchmarks/bench_integrate.py
The CyRK rows need the optional extra ``bench`` (CyRK, numba and Cython):  pip install -e ".[bench]"; the compiled
row with events also needs a C++ compiler and the Python headers (as the package's own build does).  Without them
the benchmark prints why and skips those rows; the heyoka and scipy rows always run.

Part 1, ``simulate()`` (integration + events + Trajectory), each backend at its default accuracy: heyoka at
tol = machine ε against scipy DOP853 at rtol 3e-14.

Part 2, integration + turning points only, at equal energy error.  Every backend integrates the same right-hand side,
:func:`rocknroller.analysis.model.equations.body_frame_rhs`, and reports every turning point of θ (a zero of
dγ3/dt, :func:`~rocknroller.analysis.model.equations.turning_point_function`):

- heyoka: taylor_adaptive with a non-terminal event.  Its tolerance only selects the Taylor order, so its energy
  error comes in discrete levels; two levels are compared (tol 1e-11 and 1e-9), and tol = ε is shown alone;
- scipy DOP853: ``solve_ivp`` with ``events=``, the library's numpy right-hand side called from Python;
- CyRK DOP853 compiled + events: ``cysolve_ivp``, CyRK's C++ DOP853 with its event location, right-hand side and
  event function compiled (a Cython module generated here, built once and kept in the rocknroller cache,
  ``$ROCKNROLLER_CACHE/bench``);
- CyRK DOP853 numba, **without events**: ``nbsolve2_ivp``, the same C++ DOP853 calling a numba ``cfunc``
  right-hand side.  That entry point has no events, so the turning points are located after the run, inside the
  same compiled function: sign changes of dγ3/dt between steps, refined on CyRK's dense output (Illinois regula
  falsi to 4 ulp of t);
- CyRK DOP853 py + events: ``pysolve_ivp``, the same C++ DOP853 with CyRK's events, but its right-hand side and
  event function (numba-compiled) are called back through Python.

DOP853's rtol (atol 1e-20, far below every component) is scanned with the CyRK numba run and, for each heyoka
level, set to the value whose energy error is nearest heyoka's; scipy uses the same rtol (same method: CyRK's DOP853
is scipy's, ported to C++).  Rows whose energy error is off heyoka's by more than 2x are flagged.

The compiled right-hand sides are generated, not retyped: body_frame_rhs is traced (it uses only + − × ÷) into
straight-line code with the same operations in the same order, compiled by numba and by Cython; before anything is
timed each must agree with body_frame_rhs at 1000 random states to 1e-14 relative (bitwise agreement is expected).

Energy error, every backend alike: max |E(t) − E(0)| / (E(0) + g a) on a 3001-point grid of the run's dense output,
measured in an untimed rerun.  Times: best of 3 (scipy, seconds) or of 10 (the others, milliseconds); the one-off
costs (heyoka's LLVM compilation and its disk-cache build, numba's JIT, the Cython build) are reported separately.
Each backend's turning points are compared with heyoka's at tol = ε: count and largest time difference.
"""

from __future__ import annotations

import math
import time

import numpy as np

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.invariants import energy
from rocknroller.analysis.model.equations import STATE_SIZE, body_frame_rhs, turning_point_function
from rocknroller.numerics.backends import PARAM_COUNTS, _build_heyoka, _EventLog
from rocknroller.numerics.integrate import heyoka_integrator, simulate
from rocknroller.numerics.run_limits import energy_scale
from rocknroller.analysis.model.equations import fig5_start

T_END = 1500.0
N_GRID = 3001
REPEATS = 3  # best of 3 for the runs of seconds (scipy)
REPEATS_FAST = 10  # best of 10 for the runs of milliseconds, whose timing noise on a shared machine is larger
#: heyoka's tolerance only selects the Taylor order (the step size follows from the series' radius of convergence),
#: so its energy error comes in discrete levels; these two give ≈ 2e-13 and ≈ 7e-12 on this run.  DOP853's rtol is
#: the continuous knob: it is scanned and tuned to each level.
HEYOKA_LEVELS = (1e-11, 1e-9)
#: rtol grid, 8 points per decade from 2.3e-14 (scipy and CyRK raise any rtol below 100 ε to 100 ε).
DOP853_RTOLS = tuple(2.3e-14 * 10.0 ** (k / 8) for k in range(22))
DOP853_ATOL = 1e-20  # far below every component's size: the error is set by rtol alone


def best_of(fn, n=REPEATS):
    times, out = [], None
    for _ in range(n):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def energy_error(body, states):
    """max |E − E(0)| / (E(0) + g a) over states of shape (N, 11), the first being the initial state."""
    E = energy(body, states[:, 0:3].T, states[:, 3:6].T)
    return float(np.max(np.abs(E - E[0])) / energy_scale(body, E[0]))


# ---------------------------------------------------------------------------------------------------------------------
# The compiled right-hand side, generated from body_frame_rhs


class _Traced:
    """A value in a straight-line trace: each arithmetic operation appends one assignment to ``lines``."""

    def __init__(self, name, lines):
        self.name, self.lines = name, lines

    def _emit(self, expr):
        name = f"t{len(self.lines)}"
        self.lines.append(f"    {name} = {expr}")
        return _Traced(name, self.lines)

    def _bin(self, a, op, b):
        return self._emit(f"{_operand(a)} {op} {_operand(b)}")

    def __add__(self, other):
        return self._bin(self, "+", other)

    def __radd__(self, other):
        return self._bin(other, "+", self)

    def __sub__(self, other):
        return self._bin(self, "-", other)

    def __rsub__(self, other):
        return self._bin(other, "-", self)

    def __mul__(self, other):
        return self._bin(self, "*", other)

    def __rmul__(self, other):
        return self._bin(other, "*", self)

    def __truediv__(self, other):
        return self._bin(self, "/", other)

    def __rtruediv__(self, other):
        return self._bin(other, "/", self)

    def __neg__(self):
        return self._emit(f"-{self.name}")


def _operand(v):
    """A traced value's name, or a number constant written exactly."""
    return v.name if isinstance(v, _Traced) else f"({float(v)!r})"


def _trace():
    """Straight-line statements of body_frame_rhs and of turning_point_function on y[0..10], p[0..4]:
    ((statements, output names) of the right-hand side, (statements, output name) of dγ3/dt)."""
    lines = []
    y = [_Traced(f"y[{i}]", lines) for i in range(STATE_SIZE)]
    p = [_Traced(f"p[{i}]", lines) for i in range(5)]
    out = body_frame_rhs(y, p)
    rhs = (lines, [v.name for v in out])
    lines = []
    y = [_Traced(f"y[{i}]", lines) for i in range(STATE_SIZE)]
    tp = (lines, turning_point_function(y).name)
    return rhs, tp


def traced_source():
    """Python source of ``rhs(dy, t, y, p)`` (writes dy) and ``tp(t, y, p)`` (dγ3/dt), for numba."""
    (rhs, out), (tp, root) = _trace()
    return "\n".join(["def rhs(dy, t, y, p):", *rhs, *(f"    dy[{i}] = {v}" for i, v in enumerate(out)), "", "",
                      "def tp(t, y, p):", *tp, f"    return {root}", ""])


def cython_source():
    """Cython source of a module calling CyRK's C++ DOP853 (cysolve_ivp) with the traced right-hand side and dγ3/dt
    as a compiled event: ``run(y0, p, t_end, rtol, atol, grid) -> (event times, steps, dense output on grid)``."""
    (rhs, out), (tp, root) = _trace()
    rhs = [line.replace("    t", "    cdef double t", 1) for line in rhs]
    tp = [line.replace("    t", "    cdef double t", 1) for line in tp]
    return "\n".join([
        "# distutils: language = c++",
        "# cython: boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False, language_level=3",
        "# Generated by benchmarks/bench_integrate.py from rocknroller.analysis.model.equations; do not edit.",
        "from libcpp.vector cimport vector",
        "from libcpp.limits cimport numeric_limits",
        "from CyRK.cy.common cimport PreEvalFunc",
        "from CyRK.cy.events cimport Event",
        "from CyRK.cy.cysolver_api cimport cysolve_ivp_noreturn, WrapCySolverResult, ODEMethod, CySolverResult",
        "import numpy as np",
        "",
        "cdef void rhs(double* dy, double t, double* y, char* args, PreEvalFunc pre_eval) noexcept nogil:",
        "    cdef double* p = <double*>args",
        *rhs, *(f"    dy[{i}] = {v}" for i, v in enumerate(out)),
        "",
        "cdef double tp(double t, double* y, char* args) noexcept nogil:",
        *tp, f"    return {root}",
        "",
        "def rhs_eval(double[::1] y, double[::1] p):",
        "    out = np.empty(y.shape[0])",
        "    cdef double[::1] dy = out",
        "    rhs(&dy[0], 0.0, &y[0], <char*>&p[0], NULL)",
        "    return out",
        "",
        "def tp_eval(double[::1] y, double[::1] p):",
        "    return tp(0.0, &y[0], <char*>&p[0])",
        "",
        "def run(double[::1] y0, double[::1] p, double t_end, double rtol, double atol, double[::1] grid):",
        "    cdef size_t i",
        "    cdef vector[double] y0_vec = vector[double](y0.shape[0])",
        "    for i in range(<size_t>y0.shape[0]):",
        "        y0_vec[i] = y0[i]",
        "    cdef vector[char] args_vec = vector[char](p.shape[0] * sizeof(double))",
        "    cdef double* args_ptr = <double*>args_vec.data()",
        "    for i in range(<size_t>p.shape[0]):",
        "        args_ptr[i] = p[i]",
        "    cdef vector[Event] events_vec = vector[Event]()",
        "    events_vec.emplace_back(tp, numeric_limits[size_t].max(), 0)  # every root, either direction",
        "    cdef WrapCySolverResult solution = WrapCySolverResult()",
        "    solution.build_cyresult(ODEMethod.DOP853)",
        "    cdef CySolverResult* ptr = solution.cyresult_uptr.get()",
        "    cdef vector[double] no_t_eval = vector[double]()",
        "    # (solution, diffeq, t0, t1, y0, rtol, atol, args, num_extra, max_num_steps, max_ram_MB, dense_output,",
        "    #  t_eval, pre_eval_func, events)",
        "    cysolve_ivp_noreturn(ptr, rhs, 0.0, t_end, y0_vec, rtol, atol, args_vec, 0, 0, 2000, grid.shape[0] > 0,",
        "                         no_t_eval, NULL, events_vec)",
        "    solution.finalize()",
        "    if not ptr.success:",
        "        raise RuntimeError('CyRK cysolve_ivp DOP853 failed: ' + solution.message)",
        "    roots = np.array([ptr.event_times[0][i] for i in range(ptr.event_times[0].size())])",
        "    dense = solution.call_vectorize(grid).T if grid.shape[0] > 0 else None",
        "    return roots, ptr.steps_taken, dense",
        ""])


def build_cysolve(body):
    """Build (or load from the rocknroller cache) the Cython module of :func:`cython_source`.

    Returns (run, seconds spent building or loading, True if built now) or (None, why not, None)."""
    import hashlib
    import importlib.util
    import sys
    import sysconfig

    try:
        import CyRK
        from Cython.Build import cythonize
        from setuptools import Distribution, Extension
    except ImportError as exc:
        return None, f"CyRK cysolve_ivp row skipped: {exc} (it needs CyRK, Cython and a C++ compiler)", None
    from rocknroller.numerics.cache import cache_dir

    t0 = time.perf_counter()
    source = cython_source()
    key = hashlib.sha256("\0".join([source, CyRK.__version__, np.__version__, sys.version,
                                     sysconfig.get_platform()]).encode()).hexdigest()[:16]
    name = f"fig5_cysolve_{key}"
    folder = cache_dir() / "bench" / name
    built = sorted(folder.glob(f"{name}*{sysconfig.get_config_var('EXT_SUFFIX')}"))
    fresh = not built
    if fresh:
        try:
            folder.mkdir(parents=True, exist_ok=True)
            (folder / f"{name}.pyx").write_text(source)
            ext = Extension(name, [str(folder / f"{name}.pyx")], include_dirs=[*CyRK.get_include(), np.get_include()],
                            language="c++", extra_compile_args=["-O2", "-std=c++20", "-w"])
            dist = Distribution({"ext_modules": cythonize([ext], quiet=True, build_dir=str(folder))})
            cmd = dist.get_command_obj("build_ext")
            cmd.build_lib, cmd.build_temp = str(folder), str(folder / "build")
            cmd.ensure_finalized()
            cmd.run()
        except Exception as exc:  # no compiler, no headers, an incompatible CyRK: skip the row, say why
            return None, f"CyRK cysolve_ivp row skipped: building its module failed ({type(exc).__name__}: {exc})", None
        built = sorted(folder.glob(f"{name}*{sysconfig.get_config_var('EXT_SUFFIX')}"))
    spec = importlib.util.spec_from_file_location(name, built[0])
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    worst = check_generated(body, module.rhs_eval, module.tp_eval)
    return (module.run, worst), time.perf_counter() - t0, fresh


def check_generated(body, rhs, tp):
    """Largest relative difference between a generated right-hand side ``rhs(y, p) -> dy`` and body_frame_rhs at
    1000 random states; raises if it exceeds 1e-14 or if ``tp(y, p)`` differs from turning_point_function."""
    rng = np.random.default_rng(2024)
    p = np.asarray(body.params, float)
    worst = 0.0
    for _ in range(1000):
        yy = rng.normal(size=STATE_SIZE)
        yy[0:3] /= np.linalg.norm(yy[0:3])
        ref = np.array(body_frame_rhs(yy, p))
        worst = max(worst, float(np.max(np.abs(rhs(yy, p) - ref) / np.maximum(np.abs(ref), 1e-300))))
        if tp(yy, p) != turning_point_function(yy):
            raise RuntimeError("generated dγ3/dt differs from turning_point_function")
    if not worst <= 1e-14:
        raise RuntimeError(f"generated right-hand side differs from body_frame_rhs by {worst:.1e} (relative)")
    return worst


def build_cyrk(body):
    """Compile the CyRK runners; returns (runners, message) or (None, why not)."""
    try:
        import numba as nb
        from CyRK import __version__ as cyrk_version
        from CyRK import cyjit, nbsolve2_ivp, pysolve_ivp
    except ImportError as exc:
        return None, f"CyRK rows skipped: {exc} (pip install -e \".[bench]\" installs CyRK and numba)"

    namespace = {}
    exec(compile(traced_source(), "<traced body_frame_rhs>", "exec"), namespace)
    t0 = time.perf_counter()
    rhs_nj = nb.njit(namespace["rhs"])
    tp_nj = nb.njit(namespace["tp"])
    rhs_c = cyjit(namespace["rhs"])  # C callback: void(double* dy, double t, double* y, double* p)
    address = rhs_c.address

    # The generated right-hand side must agree with the library's before anything is timed.
    p = np.asarray(body.params, float)

    def rhs_eval(yy, pp):
        dy = np.empty(STATE_SIZE)
        rhs_nj(dy, 0.0, yy, pp)
        return dy

    worst = check_generated(body, rhs_eval, lambda yy, pp: tp_nj(0.0, yy, pp))

    @nb.njit
    def compiled_run(y0, p, t_end, rtol, atol, dense_check):
        """nbsolve2_ivp DOP853 with dense output, then the turning points: sign changes of dγ3/dt between steps,
        each refined on the dense output (Illinois regula falsi to 4 ulp of t).  Returns (roots, directions,
        final state, steps, the dense output on dense_check)."""
        sol = nbsolve2_ivp(address, (0.0, t_end), y0, method="DOP853", dense_output=True, args=p, rtol=rtol,
                           atol=atol)
        if not sol.success:
            sol.free()
            raise RuntimeError("CyRK DOP853 failed")
        ts = sol.t
        ys = sol.y
        n = ts.size
        gs = ys[0, :] * ys[4, :] - ys[1, :] * ys[3, :]
        roots = np.empty(n)
        dirs = np.empty(n, dtype=np.int64)
        k = 0
        for i in range(n - 1):
            ga, gb = gs[i], gs[i + 1]
            if ga == 0.0 or ga * gb > 0.0:  # a root at a step point counts once, in the step that it ends
                continue
            a, b = ts[i], ts[i + 1]
            side = 0
            for _ in range(200):
                if b - a <= 4.0 * 2.220446049250313e-16 * max(1.0, abs(b)) or gb == 0.0:
                    break
                c = b - gb * (b - a) / (gb - ga)
                yc = sol.call(c)
                gc = yc[0, 0] * yc[4, 0] - yc[1, 0] * yc[3, 0]
                if gc * gb > 0.0:
                    b, gb = c, gc
                    if side == -1:
                        ga *= 0.5
                    side = -1
                elif gc * ga > 0.0:
                    a, ga = c, gc
                    if side == 1:
                        gb *= 0.5
                    side = 1
                else:
                    a = b = c
                    gb = 0.0
            roots[k] = b
            dirs[k] = 1 if gs[i + 1] > gs[i] else -1
            k += 1
        y_end = ys[:, n - 1].copy()
        steps = sol.steps_taken
        dense = sol.call_vectorize(dense_check).T.copy() if dense_check.size > 0 else np.empty((0, y0.size))
        sol.free()
        return roots[:k].copy(), dirs[:k].copy(), y_end, steps, dense

    y_test = np.array([0.1, 0.2, np.sqrt(0.95), 0.1, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0])
    compiled_run(y_test, p, 1.0, 1e-8, 1e-10, np.empty(0))  # compile once
    # pysolve_ivp reads an event's direction from its attributes; rising (+1) is a maximum of θ.
    tp_nj(0.0, y_test, p)
    rhs_nj(np.empty(STATE_SIZE), 0.0, y_test, p)
    t_jit = time.perf_counter() - t0
    return {"compiled_run": compiled_run, "pysolve_ivp": pysolve_ivp, "rhs_nj": rhs_nj, "tp_nj": tp_nj,
            "t_jit": t_jit, "worst": worst, "version": cyrk_version, "numba": nb.__version__}, None


# ---------------------------------------------------------------------------------------------------------------------


def heyoka_core(ta, y0, t_end):
    ta.time = 0.0
    ta.state[:] = y0
    ta.reset_cooldowns()
    ta.nt_events[0].callback.events.clear()
    ta.propagate_until(t_end)
    return [t for t, _ in ta.nt_events[0].callback.events]


def main() -> None:
    import heyoka as hy
    from scipy.integrate import solve_ivp

    body = Body.paper(1e-3)
    initial = fig5_start()
    y0 = np.asarray(initial.to_body_state(), float)
    p = np.asarray(body.params, float)
    grid = np.linspace(0.0, T_END, N_GRID)

    # heyoka's one-off costs: a compilation with its caches off, then a build from the on-disk cache (what every
    # later process pays).
    disk = hy.llvm_state.get_diskcache_enabled()
    hy.llvm_state.set_diskcache_enabled(False)
    hy.llvm_state.clear_memcache()
    t0 = time.perf_counter()
    _build_heyoka(float, float(np.finfo(float).eps), PARAM_COUNTS[0])  # the paper's form
    t_compile = time.perf_counter() - t0
    hy.llvm_state.set_diskcache_enabled(disk)
    heyoka_integrator()

    def from_disk():
        hy.llvm_state.clear_memcache()
        return _build_heyoka(float, float(np.finfo(float).eps), PARAM_COUNTS[0])  # the paper's form

    t_load, _ = best_of(from_disk) if disk else (math.nan, None)

    # Part 1: simulate() --------------------------------------------------------------------------------------------
    t_hy, tr_hy = best_of(lambda: simulate(body, initial, T_END), REPEATS_FAST)
    t_sc, tr_sc = best_of(lambda: simulate(body, initial, T_END, method="scipy"))
    print(f"figure-5 run, {T_END:g} time units, {len(tr_hy.maxima)} maxima + {len(tr_hy.minima)} minima")
    print("\n1. simulate() (integration, events, Trajectory)")
    print(f"{'backend':40s} {'time [s]':>10s} {'energy err':>11s}")
    print(f"{'heyoka (tol = eps)':40s} {t_hy:10.4f} {tr_hy.energy_rel_error:11.2e}")
    print(f"{'scipy DOP853 (rtol 3e-14)':40s} {t_sc:10.4f} {tr_sc.energy_rel_error:11.2e}")
    print(f"ratio scipy/heyoka: {t_sc / t_hy:.0f}x, at {tr_sc.energy_rel_error / tr_hy.energy_rel_error:.0f}x "
          "larger energy error for scipy")

    # Part 2: integration + turning points, equal energy error -------------------------------------------------------
    print(f"\n2. integration + turning points only, at equal energy error (max over a {N_GRID}-point grid of the "
          "dense output, scale E0 + g a)")
    y = hy.make_vars(*[f"y{i}" for i in range(STATE_SIZE)])
    pars = [hy.par[i] for i in range(5)]
    sys_ = list(zip(y, body_frame_rhs(y, pars)))

    def heyoka_ta(tol):
        return hy.taylor_adaptive(sys_, y0, pars=p, tol=tol,
                                  nt_events=[hy.nt_event(turning_point_function(y), _EventLog())])

    def heyoka_error(ta):
        ta.time = 0.0
        ta.state[:] = y0
        ta.reset_cooldowns()
        c_out = ta.propagate_until(T_END, c_output=True)[4]
        return energy_error(body, np.asarray(c_out(grid)))

    reference = np.sort(heyoka_core(heyoka_ta(np.finfo(float).eps), y0, T_END))
    reference = reference[reference > 0.0]

    def sc_fun(t, yy):  # the library's numpy right-hand side, called from Python
        return np.array(body_frame_rhs(yy, p))

    def sc_event(t, yy):
        return turning_point_function(yy)

    def sc_core(rtol, dense=False):
        sol = solve_ivp(sc_fun, (0.0, T_END), y0, method="DOP853", rtol=rtol, atol=DOP853_ATOL, events=[sc_event],
                        dense_output=dense)
        assert sol.success, sol.message
        return sol

    def sc_error(rtol):
        return energy_error(body, sc_core(rtol, dense=True).sol(grid).T)

    cyrk, why_not = build_cyrk(body)
    if cyrk is None:
        print(why_not)
        run = cysolve = None
        dop853_error = sc_error
        rtols = DOP853_RTOLS[::4]  # scipy is slow: a coarser scan
    else:
        run = cyrk["compiled_run"]
        print(f"CyRK {cyrk['version']} + numba {cyrk['numba']}: the generated right-hand side agrees with "
              f"body_frame_rhs to {cyrk['worst']:.1e} (relative) at 1000 random states")

        def dop853_error(rtol):
            return energy_error(body, run(y0, p, T_END, rtol, DOP853_ATOL, grid)[4])

        rtols = DOP853_RTOLS
        rhs_nj, tp_nj = cyrk["rhs_nj"], cyrk["tp_nj"]
        tp_nj.direction = 0  # pysolve_ivp reads an event's direction and terminal flag from its attributes
        tp_nj.terminal = False

        cysolve, t_cysolve, cysolve_fresh = build_cysolve(body)
        if cysolve is None:
            print(t_cysolve)
        else:
            cysolve, worst = cysolve
            print(f"CyRK cysolve_ivp module {'built' if cysolve_fresh else 'loaded from the cache'} in "
                  f"{t_cysolve:.2f} s; its right-hand side agrees with body_frame_rhs to {worst:.1e} (relative)")

        def py_core(rtol, dense=False):
            sol = cyrk["pysolve_ivp"](rhs_nj, (0.0, T_END), y0, method="DOP853", rtol=rtol, atol=DOP853_ATOL,
                                      args=(p,), pass_dy_as_arg=True, events=[tp_nj], dense_output=dense)
            assert sol.success, sol.message
            return sol

    # DOP853's energy error against rtol (CyRK's and scipy's DOP853 are the same method: scipy's, ported to C++).
    dop_scan = [(rtol, dop853_error(rtol)) for rtol in rtols]
    print(f"DOP853 rtol scan (atol {DOP853_ATOL:.0e}, {'CyRK numba' if run else 'scipy'}): "
          + ", ".join(f"{r:.1e} -> {e:.1e}" for r, e in dop_scan))

    rows = []
    for tol in HEYOKA_LEVELS:
        ta = heyoka_ta(tol)
        err_hy = heyoka_error(ta)
        t_hy_core, roots = best_of(lambda: heyoka_core(ta, y0, T_END), REPEATS_FAST)
        rtol, _ = min(dop_scan, key=lambda s: abs(math.log(s[1] / err_hy)))
        level = [(f"heyoka, tol {tol:.0e}", "yes: heyoka nt_event", t_hy_core, err_hy, roots)]
        t_sc_core, sol = best_of(lambda: sc_core(rtol))
        level.append((f"scipy DOP853, rtol {rtol:.1e}", "yes: solve_ivp events", t_sc_core, sc_error(rtol),
                      sol.t_events[0]))
        if run is not None:
            if cysolve is not None:
                t_cs, out = best_of(lambda: cysolve(y0, p, T_END, rtol, DOP853_ATOL, np.empty(0)), REPEATS_FAST)
                level.append((f"CyRK DOP853 compiled + events, rtol {rtol:.1e}", "yes: CyRK events, compiled", t_cs,
                              energy_error(body, cysolve(y0, p, T_END, rtol, DOP853_ATOL, grid)[2]), out[0]))
            t_cy, out = best_of(lambda: run(y0, p, T_END, rtol, DOP853_ATOL, np.empty(0)), REPEATS_FAST)
            level.append((f"CyRK DOP853 numba, rtol {rtol:.1e}", "no: sign changes refined after the run", t_cy,
                          dop853_error(rtol), out[0]))
            t_py, sol = best_of(lambda: py_core(rtol), REPEATS_FAST)
            level.append((f"CyRK DOP853 py + events, rtol {rtol:.1e}", "yes: CyRK events, Python callbacks", t_py,
                          energy_error(body, py_core(rtol, dense=True).call_vectorize(grid).T), sol.t_events[0]))
        rows.append(level)

    print(f"\n{'backend':44s} {'turning points':38s} {'time [s]':>9s} {'energy err':>10s} {'err/hy':>6s} "
          f"{'t/t_hy':>7s} {'count':>5s} {'max |dt|':>8s}")
    for level in rows:
        _, _, t_ref, err_ref, _ = level[0]
        for name, events, t, err, roots in level:
            # A start with θ̇ = 0 is a root of dγ3/dt at t = 0: heyoka and CyRK's events report it, simulate()
            # drops it, and so does this comparison.
            roots = np.sort(np.asarray(roots, float))
            roots = roots[roots > 0.0]
            dt = float(np.max(np.abs(roots - reference))) if len(roots) == len(reference) else math.nan
            flag = "" if 0.5 <= err / err_ref <= 2.0 else "  <- energy errors differ by more than 2x"
            print(f"{name:44s} {events:38s} {t:9.4f} {err:10.2e} {err / err_ref:6.2f} {t / t_ref:7.1f} "
                  f"{len(roots):5d} {dt:8.1e}{flag}")
        print()
    ta = heyoka_ta(np.finfo(float).eps)
    t_eps, _ = best_of(lambda: heyoka_core(ta, y0, T_END), REPEATS_FAST)
    print(f"heyoka at tol = eps: {t_eps:.4f} s, energy error {heyoka_error(ta):.2e}; DOP853 cannot get there: its "
          f"rtol stops at 100 eps ({dop_scan[0][0]:.1e} -> {dop_scan[0][1]:.2e})\n")
    print(f"times: best of {REPEATS} (scipy) or {REPEATS_FAST} (the others); count and max |dt|: turning points "
          f"against heyoka at tol = eps ({len(reference)} after t = 0)")
    print(f"one-off: heyoka compile {t_compile:.2f} s (once per machine), build from its disk cache "
          f"{1e3 * t_load:.0f} ms" + ("" if cyrk is None else f"; numba JIT of the CyRK runners {cyrk['t_jit']:.2f} s"
                                      " (once per process)")
          + ("" if cysolve is None else "; CyRK cysolve_ivp module "
             + ("built (once per machine)" if cysolve_fresh else "loaded from the cache") + f" {t_cysolve:.2f} s"))


if __name__ == "__main__":
    main()
