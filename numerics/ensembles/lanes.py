"""How many lanes ``run_ensemble`` uses by default: heyoka's recommendation, or the width measured faster here.

heyoka recommends a batch width for the CPU (:func:`~rocknroller.numerics.ensembles.batch.batch_width`), but the
width that runs an ensemble fastest is not always that one: on an AVX2-only machine 4 and 8 lanes measured the same
(2.2-2.6× the scalar loop), while on an AVX-512 machine whose heyoka recommends 4, 8 lanes took 7.1 ms of CPU per
trajectory against 8.0 ms (32 jobs of 1000 time units, benchmarks/bench_ensemble.py's case).  A job's results do not
depend on the width (:mod:`~rocknroller.numerics.ensembles.batch`: the same bit for bit in any lane and at any width),
so the width is free to follow the measurement.

:func:`measure_lanes` (run by ``rocknroller warm``) times the widths ``LANE_CANDIDATES`` side by side on a fixed
ensemble and records the choice of :func:`choose_lanes` in the cache directory, keyed by heyoka's version and the
CPU's model and flags; :func:`default_lanes` reads it, and falls back to heyoka's recommendation when there is no
record for this machine (or the record fails its check: it is a plain array file, :mod:`rocknroller.numerics.cache`).
"""

from __future__ import annotations

import hashlib
import math
import platform
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Mapping

import numpy as np

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.numerics.cache import CacheWarning, cache_dir, load_arrays, save_arrays
from rocknroller.numerics.ensembles.batch import MAX_LANES, MIN_LANES, batch_width, run_batch

__all__ = ["LANE_CANDIDATES", "LANE_MARGIN", "MAX_MEASURE_JOBS", "MAX_MEASURE_T_END", "LaneChoice", "choose_lanes",
           "machine_key", "default_lanes", "measure_lanes"]

#: The widths compared: those heyoka recommends for AVX2 (4) and AVX-512 (8) double precision.
LANE_CANDIDATES = (4, 8)
#: Another width replaces the recommended one only when faster by more than this fraction: the spread of the best of
#: three interleaved rounds on a quiet machine is ≈ 2 % (benchmarks/bench_ensemble.py), so equal widths stay equal.
LANE_MARGIN = 0.05
#: Rounds of :func:`measure_lanes`, interleaved over the widths; the best of them counts.
_ROUNDS = 3
#: Largest ensemble :func:`measure_lanes` times (jobs), and longest run (time units): about 1 ms of CPU a time unit.
MAX_MEASURE_JOBS, MAX_MEASURE_T_END = 256, 1e4


def choose_lanes(recommended: int, cpu_seconds: Mapping[int, float]) -> int:
    """The width to use: the fastest of ``cpu_seconds`` (width → CPU time of one ensemble) when it beats the
    ``recommended`` width's time by more than ``LANE_MARGIN``, else ``recommended``.

    Examples
    --------
    >>> from rocknroller.numerics.ensembles.lanes import choose_lanes
    >>> choose_lanes(4, {4: 8.03, 8: 7.07}), choose_lanes(4, {4: 8.03, 8: 7.9}), choose_lanes(8, {4: 5.0, 8: 5.0})
    (8, 4, 8)
    """
    if recommended not in cpu_seconds:
        raise ValueError(f"recommended must be one of the widths timed, {sorted(cpu_seconds)}, got {recommended!r}")
    fastest = min(cpu_seconds, key=lambda w: (cpu_seconds[w], w != recommended))
    return fastest if cpu_seconds[fastest] < (1.0 - LANE_MARGIN) * cpu_seconds[recommended] else recommended


def machine_key() -> str:
    """What the lane record depends on: heyoka's version and the CPU (its model name and flags from /proc/cpuinfo,
    else ``platform.processor()``), hashed.

    Examples
    --------
    >>> from rocknroller.numerics.ensembles.lanes import machine_key
    >>> len(machine_key()), machine_key() == machine_key()
    (16, True)
    """
    import heyoka as hy

    cpu = platform.machine() + " " + platform.processor()
    info = Path("/proc/cpuinfo")
    if info.exists():
        lines = info.read_text(errors="replace").splitlines()
        cpu = " ".join(next((ln.split(":", 1)[1].strip() for ln in lines if ln.startswith(field)), "")
                       for field in ("model name", "flags"))
    return hashlib.sha256(f"lanes v1 heyoka {hy.__version__} cpu {cpu}".encode()).hexdigest()[:16]


def _record_path() -> Path:
    return cache_dir() / f"lanes-{machine_key()}.npz"


_SPEC = {"widths": (len(LANE_CANDIDATES),), "cpu_seconds": (len(LANE_CANDIDATES),), "chosen": ()}


def default_lanes() -> int:
    """The lanes ``run_ensemble`` uses when none are given: the width :func:`measure_lanes` recorded for this machine,
    or heyoka's recommendation (:func:`~rocknroller.numerics.ensembles.batch.batch_width`) without a valid record.

    Examples
    --------
    >>> from rocknroller.numerics.ensembles.lanes import LANE_CANDIDATES, default_lanes
    >>> from rocknroller.numerics.ensembles.batch import batch_width
    >>> default_lanes() in (*LANE_CANDIDATES, batch_width())
    True
    """
    path = _record_path()
    if not path.exists():
        return batch_width()
    arrays, reason = load_arrays(path, path.stem, _SPEC)
    chosen = float(arrays["chosen"]) if arrays is not None else math.nan
    if arrays is None or not (chosen == int(chosen) and MIN_LANES <= chosen <= MAX_LANES):
        warnings.warn(f"ignoring the lane record {path} ({reason or f'its width {chosen!r} is not a lane count'}): "
                      "run_ensemble uses heyoka's recommended width; `rocknroller warm` measures it again",
                      CacheWarning, stacklevel=2)
        return batch_width()
    return int(chosen)


@dataclass(frozen=True)
class LaneChoice:
    """The widths timed side by side and the one chosen (:func:`measure_lanes`).

    Attributes
    ----------
    cpu_ms : dict
        Width → CPU milliseconds per trajectory, the best of the interleaved rounds.
    recommended : int
        heyoka's recommendation for this CPU.
    chosen : int
        :func:`choose_lanes`'s pick, which ``run_ensemble`` now uses by default.
    saved : bool
        Whether the record was written (False when the cache directory cannot be written).
    """

    cpu_ms: dict[int, float]
    recommended: int
    chosen: int
    saved: bool

    def describe(self) -> str:
        """One line: the times and the choice."""
        times = ", ".join(f"{w} lanes {ms:.2f} ms" for w, ms in sorted(self.cpu_ms.items()))
        return (f"{times} of CPU per trajectory (heyoka recommends {self.recommended}): run_ensemble uses "
                f"{self.chosen} lanes" + ("" if self.saved else " in this process only (the record was not saved)"))


def measure_lanes(jobs: int = 32, t_end: float = 500.0, *, save: bool = True,
                  timer: Callable[[], float] = time.process_time) -> LaneChoice:
    """Time ``run_batch`` at each width of ``LANE_CANDIDATES`` (and heyoka's recommendation) on the same ensemble,
    in interleaved rounds, best of three; choose with :func:`choose_lanes` and, with ``save``, record the choice for
    :func:`default_lanes`.  Compiles the batch integrator of each width not yet in heyoka's disk cache first (untimed).

    Parameters
    ----------
    jobs : int
        Releases from rest at 0.95π of the paper's body (ε = 1e-3), spread in ψ0 over [0, π/2), in
        [1, ``MAX_MEASURE_JOBS``].
    t_end : float
        Each run's length, in (0, ``MAX_MEASURE_T_END``].
    save : bool
        Record the choice in the cache directory.
    timer : callable
        The clock (CPU time of this process by default).

    Examples
    --------
    >>> from rocknroller.numerics.ensembles.lanes import measure_lanes
    >>> choice = measure_lanes(8, 20.0, save=False)
    >>> choice.chosen in choice.cpu_ms and choice.recommended in choice.cpu_ms
    True
    """
    if isinstance(jobs, bool) or not isinstance(jobs, (int, np.integer)) or not 1 <= jobs <= MAX_MEASURE_JOBS:
        raise ValueError(f"jobs must be a whole number in [1, {MAX_MEASURE_JOBS}], got jobs={jobs!r}")
    if isinstance(t_end, bool) or not (isinstance(t_end, (int, float, np.floating)) and 0.0 < t_end <= MAX_MEASURE_T_END):
        raise ValueError(f"t_end must be a number in (0, {MAX_MEASURE_T_END:g}], got t_end={t_end!r}")
    body = Body.paper(1e-3)
    runs = [(body, EulerState(0.95 * math.pi, 0.0, psi, 0.0, 0.0, 0.0), float(t_end))
            for psi in np.linspace(0.0, 0.5 * math.pi, int(jobs), endpoint=False)]
    recommended = batch_width()
    widths = sorted({*LANE_CANDIDATES, recommended})
    for w in widths:
        run_batch(runs[:1], w)
    best = dict.fromkeys(widths, math.inf)
    for _ in range(_ROUNDS):
        for w in widths:
            start = timer()
            for k in range(0, len(runs), w):
                run_batch(runs[k:k + w], w)
            best[w] = min(best[w], timer() - start)
    chosen = choose_lanes(recommended, best)
    saved = save
    try:
        if save:
            save_arrays(_record_path(), _record_path().stem, {
                "widths": np.array(LANE_CANDIDATES, float),
                "cpu_seconds": np.array([best[w] for w in LANE_CANDIDATES], float),
                "chosen": np.array(float(chosen))})
    except OSError:
        saved = False
    return LaneChoice({w: 1e3 * t / len(runs) for w, t in best.items()}, recommended, chosen, saved)
