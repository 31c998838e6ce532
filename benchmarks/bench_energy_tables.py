"""The tables over energy against today's per-energy tables, side by side: the build once per body, the first
prediction at a release angle never used before, an atlas over θ0 at order 2, and the error at the build's checks.

Run:  python benchmarks/bench_energy_tables.py [--atlas-rows 40]
Each command runs in its own process as a user types it (``python -m rocknroller.cli ...``), its CPU seconds those of
the child and its workers (``resource.getrusage(RUSAGE_CHILDREN)``).  Two fresh table caches (temporary
``ROCKNROLLER_CACHE``; heyoka's disk cache warm): in one, ``rocknroller warm --tables`` builds the tables over energy
of the paper body; the other has none, as today.  The rows:

* the build, ``warm --tables`` (2 processes), against one per-energy build of the release and second-order tables at
  a θ0 (``slow --order 2`` in the empty cache, below): how many release angles the build is worth;
* ``slow --order 2 --processes 1`` at θ0 = 0.9137π (no node of either table), in each cache: the first prediction at
  a new energy with the tables over energy against building its tables; and the table's own cost in process
  (``release_tables`` at a second new θ0 after a first prediction has loaded everything); both again with one
  OpenBLAS thread (``OPENBLAS_NUM_THREADS=1``): on these small products OpenBLAS's second thread spins while it
  waits, which numpy's process time counts, and gains no wall time;
* ``atlas --order 2`` over --atlas-rows × 40 (θ0, ψ0), θ0 in [0.8π, 0.98π], ψ0 in [0.05, 1.5], ε = 1e-3, 1000 time units,
  no confirmation, with the tables over energy, beside the same atlas over 4 rows of each kind: per-energy tables
  built for each row against the tables over energy.
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time

CLI = [sys.executable, "-m", "rocknroller.cli"]
NEW = "0.9137pi"
#: Another new release angle, for the run with one BLAS thread (OPENBLAS_NUM_THREADS=1).
NEW_ONE_THREAD = "0.9059pi"
IN_PROCESS = ("import math, time, warnings, rocknroller as rr; "
              "from rocknroller.analysis.slow.map.tables_at_once import release_tables; "
              "warnings.simplefilter('ignore'); b = rr.Body.paper(1e-3); "
              "rr.predict_slow_motion(b, 0.9211 * math.pi, 0.5, 100.0, order=2); "
              "c = time.process_time(); release_tables(b, 0.9313 * math.pi, 2); print(time.process_time() - c)")


def measure(argv: list[str], cache: str, **env: str) -> tuple[float, float, str]:
    """(CPU seconds, wall seconds, stdout) of ``argv`` in a child process with the table cache ``cache`` (and the
    variables ``env``), which writes and reads Python's bytecode cache as a regular install does."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    child = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    out = subprocess.run(argv, capture_output=True, text=True,
                         env=dict(child, MPLBACKEND="Agg", ROCKNROLLER_CACHE=cache, **env))
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode:
        raise RuntimeError(f"{' '.join(argv)} failed ({out.returncode}):\n{out.stderr[-2000:]}")
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), wall, out.stdout


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--atlas-rows", type=int, default=40, help="rows of the large atlas (default 40)")
    args = parser.parse_args()
    print(f"load average: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; heyoka's disk cache warm")
    slow = CLI + ["slow", "--theta0", NEW, "--psi0", "0.5", "--eps", "1e-3", "--order", "2", "--processes", "1",
                  "--quiet"]

    def atlas(rows: int, out: str) -> list[str]:
        return CLI + ["atlas", "--theta0", f"0.8pi:0.98pi:{rows}", "--psi0", "0.05:1.5:40", "--eps", "1e-3",
                      "--order", "2", "--confirm-every", "0", "--processes", "1", "--quiet", "--out", out]

    with tempfile.TemporaryDirectory(prefix="bench_energy_") as tmp:
        over, per = os.path.join(tmp, "over-energy"), os.path.join(tmp, "per-energy")
        rows = []
        build, build_wall, said = measure(CLI + ["warm", "--tables", "--processes", "2", "--quiet"], over)
        first_per, wall_per, _ = measure(slow, per)
        first_over, wall_over, _ = measure(slow, over)
        slow_one = [NEW_ONE_THREAD if a == NEW else a for a in slow]
        first_one, wall_one, _ = measure(slow_one, over, OPENBLAS_NUM_THREADS="1")
        again_per, _, _ = measure(slow, per)
        inside = float(measure([sys.executable, "-c", IN_PROCESS], over)[2].split()[-1])
        inside_one = float(measure([sys.executable, "-c", IN_PROCESS], over, OPENBLAS_NUM_THREADS="1")[2].split()[-1])
        small_per, _, _ = measure(atlas(4, os.path.join(tmp, "a1")), per)
        small_over, _, _ = measure(atlas(4, os.path.join(tmp, "a2")), over)
        large, large_wall, _ = measure(atlas(args.atlas_rows, os.path.join(tmp, "a3")), over)
        rows += [
            ("warm --tables (2 processes), empty table cache", build, build_wall,
             f"asked: <= 300 s CPU; = {build / first_per:.0f} first predictions at new energies, per energy"),
            (f"slow --order 2 at {NEW}, first: per-energy tables built", first_per, wall_per, ""),
            (f"slow --order 2 at {NEW}, first: tables over energy", first_over, wall_over,
             f"asked: <= 1.5 s CPU; per energy / over energy {first_per / first_over:.1f}x"),
            (f"slow --order 2 at {NEW_ONE_THREAD}, first: tables over energy, 1 BLAS thread", first_one, wall_one,
             f"/ OpenBLAS's default threads: {first_one / first_over:.2f}x CPU, {wall_one / wall_over:.2f}x wall"),
            (f"slow --order 2 at {NEW}, again: per-energy tables cached", again_per, None,
             f"/ over energy, first: {again_per / first_over:.2f}x"),
            ("a new theta0's tables, in process (release_tables, order 2)", inside, None, "asked: <= 0.1 s"),
            ("the same, 1 BLAS thread (OPENBLAS_NUM_THREADS=1)", inside_one, None,
             f"/ default threads: {inside_one / inside:.2f}x CPU"),
            ("atlas --order 2, 4 x 40, per-energy tables built", small_per, None, ""),
            ("atlas --order 2, 4 x 40, tables over energy", small_over, None,
             f"per energy / over energy {small_per / small_over:.1f}x"),
            (f"atlas --order 2, {args.atlas_rows} x 40, tables over energy", large, large_wall, "asked: <= 60 s CPU"),
        ]
        print(f"{'what':<66} {'CPU s':>7} {'wall s':>7}  ratio")
        for what, cpu, wall, note in rows:
            print(f"{what:<66} {cpu:7.2f} {'-' if wall is None else f'{wall:7.2f}':>7}  {note}")
        print(f"the build's own checks: {said.strip().splitlines()[-1].split(': ', 1)[-1]}")
    print(f"load average: {os.getloadavg()[0]:.2f} at the end")


if __name__ == "__main__":
    main()
