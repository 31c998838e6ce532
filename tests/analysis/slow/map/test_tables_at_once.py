"""Release tables of many θ0 at once: every array of every table the same bit for bit as the one-process
``build_table``'s, whether the nodes ran in threads, spawned processes, a local dask cluster or the workers of a
running one; the tables are cached as ``load_or_build_table`` caches them; bad input is refused before any work,
naming the parameter; the same for the second-order tables.

A coarse grid (16 × 8 nodes: two blocks of nodes per table, so the blocks of different tables interleave on the
workers) keeps each build to about a second; the built tables go to a temporary ROCKNROLLER_CACHE (heyoka's
compilation cache stays the shared one).
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map import table as slow_table
from rocknroller.analysis.slow.map import tables_at_once
from rocknroller.analysis.slow.map.limits import AveragingValidityWarning
from rocknroller.analysis.slow.map.table import build_table, load_or_build_table
from rocknroller.analysis.slow.map.second_order import build_second_order_table, load_or_build_second_order_table
from rocknroller.analysis.slow.map.tables_at_once import build_release_tables, build_second_order_tables

BODY = Body.paper(1e-3)
THETA0 = (0.95 * math.pi, 0.9 * math.pi, 0.95 * math.pi)  # a repeated angle is built once
GRID = {"nu": 16, "nv": 8}


def _quiet(fn, *args, **kw):
    """``fn(*args, **kw)`` without the coarse grid's interpolation warning."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", "the (averaging|second-order) tables .* interpolate", AveragingValidityWarning)
        return fn(*args, **kw)


def assert_bit_identical(a, b) -> None:
    """Every field equal, arrays and numbers, element for element, of the same dtype and shape (a number read from
    the cache is a float where the build's is a numpy float64 of the same value)."""
    assert type(a) is type(b)
    for f in dataclasses.fields(a):
        u, v = np.asarray(getattr(a, f.name)), np.asarray(getattr(b, f.name))
        assert u.dtype == v.dtype and u.shape == v.shape and np.array_equal(u, v), (f.name, u, v)


@pytest.fixture(scope="module")
def one_process():
    """The tables as one process builds them, one after the other (no cache)."""
    return {t: _quiet(build_table, BODY, t, **GRID) for t in set(THETA0)}


@pytest.fixture
def empty_cache(tmp_path, monkeypatch):
    """An empty disk cache and an empty memory cache of tables."""
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path))
    monkeypatch.setattr(slow_table, "_TABLES", {})
    return tmp_path


def _check(where: dict, one_process, empty_cache) -> None:
    tables = _quiet(build_release_tables, BODY, THETA0, progress=False, **where, **GRID)
    assert len(tables) == len(THETA0)
    for t, table in zip(THETA0, tables):
        assert_bit_identical(table, one_process[t])
    # cached as load_or_build_table caches: one file per angle, read back from disk to the bit
    assert len(list((empty_cache / "averaging").glob("slowmap-*.npz"))) == len(set(THETA0))
    slow_table._TABLES = {}
    for t in set(THETA0):
        assert_bit_identical(load_or_build_table(BODY, t, build=False, **GRID), one_process[t])


@pytest.mark.parametrize("where", [{}, {"threads": 2}, {"processes": 2}], ids=["loop", "threads", "processes"])
def test_in_this_machine_the_tables_are_the_one_process_builds(where, one_process, empty_cache):
    _check(where, one_process, empty_cache)


def test_a_local_cluster_builds_the_one_process_tables(one_process, empty_cache):
    pytest.importorskip("distributed")
    _check({"workers": 2}, one_process, empty_cache)


def test_a_running_cluster_builds_the_one_process_tables(one_process, empty_cache):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as c:
        _check({"scheduler": c.scheduler_address}, one_process, empty_cache)


def test_cached_tables_are_not_rebuilt(one_process, empty_cache, monkeypatch):
    _quiet(build_release_tables, BODY, THETA0[:1], progress=False, **GRID)
    handed = []

    def record(fn, blocks, sizes, **kw):
        handed.extend(blocks)
        return [fn(*b) for b in blocks]

    monkeypatch.setattr(tables_at_once, "run_blocks", record)
    tables = _quiet(build_release_tables, BODY, THETA0, progress=False, **GRID)
    assert {b[1] for b in handed} == {one_process[0.9 * math.pi].E0}  # only the new angle's nodes ran
    assert sum(len(b[2]) for b in handed) == GRID["nu"] * GRID["nv"] // 2  # a mirrored grid: half its nodes run
    for t, table in zip(THETA0, tables):
        assert_bit_identical(table, one_process[t])


@pytest.mark.parametrize("kw, name", [
    ({"scheduler": "http://10.0.0.5:8786"}, "scheduler"),
    ({"workers": 0}, "workers"),
    ({"threads": 1.5}, "threads"),
    ({"processes": 0}, "processes"),
    ({"processes": 2, "threads": 2}, "processes"),
    ({"workers": 2, "threads": 2}, "threads"),
    ({"theta0": 0.5 * math.pi}, "theta0"),
    ({"theta0": np.full((2, 2), 0.95 * math.pi)}, "theta0"),
    ({"nu": 7}, "nu"),
    ({"nodes": 8}, "nodes"),
    ({"nu": 4096, "budget": 10.0}, r"2 release tables to build \(32768 nodes each\).*budget of 10 s"),
])
def test_bad_input_is_refused_before_any_work(kw, name, empty_cache, monkeypatch):
    def no_work(*args, **kw):
        raise AssertionError("work started")

    monkeypatch.setattr(tables_at_once, "release_frame", no_work)
    kw = {"theta0": THETA0, **GRID, **kw}
    with pytest.raises(ValueError, match=name):
        build_release_tables(BODY, kw.pop("theta0"), progress=False, **kw)


K2_GRID = {"nu": 16, "nv": 4}  # 32 nodes, 16 computed: two blocks of k2 nodes


@pytest.fixture(scope="module")
def one_process_k2(tmp_path_factory):
    """The second-order table of 0.95π and its release table (default grid), built by one process in a cache of
    their own."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("ROCKNROLLER_CACHE", str(tmp_path_factory.mktemp("k2")))
        mp.setattr(slow_table, "_TABLES", {})
        second = _quiet(build_second_order_table, BODY, THETA0[0], **K2_GRID)
        return load_or_build_table(BODY, THETA0[0], build=False), second


@pytest.mark.parametrize("where", [{"threads": 2}, {"workers": 2}], ids=["threads", "local cluster"])
def test_second_order_tables_are_the_one_process_builds(where, one_process_k2, empty_cache):
    if "workers" in where:
        pytest.importorskip("distributed")
    first, second = one_process_k2
    tables = _quiet(build_second_order_tables, BODY, THETA0[:1] * 2, progress=False, **where, **K2_GRID)
    assert len(tables) == 2 and tables[0] is tables[1]
    assert_bit_identical(tables[0], second)
    slow_table._TABLES = {}  # read back from the disk cache: the release table and the second-order table
    assert_bit_identical(load_or_build_table(BODY, THETA0[0], build=False), first)
    assert_bit_identical(load_or_build_second_order_table(BODY, THETA0[0], build=False, **K2_GRID), second)


def test_second_order_bad_input_is_refused_before_any_work(empty_cache, monkeypatch):
    monkeypatch.setattr(tables_at_once, "build_release_tables", lambda *a, **k: pytest.fail("work started"))
    for kw, name in (({"nu": 7}, "nu"), ({"threads": 0}, "threads"), ({"scheduler": "x"}, "scheduler")):
        with pytest.raises(ValueError, match=name):
            build_second_order_tables(BODY, THETA0, **kw)
