"""What a user waits for the first time: the averaging tables' builds, and a first prediction from a start with
velocity (tables included) beside the direct ODE.

Run:  python benchmarks/bench_tables.py
In a fresh cache folder, CPU seconds (this process's, threads included, and its worker processes') and wall seconds
of: a release table
(θ0 = 0.95π), its second-order table in one process (CPU seconds, the measure the tables' cost is stated in), the region
tables of a start with velocity on the spindle chart (a release at 0.3π) and on the band chart (the paper's fig. 8
start on Q_J,π^crit), and for that start the first prediction (its tables built) and a second one (tables cached)
against the direct ODE over the same 1000 time units.  Before and after: k₂ at nodes of the second-order table by
the scalar path (one start's turning-point solve and one orbit per Θ_a, the chart's derivatives per point; kept as
the reference in tests/analysis/slow/map/test_second_order_batch.py) and by the batched path the build uses, on the same
nodes, one after the other in this process; and the fig. 8 start's band-chart tables built as the package builds them
(one orbit with three ε-responses per node, half the nodes: the mirror images follow by symmetry) and on the same
chart from every node's three orbits (the construction kept as the reference in
tests/analysis/slow/map/test_mirror_nodes.py), with the largest difference of their values.  The "before" row leaves
out the chart's own cost, which the build includes (its edge then took 183 evaluations of min U, now 22).
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


def k2_before_after(nodes: int = 4) -> tuple[float, float, float]:
    """CPU seconds per node of k₂'s harmonics by the scalar path (before) and the batched one (after) on the same
    ``nodes`` nodes of the release table at 0.95π, and their largest difference relative to each component's
    largest harmonic."""
    import sys
    from pathlib import Path

    import numpy as np

    from rocknroller.analysis.model.body import Body
    from rocknroller.analysis.slow.map.chart import cheb_nodes
    from rocknroller.analysis.slow.map.second_order import k2_harmonics_at
    from rocknroller.analysis.slow.map.table import load_or_build_table

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "analysis" / "slow" / "map"))
    from test_second_order_batch import _k2_harmonics_scalar

    table = load_or_build_table(Body.paper(), 0.95 * math.pi, progress=False)
    XI, ETA = np.meshgrid(cheb_nodes(64), cheb_nodes(6), indexing="ij")
    QR, QJ = table.chart(XI, ETA)
    picks = np.linspace(0, 31, nodes).astype(int)
    Q = np.array([(QR[i, k % 6], QJ[i, k % 6]) for k, i in enumerate(picks)])
    old, c_old, _ = timed(lambda: np.array([_k2_harmonics_scalar(table, q) for q in Q]))
    new, c_new, _ = timed(lambda: k2_harmonics_at(table, Q))
    diff = float((np.abs(new - old).max(axis=2) / np.abs(old).max(axis=2)).max())
    return c_old / nodes, c_new / nodes, diff


def region_before_after(E: float) -> tuple[float, float, float]:
    """CPU seconds of the band-chart region tables of energy E as built (after) and, on the same chart, from every
    node's three orbits (before; ``test_mirror_nodes._every_node``), and the largest difference of the two tables'
    values at the nodes relative to each function's largest (the functions that vanish by symmetry left out)."""
    import sys
    from pathlib import Path

    import numpy as np

    from rocknroller.analysis.model.body import Body
    from rocknroller.analysis.routh.turning_points import turning_points
    from rocknroller.analysis.slow.map.region import build_region_table, region_frame
    from rocknroller.analysis.slow.map.table import fit_table

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "analysis" / "slow" / "map"))
    from test_mirror_nodes import _every_node, _values

    sym = Body.paper()
    new, c_new, _ = timed(lambda: build_region_table(sym, E, progress=False))
    frame = region_frame(sym, E)

    def before():
        thX = np.asarray(turning_points(E, *frame.nodes(), sym)[1], float)
        return fit_table(frame, *_every_node(frame, thX))

    old, c_old, _ = timed(before)
    (a, scale), (b, _) = _values(new), _values(old)
    keep = scale > 1e-9 * scale.max()
    return c_old, c_new, float((np.abs(a - b).max(axis=(1, 2))[keep] / scale[keep]).max())


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
    c_old, c_new, diff = k2_before_after()
    rows = [("k2 per node of the second-order table: scalar path (before)", c_old, math.nan),
            ("k2 per node of the second-order table: batched (after)", c_new, math.nan),
            ("release table, theta0 = 0.95pi (1 process)", *timed(lambda: av.build_table(sym, 0.95 * math.pi,
                                                                                         progress=False))[1:]),
            ("its second-order table (1 process)",
             *timed(lambda: build_second_order_table(sym, 0.95 * math.pi, workers=1, progress=False))[1:]),
            ("region tables, spindle chart, E of a release at 0.3pi (1 process)",
             *timed(lambda: build_region_table(sym, rest_energy(sym, 0.3 * math.pi), progress=False))[1:])]
    start = critical_start(body, 0.95 * math.pi, math.pi / 4, "pi", psi_dot0=0.002).state()
    E = first_maximum(body, start).E
    r_old, r_new, r_diff = region_before_after(E)
    rows += [("region tables, band chart, fig. 8 start: every node's 3 orbits (before)", r_old, math.nan),
             ("region tables, band chart, fig. 8 start (1 process)", r_new, math.nan)]
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
        print(f"{what:66s} {c:9.3g} {'-' if math.isnan(w) else f'{w:9.3g}':>9s}")
    print(f"first prediction / ODE: {c_first / c_ode:.0f}x CPU; second prediction: ODE / map = {c_ode / c_again:.1f}x")
    print(f"k2 per node, scalar / batched: {c_old / c_new:.1f}x CPU; largest difference {diff:.1e} of each component's "
          "largest harmonic")
    print(f"region tables, band chart, every node's 3 orbits / as built: {r_old / r_new:.2f}x CPU (the chart not "
          f"counted before); largest difference of their values {r_diff:.1e} of each function's largest")


if __name__ == "__main__":
    main()
