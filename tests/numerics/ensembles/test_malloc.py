"""glibc's malloc thresholds fixed at the first batch run (``batch._steady_malloc``): set once, to glibc's own dynamic
maxima, not where the environment sets them or the C library is another; a second batch run then reuses the heap for
its dense output rather than mapping it afresh page by page."""

from __future__ import annotations

import os
import platform
import subprocess
import sys
import textwrap

import pytest

from rocknroller.numerics.ensembles import batch


class _FakeLibc:
    def __init__(self) -> None:
        self.calls: list[tuple[int, int]] = []

    def mallopt(self, param: int, value: int) -> int:
        self.calls.append((param, value))
        return 1


@pytest.fixture
def fake_libc(monkeypatch):
    libc = _FakeLibc()
    monkeypatch.setattr(batch.ctypes, "CDLL", lambda name: libc)
    monkeypatch.setattr(batch.platform, "libc_ver", lambda: ("glibc", "2.36"))
    monkeypatch.setattr(batch, "_MALLOC_DONE", batch.threading.Event())
    for name in ("MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_", "GLIBC_TUNABLES"):
        monkeypatch.delenv(name, raising=False)
    return libc


def test_the_thresholds_are_glibcs_dynamic_maxima_set_once(fake_libc):
    batch._steady_malloc()
    batch._steady_malloc()
    # glibc's malloc.h: M_TRIM_THRESHOLD -1, M_MMAP_THRESHOLD -3; DEFAULT_MMAP_THRESHOLD_MAX = 4 MiB × sizeof(long);
    # trim past twice the largest doubling series below it (< 2 × 32 MiB)
    assert fake_libc.calls == [(-1, 4 * 4 * 2**20 * 8), (-3, 4 * 2**20 * 8)]


@pytest.mark.parametrize("name, value", [("MALLOC_MMAP_THRESHOLD_", "1048576"), ("MALLOC_TRIM_THRESHOLD_", "1048576"),
                                         ("GLIBC_TUNABLES", "glibc.malloc.trim_threshold=1048576"),
                                         ("GLIBC_TUNABLES", "glibc.elision.enable=1:glibc.malloc.mmap_threshold=65536")])
def test_the_environments_thresholds_are_kept(fake_libc, monkeypatch, name, value):
    monkeypatch.setenv(name, value)
    batch._steady_malloc()
    assert fake_libc.calls == []


def test_other_tunables_do_not_keep_glibcs_dynamic_thresholds(fake_libc, monkeypatch):
    monkeypatch.setenv("GLIBC_TUNABLES", "glibc.malloc.arena_max=2")
    batch._steady_malloc()
    assert len(fake_libc.calls) == 2


def test_another_c_library_is_left_alone(fake_libc, monkeypatch):
    monkeypatch.setattr(batch.platform, "libc_ver", lambda: ("", ""))
    batch._steady_malloc()
    assert fake_libc.calls == []


_GROWTH = textwrap.dedent("""
    import ctypes, resource, sys
    libc = ctypes.CDLL(None)
    if len(sys.argv) > 1:  # M_TRIM_THRESHOLD, M_MMAP_THRESHOLD as _steady_malloc sets them
        libc.mallopt(-1, int(sys.argv[1]))
        libc.mallopt(-3, int(sys.argv[2]))
    libc.malloc.restype, libc.malloc.argtypes = ctypes.c_void_p, [ctypes.c_size_t]
    libc.free.argtypes, libc.memset.argtypes = [ctypes.c_void_p], [ctypes.c_void_p, ctypes.c_int, ctypes.c_size_t]
    STEP = 14784  # bytes of one step's Taylor coefficients at 8 lanes: 11 variables, order 20
    faults = []
    for steps in range(1030, 1090, 10):  # a stretch's dense output: a vector grown by doubling, then freed
        f0 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
        cap, buf, small = 1, libc.malloc(STEP), []
        for n in range(1, steps + 1):
            if n > cap:
                new = libc.malloc(2 * cap * STEP)
                libc.memset(new, 0, cap * STEP)
                libc.free(buf)
                buf, cap = new, 2 * cap
            libc.memset(buf + (n - 1) * STEP, 1, STEP)
            if n % 100 == 0:
                small.append(libc.malloc(2000))  # the small objects made along the way
        libc.free(buf)
        for p in small:
            libc.free(p)
        faults.append(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - f0)
    print(*faults)
""")


@pytest.mark.skipif(platform.libc_ver()[0] != "glibc", reason="glibc's malloc only")
def test_a_stretchs_dense_output_reuses_the_heap():
    """Six stretches' dense output grown as heyoka grows it (≈ 30 MB at 8 lanes, written step by step), in a fresh
    process that imports nothing else: with glibc's dynamic thresholds every stretch maps its memory afresh (a fault
    per 4 kB page, ≈ 7400 for its 30 MB); with the thresholds ``_steady_malloc`` sets (the test above) only the first
    does, the others reuse the heap (a few dozen faults).  Whether a process reaches the first case depends on what
    it allocated before (benchmarks/bench_ensemble.py met it in one process of two); this one always does."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("MALLOC_")}

    def faults(*thresholds: int) -> list[int]:
        out = subprocess.run([sys.executable, "-c", _GROWTH, *map(str, thresholds)], env=env, capture_output=True,
                             text=True, check=True)
        return [int(f) for f in out.stdout.split()]

    pages = 1030 * 14784 // 4096
    assert min(faults()[1:]) > pages  # the test sees what the thresholds are for
    assert max(faults(batch.MALLOC_TRIM_THRESHOLD, batch.MALLOC_MMAP_THRESHOLD)[1:]) < pages // 20
