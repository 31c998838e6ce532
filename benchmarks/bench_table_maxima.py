"""The first prediction from a start with velocity at a new energy (its region tables built), before and after issue
24 item 5, side by side in one process.

Run:  python benchmarks/bench_table_maxima.py

The tables' orbits run maximum to maximum in the lanes of heyoka's batch integrator with their variational equations
(analysis/slow/map/orbit.py).  Before issue 24 each orbit's next θ-maximum was found by a Python loop over single steps
(``tb.step``, the sign of dγ3/dt checked after each) and a Newton iteration per lane on the step's dense output; now
each lane stops at its own next maximum, a terminal event of the batch integrator.  "Before" is that loop, kept here
(and only here) as it was, on an integrator without the event; both build the fig. 8 start's region tables from an
empty cache, in this process, one after the other.  Also reported: the orbits alone (``first_order_steps`` on 512
starts), and the largest difference between the two tables' values relative to their size.
"""

from __future__ import annotations

import math
import os
import shutil
import tempfile
import time
import warnings
from typing import Any

import numpy as np


def old_to_next_maxima(order: int, sym: Any, x0: np.ndarray, lanes: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The step loop of rocknroller before issue 24 (analysis/slow/map/orbit.py at ccb3b7c), verbatim but for the
    integrator, built here without the terminal event."""
    import heyoka as hy

    from rocknroller.analysis.model.equations import turning_point_function
    from rocknroller.analysis.slow.map import orbit as so

    key = ("old", order)
    if key not in _OLD:
        eqs = so._system(order)
        width = int(hy.recommended_simd_size())
        _OLD[key] = hy.taylor_adaptive_batch(eqs, np.zeros((len(eqs), width)), pars=np.zeros((5, width)),
                                             compact_mode=True)
    tb = _OLD[key]
    lanes, n = tb.batch_size, x0.shape[1]
    t1, out = np.empty(n), np.empty_like(x0)
    p0 = sym.params
    for first in range(0, n, lanes):
        take = np.minimum(np.arange(first, first + lanes), n - 1)
        tb.set_time(np.zeros(lanes))
        tb.state[:] = x0[:, take]
        tb.pars[:] = np.array([sym.a, sym.I1, sym.I3, sym.g, 0.0])[:, None]
        h_prev = turning_point_function(x0[:11, take])
        passed_min, done = np.zeros(lanes, bool), np.zeros(lanes, bool)
        for _ in range(100000):
            t_start = np.array(tb.time)
            tb.step(write_tc=True)
            hv = turning_point_function(tb.state[:11])
            passed_min |= (h_prev > 0.0) & (hv <= 0.0)
            for k in np.flatnonzero(passed_min & (h_prev < 0.0) & (hv >= 0.0) & ~done):
                times = np.array(tb.time)
                t = old_maximum_in_step(tb, times, int(k), float(t_start[k]), p0)
                times[k] = t
                tb.update_d_output(times)
                if first + k < n:
                    t1[first + k], out[:, first + k] = t, tb.d_output[:, k]
                done[k] = True
            if done.all():
                break
            h_prev = hv
    return t1, out


def old_maximum_in_step(tb: Any, times: np.ndarray, k: int, t_start: float, p0: Any) -> float:
    from rocknroller.analysis.model.equations import body_frame_rhs, turning_point_function
    from rocknroller.analysis.slow.map.family import directional_derivative

    lo, hi = t_start, float(times[k])
    t = hi
    for _ in range(200):
        times[k] = t
        tb.update_d_output(times)
        Y = np.array(tb.d_output[:11, k])
        h = turning_point_function(Y)
        if h < 0.0:
            lo = t
        else:
            hi = t
        slope = float(directional_derivative(turning_point_function, Y, np.array(body_frame_rhs(Y, p0))))
        new = t - h / slope if slope > 0.0 else math.nan
        if not lo <= new <= hi:
            new = 0.5 * (lo + hi)
        dt, t = new - t, new
        if abs(dt) <= 4e-16 * t or hi - lo <= 4e-16 * hi:
            return t
    raise RuntimeError("not located")


_OLD: dict[Any, Any] = {}


def cpu() -> float:
    return time.process_time()


def main() -> None:
    warnings.simplefilter("ignore")
    os.environ["ROCKNROLLER_CACHE"] = tempfile.mkdtemp(prefix="bench_table_maxima_")
    from rocknroller.analysis.criticality.starts import critical_start
    from rocknroller.analysis.model.body import Body
    from rocknroller.analysis.slow import prediction as av
    from rocknroller.analysis.slow.map import harmonic
    from rocknroller.analysis.slow.map import orbit as so
    from rocknroller.analysis.slow.map import table as slow_table
    from rocknroller.analysis.slow.map.family import rest_energy
    from rocknroller.numerics.cache import MemoryCache

    body = Body.paper(1e-3)
    start = critical_start(body, 0.95 * math.pi, math.pi / 4, "pi", psi_dot0=0.002).state()
    new_impl = so._to_next_maxima
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")

    # the orbits alone: 512 first-order steps
    sym = body.symmetric()
    E = rest_energy(sym, 0.9 * math.pi)
    rng = np.random.default_rng(0)
    QR, QJ, psi = rng.uniform(-0.02, 0.02, 512), rng.uniform(-0.02, 0.02, 512), rng.uniform(0, math.pi, 512)
    results = {}
    for label, impl in (("before", old_to_next_maxima), ("after", new_impl)):
        so._to_next_maxima = impl
        so.first_order_steps(body, E, QR[:8], QJ[:8], psi[:8])  # compiled, outside the timing
        c = cpu()
        results[label] = (so.first_order_steps(body, E, QR, QJ, psi), cpu() - c)
    step_b, c_b = results["before"]
    step_a, c_a = results["after"]
    diff = max(float(np.max(np.abs(np.asarray(step_a.d[k]) - np.asarray(step_b.d[k])) / np.max(np.abs(step_b.d[k]))))
               for k in step_b.d)
    print(f"512 first-order steps: before {c_b:.3f} s CPU, after {c_a:.3f} s: {c_b / c_a:.2f}x; largest difference of "
          f"their eps-derivatives relative to their size {diff:.1e}")

    rows = []
    for label, impl in (("before", old_to_next_maxima), ("after", new_impl)):
        so._to_next_maxima = harmonic._to_next_maxima = impl  # the tables' nodes run through harmonic_steps
        shutil.rmtree(os.environ["ROCKNROLLER_CACHE"], ignore_errors=True)
        slow_table._TABLES = MemoryCache(slow_table.TABLE_CACHE_BYTES)
        c, w = cpu(), time.perf_counter()
        pred = av.predict_slow_motion(body, start, t_end=1000.0, progress=False)
        rows.append((label, cpu() - c, time.perf_counter() - w, pred))
    so._to_next_maxima = harmonic._to_next_maxima = new_impl
    (_, c_b, w_b, p_b), (_, c_a, w_a, p_a) = rows
    print(f"first prediction from the fig. 8 start, its tables built (1 process): before {c_b:.1f} s CPU "
          f"({w_b:.1f} s wall), after {c_a:.1f} s CPU ({w_a:.1f} s wall): {c_b / c_a:.2f}x CPU")
    print(f"the two predictions' Q_R at the maxima differ by at most {np.max(np.abs(p_a.series.QR - p_b.series.QR)):.1e} "
          f"(extent {p_b.QR_extent:.3e}), their slow periods {p_b.slow_period!r} and {p_a.slow_period!r}")


if __name__ == "__main__":
    main()
