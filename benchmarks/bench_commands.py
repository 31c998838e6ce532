"""What a user waits for at the command line: the first run of each command at a new energy, from an empty table
cache, beside the same command again with its tables cached; and the first chaos call with heyoka's disk cache warm
and cold.

Run:  python benchmarks/bench_commands.py [--no-compile]
Each command runs in its own process, as a user types it (``python -m rocknroller.cli ...``), its CPU seconds those
of the finished child and its workers (``resource.getrusage(RUSAGE_CHILDREN)``, user + system) and its wall seconds
around it.  heyoka's disk cache (``HEYOKA_CACHE_DIR``) is warm for every row but the cold chaos call: ``rocknroller
warm`` runs first, untimed.  Each "first" row starts from an empty table cache (a fresh temporary
``ROCKNROLLER_CACHE``): it builds every averaging table it needs; its "again" row reruns the same command on the
tables the first one left.  The rows:

* ``slow`` released from rest at a new energy (θ0 = 0.93π, ε = 5e-3, ψ0 = 0.3) at order 1 and at order 2, in one
  process (``--processes 1``);
* ``slow --statistics 32`` (the map's ensemble of 32 releases) against ``slow --statistics 0``, tables cached;
* ``portrait`` and ``bifurcation`` with their defaults (orders, grids: what a user gets without options);
* ``reproduce`` (every figure and table of the paper) into a temporary folder;
* the first chaos call, :func:`rocknroller.direct_chaos_indicators` over 300 time units from rest at 0.95π in a new
  Python process, with heyoka's disk cache warm and cold (a fresh temporary ``HEYOKA_CACHE_DIR``: the double-precision
  and the variational integrators are compiled, once; ``--no-compile`` leaves this row out), beside the floor of
  every command, ``import rocknroller``.
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CLI = [sys.executable, "-m", "rocknroller.cli"]
#: ``slow`` from rest at an energy of its own (θ0 = 0.93π, between the paper's 0.9π and 0.95π); default t_end.
SLOW = ["slow", "--theta0", "0.93pi", "--eps", "5e-3", "--psi0", "0.3", "--quiet"]
CHAOS = ("import math, rocknroller as rr; rr.direct_chaos_indicators(rr.Body.paper(epsilon=1e-3), "
         "rr.EulerState(theta=0.95 * math.pi, psi=math.pi / 4), 300.0)")


def measure(argv: list[str], **env: str) -> tuple[float, float, str]:
    """(CPU seconds, wall seconds, stderr) of one run of ``argv`` in a child process with ``env`` added to this one's;
    a failed run raises with its stderr."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    out = subprocess.run(argv, capture_output=True, text=True, env=dict(os.environ, MPLBACKEND="Agg", **env))
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode:
        raise RuntimeError(f"{' '.join(argv)} failed ({out.returncode}):\n{out.stderr[-2000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, wall, out.stderr


def first_and_again(args: list[str], out_option: str | None = None) -> tuple[tuple[float, float], tuple[float, float]]:
    """The command ``rocknroller args`` from an empty table cache, then again on the tables it left (each into a new
    temporary folder given as ``out_option`` when the command writes files)."""
    with tempfile.TemporaryDirectory(prefix="bench_commands_") as tmp:
        runs = []
        for k in range(2):
            out = [out_option, str(Path(tmp) / f"out{k}")] if out_option else []
            runs.append(measure([*CLI, *args, *out], ROCKNROLLER_CACHE=str(Path(tmp) / "tables"))[:2])
    return runs[0], runs[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-compile", action="store_true",
                        help="leave out the chaos call with a cold heyoka cache (it compiles two integrators)")
    args = parser.parse_args()
    measure([*CLI, "warm"])  # heyoka's disk cache: every integrator compiled or loaded, untimed
    load = os.getloadavg()[0]
    rows: list[tuple[str, float, float, str]] = []

    def pair(label: str, command: list[str], out_option: str | None = None, asked: str = "") -> None:
        (c1, w1), (c2, w2) = first_and_again(command, out_option)
        rows.append((f"{label}: first, empty table cache", c1, w1, asked))
        rows.append((f"{label}: again, tables cached", c2, w2, f"first / again {c1 / c2:.1f}x CPU"))

    pair("slow --order 1 (theta0 0.93pi, 1 process)", [*SLOW, "--order", "1", "--processes", "1"])
    pair("slow --order 2 (theta0 0.93pi, 1 process)", [*SLOW, "--order", "2", "--processes", "1"],
         asked="asked: <= 25 s CPU")
    with tempfile.TemporaryDirectory(prefix="bench_commands_") as tmp:
        cache = str(Path(tmp) / "tables")
        measure([*CLI, *SLOW, "--statistics", "0"], ROCKNROLLER_CACHE=cache)  # the tables, untimed
        c0, w0, _ = measure([*CLI, *SLOW, "--statistics", "0"], ROCKNROLLER_CACHE=cache)
        c32, w32, _ = measure([*CLI, *SLOW, "--statistics", "32"], ROCKNROLLER_CACHE=cache)
    rows += [("slow --statistics 0 (the point prediction alone), tables cached", c0, w0, ""),
             ("slow --statistics 32, tables cached", c32, w32, f"/ --statistics 0: {c32 / c0:.1f}x CPU")]
    pair("portrait, its defaults", ["portrait", "--quiet"], "--out")
    pair("bifurcation, its defaults", ["bifurcation", "--quiet"], "--out")
    pair("reproduce (every figure and table)", ["reproduce", "--quiet"], "--out")
    c_import, w_import, _ = measure([sys.executable, "-c", "import rocknroller"])
    c_warm, w_warm, _ = measure([sys.executable, "-c", CHAOS])
    rows += [("import rocknroller (the floor of every command)", c_import, w_import, ""),
             ("first chaos call, new process, heyoka cache warm", c_warm, w_warm, f"/ import {c_warm / c_import:.1f}x")]
    notes: list[str] = []
    if not args.no_compile:
        with tempfile.TemporaryDirectory(prefix="bench_commands_heyoka_") as tmp:
            c_cold, w_cold, err = measure([sys.executable, "-c", CHAOS], HEYOKA_CACHE_DIR=tmp)
        rows.append(("first chaos call, new process, heyoka cache cold", c_cold, w_cold,
                     f"/ warm {c_cold / c_warm:.0f}x CPU"))
        notes = [line for line in err.splitlines() if line.startswith("rocknroller: compiling")]
    print(f"load average {load:.2f} at the start on {os.cpu_count()} cores; heyoka's disk cache warm (rocknroller "
          "warm, untimed) but where it says cold; CPU: the child process and its workers")
    print(f"{'what':70s} {'CPU s':>7s} {'wall s':>7s}  ratio")
    for what, c, w, ratio in rows:
        print(f"{what:70s} {c:7.2f} {w:7.2f}  {ratio}")
    if not args.no_compile:
        print("the cold chaos call's notes on stderr:" + "".join(f"\n  {line}" for line in notes or ["(none)"]))
    print(f"load average {os.getloadavg()[0]:.2f} at the end")


if __name__ == "__main__":
    main()
