"""The averaging-table cache holds plain, checked arrays: nothing in a planted file runs or is used.

A small table (8 × 4 nodes, ~1 s to build) is enough: the cache logic does not depend on the grid.  Every
bad file is planted at the exact path the table would be read from; it must be refused with one
``CacheWarning``, rebuilt, and replaced by a good file.
"""

from __future__ import annotations

import functools
import hashlib
import io
import math
import os
import warnings
import zipfile

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.map import table as slow_table
from rocknroller.numerics import cache

SYM = Body.paper(0.0)
THETA0 = 0.9 * math.pi
GRID = {"nu": 8, "nv": 4}
KEY = slow_table._table_key("build_table", SYM, THETA0, {"nu": 8, "nv": 4, "u_factor": 2.5, "v_ratio": 0.002})


def _load(**kw) -> av.SlowMapTable:
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", "the averaging tables .* interpolate", av.AveragingValidityWarning)
        return av.load_or_build_table(SYM, THETA0, **GRID, **kw)


def _fields(table: av.SlowMapTable) -> dict[str, np.ndarray]:
    return {k: np.asarray(getattr(table, k), float) for k in table.__dataclass_fields__}


def _assert_same(t1: av.SlowMapTable, t2: av.SlowMapTable) -> None:
    f1, f2 = _fields(t1), _fields(t2)
    assert f1.keys() == f2.keys()
    for k in f1:  # exact: the cache stores the float64 values in binary
        assert np.array_equal(f1[k], f2[k]), k


@pytest.fixture(scope="module")
def fresh(tmp_path_factory):
    """A table built from scratch in an empty cache directory, and that file's path."""
    root = tmp_path_factory.mktemp("cache")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("ROCKNROLLER_CACHE", str(root))
        mp.setattr(slow_table, "_TABLES", {})
        table = _load()
    files = list((root / "averaging").glob("slowmap-*.npz"))
    assert len(files) == 1
    return table, files[0]


@pytest.fixture
def cache_env(tmp_path, monkeypatch, fresh):
    """An empty cache directory and an empty in-memory table cache; build_table returns the fresh table and
    counts its calls (the build is deterministic; test_pickle_payload_never_runs rebuilds for real)."""
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path / "cache"))
    monkeypatch.setattr(slow_table, "_TABLES", {})
    monkeypatch.setattr(cache, "_WARNED_DIRS", set())
    calls = []

    @functools.wraps(av.build_table)  # load_or_build_table reads its keyword options from the signature
    def build(*args, **kw):
        calls.append(kw)
        return fresh[0]

    monkeypatch.setattr(slow_table, "build_table", build)
    path = tmp_path / "cache" / "averaging" / fresh[1].name
    path.parent.mkdir(parents=True)
    return path, calls


def _expected_checksum(key: str, arrays: dict[str, np.ndarray]) -> str:
    """The documented checksum, written out: key NUL, then per field name NUL dtype NUL shape NUL bytes."""
    h = hashlib.sha256(key.encode() + b"\0")
    for name, a in arrays.items():
        h.update(f"{name}\0{a.dtype.str}\0{a.shape!r}\0".encode())
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()


def test_file_holds_plain_arrays_key_and_checksum(fresh):
    table, path = fresh
    assert path.name == f"slowmap-{hashlib.sha256(KEY.encode()).hexdigest()[:20]}.npz"
    with np.load(path, allow_pickle=False) as z:
        members = {k: z[k] for k in z.files}
    key, checksum = str(members.pop("__key__")), str(members.pop("__sha256__"))
    assert key == KEY and KEY.startswith("slowmap|") and repr(THETA0) in KEY
    assert list(members) == list(table.__dataclass_fields__)  # the checksum order
    assert all(a.dtype == np.float64 for a in members.values())
    assert checksum == _expected_checksum(KEY, members)
    _assert_same(av.SlowMapTable(**{k: a if a.ndim else float(a) for k, a in members.items()}), table)
    assert not [p for p in path.parent.iterdir() if p.suffix == ".tmp"]  # the atomic write left nothing behind


def test_numerics_integrate_reexports_cache_dir():
    from rocknroller.numerics import integrate

    assert integrate.cache_dir is cache.cache_dir


class _Payload:
    """Unpickling this creates the marker file (``open(marker, "w")``)."""

    def __init__(self, marker: str) -> None:
        self.marker = marker

    def __reduce__(self):
        return (open, (self.marker, "w"))


def _pickled_npz(path, fresh_path, marker) -> None:
    """A valid-looking table file whose coef member is a pickled object array that would create ``marker``."""
    with np.load(fresh_path, allow_pickle=False) as z:
        members = {k: z[k] for k in z.files}
    members["coef"] = np.array([_Payload(str(marker))], dtype=object)
    np.savez(path, **members)


def test_planted_payload_is_live(tmp_path, fresh):
    """The payload of the next test does run when unpickled (so its absence there means something)."""
    bait, marker = tmp_path / "bait.npz", tmp_path / "marker-live"
    _pickled_npz(bait, fresh[1], marker)
    with np.load(bait, allow_pickle=True) as z:
        z["coef"]
    assert marker.exists()


def test_pickle_payload_never_runs(tmp_path, monkeypatch, fresh):
    """A pickled object array planted at the exact cache path: nothing runs, a CacheWarning, a real rebuild
    equal to the fresh table, and the file replaced by a good one."""
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path / "cache"))
    monkeypatch.setattr(slow_table, "_TABLES", {})
    path, marker = tmp_path / "cache" / "averaging" / fresh[1].name, tmp_path / "marker"
    path.parent.mkdir(parents=True)
    _pickled_npz(path, fresh[1], marker)
    with pytest.warns(cache.CacheWarning, match="not used"):
        table = _load()
    assert not marker.exists()
    _assert_same(table, fresh[0])
    arrays, reason = cache.load_arrays(path, KEY, slow_table._table_spec(8, 4))
    assert reason == "" and np.array_equal(arrays["coef"], fresh[0].coef)
    assert not marker.exists()


def _valid_members(fresh_path) -> dict[str, np.ndarray]:
    with np.load(fresh_path, allow_pickle=False) as z:
        return {k: z[k] for k in z.files}


def _resigned(members: dict[str, np.ndarray], key: str = KEY) -> dict[str, np.ndarray]:
    """Members with the checksum recomputed for ``key`` (a consistent file that is wrong in another way)."""
    data = {k: v for k, v in members.items() if not k.startswith("__")}
    return {**data, "__key__": np.array(key), "__sha256__": np.array(cache.array_checksum(key, data, tuple(data)))}


def _plant(kind: str, path, fresh_path) -> None:
    good = _valid_members(fresh_path)
    if kind == "garbage":
        path.write_bytes(os.urandom(3000))
    elif kind == "truncated":
        raw = fresh_path.read_bytes()
        path.write_bytes(raw[: len(raw) // 2])
    elif kind == "empty":
        path.write_bytes(b"")
    elif kind == "wrong_checksum":  # one coefficient changed (the largest: many vanish by parity), checksum kept
        coef = good["coef"].copy()
        coef[np.unravel_index(np.argmax(np.abs(coef)), coef.shape)] *= 1.0 + 1e-12
        np.savez(path, **{**good, "coef": coef})
    elif kind == "wrong_key":  # consistent file for another table
        np.savez(path, **_resigned(good, KEY.replace(repr(THETA0), repr(0.8 * math.pi))))
    elif kind == "extra_member":
        np.savez(path, **good, extra=np.zeros(3))
    elif kind == "missing_member":
        np.savez(path, **_resigned({k: v for k, v in good.items() if k != "kappa"}))
    elif kind == "wrong_shape":
        np.savez(path, **_resigned({**good, "coef": np.zeros((18, 8, 5))}))
    elif kind == "wrong_dtype":
        np.savez(path, **_resigned({**good, "coef": good["coef"].astype(np.float32)}))
    elif kind == "non_finite":
        coef = good["coef"].copy()
        coef[0, 0, 0] = np.nan
        np.savez(path, **_resigned({**good, "coef": coef}))
    elif kind == "oversized_file":
        path.write_bytes(b"PK" + bytes(10**7))
    elif kind == "oversized_member":  # a small (deflated) file declaring more data than the table can have
        with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as zf:
            for k, v in good.items():
                buf = io.BytesIO()
                np.save(buf, np.zeros(10**6) if k == "kappa" else v)
                zf.writestr(f"{k}.npy", buf.getvalue())
    elif kind == "fifo":  # reading it would block forever
        os.mkfifo(path)
    else:  # pragma: no cover
        raise AssertionError(kind)


BAD = ("garbage", "truncated", "empty", "wrong_checksum", "wrong_key", "extra_member", "missing_member",
       "wrong_shape", "wrong_dtype", "non_finite", "oversized_file", "oversized_member", "fifo")


@pytest.mark.parametrize("kind", BAD)
def test_bad_file_is_refused_rebuilt_and_replaced(cache_env, fresh, kind):
    path, calls = cache_env
    _plant(kind, path, fresh[1])
    with pytest.warns(cache.CacheWarning) as rec:
        table = _load()
    assert len([w for w in rec if issubclass(w.category, cache.CacheWarning)]) == 1
    assert str(path) in str(rec[0].message) and "rebuilt" in str(rec[0].message)
    assert len(calls) == 1
    _assert_same(table, fresh[0])
    # replaced by a good file: the next process loads it silently, without building
    assert cache.load_arrays(path, KEY, slow_table._table_spec(8, 4))[1] == ""
    slow_table._TABLES.clear()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _assert_same(_load(build=False), fresh[0])
    assert len(calls) == 1


def test_bad_file_with_build_false_is_not_used(cache_env, fresh):
    path, calls = cache_env
    _plant("wrong_checksum", path, fresh[1])
    with pytest.warns(cache.CacheWarning), pytest.raises(ValueError, match="no averaging tables"):
        _load(build=False)
    assert calls == []


def test_unwritable_cache_warns_once(cache_env, tmp_path, monkeypatch):
    """A cache directory that cannot be created (it lies under a file: root can write anywhere else) gives one
    CacheWarning per process, naming the directory, the cost and the fix; the tables are still returned."""
    _, calls = cache_env
    blocker = tmp_path / "afile"
    blocker.write_text("not a directory")
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(blocker / "sub"))
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        t1 = _load()
        slow_table._TABLES.clear()
        t2 = _load()
    msgs = [str(w.message) for w in rec if issubclass(w.category, cache.CacheWarning)]
    assert len(msgs) == 1, msgs
    assert str(blocker / "sub" / "averaging") in msgs[0]
    assert "ROCKNROLLER_CACHE" in msgs[0] and "every process" in msgs[0]
    assert len(calls) == 2 and t1 is t2


def test_atomic_write_keeps_old_file_on_error(tmp_path):
    target = tmp_path / "f.bin"
    target.write_bytes(b"old")

    def fail(fh):
        fh.write(b"partial")
        raise OSError("disk full")

    with pytest.raises(OSError, match="disk full"):
        cache.atomic_write(target, fail)
    assert target.read_bytes() == b"old" and [p.name for p in tmp_path.iterdir()] == ["f.bin"]


class _Blob:
    """An object holding one array of n bytes (and a non-array attribute, not counted)."""

    def __init__(self, n: int) -> None:
        self.data = np.zeros(n, np.uint8)
        self.name = "blob"


def test_memory_cache_keeps_the_newest_within_its_budget():
    c = cache.MemoryCache(250)
    for k in "abc":
        c[k] = _Blob(100)
    assert list(c) == ["b", "c"] and c.nbytes == 200          # a dropped: 300 > 250
    assert isinstance(c["b"], _Blob) and list(c) == ["c", "b"]  # read: b is the newest
    assert c.get("a") is None and c.get("a", 0) == 0 and c.get("c") is not None and list(c) == ["b", "c"]
    assert c["b"] is not None and list(c) == ["c", "b"]      # b the newest again
    c["d"] = _Blob(100)
    assert list(c) == ["b", "d"]                               # c, the oldest now, dropped
    c["e"] = _Blob(1000)
    assert list(c) == ["e"] and c.nbytes == 1000               # larger than the budget: held alone
    assert "e" in c and "b" not in c and len(c) == 1
    c.clear()
    assert len(c) == 0 and c.nbytes == 0
    for bad in (-1, 1.5, True):
        with pytest.raises(ValueError, match="max_bytes"):
            cache.MemoryCache(bad)


def test_run_time_forms_are_bounded(monkeypatch, fresh):
    """Two tables' run-time forms in a budget of one: the older is dropped and rebuilt when used again."""
    from dataclasses import replace

    from rocknroller.analysis.slow.map import compiled_map as slow_map

    table = fresh[0]
    other = replace(table)  # another table object (the forms are kept per table object)
    one = cache.array_bytes(slow_map._FastTable(table))
    monkeypatch.setattr(slow_map, "_FAST", cache.MemoryCache(one))
    first = slow_map._fast(table)
    assert slow_map._fast(table) is first
    second = slow_map._fast(other)
    assert len(slow_map._FAST) == 1 and slow_map._FAST.nbytes == one
    again = slow_map._fast(table)
    assert again is not first and again.table is table and second.table is other
    np.testing.assert_array_equal(again.rows_jac, first.rows_jac)  # the same table: the same form, bit for bit


@pytest.mark.filterwarnings("ignore::rocknroller.analysis.slow.map.limits.AveragingValidityWarning")  # the coarse grid
def test_a_table_with_absurd_coefficients_is_named_not_t_end():
    """Issue 25, item 25: a cached table tampered to coefficients of 1e300 (finite, so the loader's checks pass when
    the checksum is recomputed) made the prediction refuse ``t_end`` ("T_theta = 0"); now the table is named."""
    import dataclasses

    body = Body.paper(1e-3)
    table = av.load_or_build_table(body, 0.95 * math.pi, nu=8, nv=4)
    bad = dataclasses.replace(table, coef=np.full_like(table.coef, 1e300))
    with pytest.raises(ValueError, match=r"^the averaging table gives T_theta = .* not a positive time: it is damaged") \
            as exc:
        av.predict_slow_motion(body, 0.95 * math.pi, 0.5, 1000.0, table=bad, order=1)
    assert "t_end" not in str(exc.value)
    with pytest.raises(ValueError, match="it is damaged"):
        av.predict_slow_motion(Body.paper(0.0), 0.95 * math.pi, 0.5, 1000.0, table=bad, order=1)  # ε = 0 too
