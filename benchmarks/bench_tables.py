"""What a user waits for the first time: the averaging tables' builds, and a first prediction from a start with
velocity (tables included) beside the direct ODE.

Run:  python benchmarks/bench_tables.py
In a fresh cache folder, CPU seconds (this process's, threads included, and its worker processes') and wall seconds
of: a release table
(θ0 = 0.95π), its second-order table with two processes (``rocknroller slow``'s default ``--processes 2``), the region
tables of a start with velocity on the spindle chart (a release at 0.3π) and on the band chart (the paper's fig. 8
start on Q_J,π^crit), and for that start the first prediction (its tables built) and a second one (tables cached)
against the direct ODE over the same 1000 time units.
"""

from __future__ import annotations

import math
import os
import tempfile
import time


def _cpu() -> float:
    """CPU seconds of this process and of its finished children (a build's worker processes)."""
    t = os.times()  # the children's in clock ticks (10 ms); this process's at the finer process_time
    return time.process_time() + t.children_user + t.children_system


def timed(fn):
    w, c = time.perf_counter(), _cpu()
    out = fn()
    return out, _cpu() - c, time.perf_counter() - w


def main() -> None:
    os.environ["ROCKNROLLER_CACHE"] = tempfile.mkdtemp(prefix="bench_tables_")
    import warnings

    from rocknroller.analysis.criticality.starts import critical_start
    from rocknroller.analysis.model.body import Body
    from rocknroller.analysis.model.equations import EulerState
    from rocknroller.analysis.slow import prediction as av
    from rocknroller.analysis.slow.map.family import first_maximum, rest_energy
    from rocknroller.analysis.slow.map.region import build_region_table
    from rocknroller.analysis.slow.map.second_order import build_second_order_table
    from rocknroller.numerics.integrate import simulate

    warnings.simplefilter("ignore")
    print(f"load average: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    sym, body = Body.paper(), Body.paper(1e-3)
    simulate(body, EulerState(0.95 * math.pi), 10.0)  # the compiled integrator, from heyoka's cache
    rows = [("release table, theta0 = 0.95pi (1 process)", *timed(lambda: av.build_table(sym, 0.95 * math.pi,
                                                                                         progress=False))[1:]),
            ("its second-order table (2 processes)",
             *timed(lambda: build_second_order_table(sym, 0.95 * math.pi, workers=2, progress=False))[1:]),
            ("region tables, spindle chart, E of a release at 0.3pi (1 process)",
             *timed(lambda: build_region_table(sym, rest_energy(sym, 0.3 * math.pi), progress=False))[1:])]
    start = critical_start(body, 0.95 * math.pi, math.pi / 4, "pi", psi_dot0=0.002).state()
    E = first_maximum(body, start).E
    rows.append(("region tables, band chart, fig. 8 start (1 process)",
                 *timed(lambda: build_region_table(sym, E, progress=False))[1:]))
    # the first prediction builds what it needs from an empty cache, memory included
    import shutil

    shutil.rmtree(os.environ["ROCKNROLLER_CACHE"])
    from rocknroller.analysis.slow.map import table as slow_table
    from rocknroller.numerics.cache import MemoryCache

    slow_table._TABLES = MemoryCache(slow_table.TABLE_CACHE_BYTES)
    _, c_first, w_first = timed(lambda: av.predict_slow_motion(body, start, t_end=1000.0, progress=False))
    _, c_again, w_again = timed(lambda: av.predict_slow_motion(body, start, t_end=1000.0, progress=False))
    _, c_ode, w_ode = timed(lambda: simulate(body, start, 1000.0, samples=False))
    rows += [("first prediction from the fig. 8 start (its tables built)", c_first, w_first),
             ("a second prediction (tables cached)", c_again, w_again),
             ("the direct ODE, same start, 1000 time units", c_ode, w_ode)]
    print(f"{'what':66s} {'CPU s':>9s} {'wall s':>9s}")
    for what, c, w in rows:
        print(f"{what:66s} {c:9.3g} {w:9.3g}")
    print(f"first prediction / ODE: {c_first / c_ode:.0f}x CPU; second prediction: ODE / map = {c_ode / c_again:.1f}x")


if __name__ == "__main__":
    main()
