"""The on-disk cache: where it lives, how files are written, and plain-array files that are checked on load; the
bound of the in-memory caches (:class:`MemoryCache`); and the note on stderr while an integrator is compiled for
heyoka's own disk cache (:func:`compiling`).

Nothing in the cache is trusted: it holds plain numeric arrays only (``.npz`` read with
``allow_pickle=False``), each file carries its key and a SHA-256 checksum of its contents, and a file
that fails any check is reported with a :class:`CacheWarning` and rebuilt by the caller, never used.
Files are written atomically (a temporary file in the same directory, then ``os.replace``), so a
reader never sees a half-written file.  A cache directory that cannot be written is not an error:
the results are recomputed in every process, and one :class:`CacheWarning` per process and
directory says so and how to fix it.

Checksum of an array file (:func:`array_checksum`): SHA-256 over the UTF-8 bytes of the key, a NUL,
then for each field in the order of the caller's ``spec``: ``name NUL dtype.str NUL repr(shape) NUL``
followed by the C-contiguous bytes of the array (``numpy.asarray(a, order="C").tobytes()``).
"""

from __future__ import annotations

import hashlib
import os
import stat
import sys
import tempfile
import threading
import warnings
import zipfile
from collections import OrderedDict
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Callable, Hashable, Iterator, Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["CacheWarning", "MemoryCache", "array_bytes", "cache_dir", "atomic_write", "probe_writable", "warn_unwritable", "array_checksum",
           "save_arrays", "load_arrays", "COMPILE_NOTE_AFTER", "compiling", "warming",
           "note_after"]

#: Names of the two bookkeeping members of an array file (0-d unicode arrays).
KEY_FIELD, CHECKSUM_FIELD = "__key__", "__sha256__"
#: Slack in bytes allowed per member of an array file over its data size (the .npy header, 64-byte aligned).
_HEADER_SLACK = 4096
_WARNED_DIRS: set[str] = set()


class CacheWarning(UserWarning):
    """A cache file failed its check (and is rebuilt), or the cache directory cannot be written."""


class MemoryCache:
    """An in-memory cache of the values used most recently, within a byte budget.

    Reading an entry (``cache[key]``) makes it the newest; storing one drops the oldest entries while the entries'
    bytes (``array_bytes`` of each value) exceed ``max_bytes``, the newest always kept (a value larger than the
    budget is held alone).  ``key in cache`` does not reorder.  The process's caches of tables and of their run-time
    forms are of this kind, so that a session over many starts (each energy its own table) keeps a bounded memory.
    Every operation holds one lock, so threads (``run_ensemble(threads=...)``, the atlas) may share a cache: a
    store's evictions cannot interleave with another thread's read or byte count.

    Parameters
    ----------
    max_bytes : int
        The budget, ≥ 0.
    """

    def __init__(self, max_bytes: int) -> None:
        if isinstance(max_bytes, bool) or int(max_bytes) != max_bytes or max_bytes < 0:
            raise ValueError(f"max_bytes must be an integer >= 0, got max_bytes={max_bytes!r}")
        self.max_bytes = int(max_bytes)
        self._entries: OrderedDict[Hashable, tuple[Any, int]] = OrderedDict()
        self._lock = threading.Lock()

    def __contains__(self, key: Hashable) -> bool:
        with self._lock:
            return key in self._entries

    def __len__(self) -> int:
        with self._lock:
            return len(self._entries)

    def __iter__(self) -> Iterator[Hashable]:
        with self._lock:
            return iter(list(self._entries))

    def __getitem__(self, key: Hashable) -> Any:
        with self._lock:
            value = self._entries[key][0]
            self._entries.move_to_end(key)
            return value

    def get(self, key: Hashable, default: Any = None) -> Any:
        """``cache[key]`` (the newest now), or ``default`` if absent (one lookup: no gap in which another thread's
        store could drop the entry between a test and a read)."""
        try:
            return self[key]
        except KeyError:
            return default

    def __setitem__(self, key: Hashable, value: Any) -> None:
        size = array_bytes(value)
        with self._lock:
            self._entries[key] = (value, size)
            self._entries.move_to_end(key)
            while len(self._entries) > 1 and self._nbytes() > self.max_bytes:
                self._entries.popitem(last=False)

    def _nbytes(self) -> int:
        return sum(n for _, n in self._entries.values())

    @property
    def nbytes(self) -> int:
        """Bytes of the arrays held (``array_bytes`` of each value)."""
        with self._lock:
            return self._nbytes()

    def clear(self) -> None:
        """Drop every entry."""
        with self._lock:
            self._entries.clear()


def array_bytes(obj: Any) -> int:
    """Bytes of the numpy arrays among an object's attributes (a table's data; the objects it refers to are not
    counted)."""
    return sum(v.nbytes for v in vars(obj).values() if isinstance(v, np.ndarray))


def cache_dir() -> Path:
    """Directory of the rocknroller cache: ``$ROCKNROLLER_CACHE`` if set, else ``$XDG_CACHE_HOME/rocknroller``
    (default ``~/.cache/rocknroller``)."""
    if os.environ.get("ROCKNROLLER_CACHE"):
        return Path(os.environ["ROCKNROLLER_CACHE"])
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "rocknroller"


def probe_writable(directory: str | os.PathLike[str]) -> OSError | None:
    """None if a file can be created in ``directory`` (created if missing), else the OSError that prevents it."""
    try:
        os.makedirs(directory, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=directory):
            pass
    except OSError as exc:
        return exc
    return None


def warn_unwritable(directory: str | os.PathLike, error: BaseException, consequence: str,
                    fix: str = "set ROCKNROLLER_CACHE to a writable folder to keep the cache") -> None:
    """One :class:`CacheWarning` per process and directory: the cache at ``directory`` cannot be used (it cannot be
    created or written, or holds files that cannot be read).

    Parameters
    ----------
    directory : path
        The cache directory that could not be used.
    error : exception
        What went wrong (its message is quoted).
    consequence : str
        What the user loses, e.g. "the averaging tables are rebuilt in every process (~6 s each)".
    fix : str
        How to fix it.
    """
    key = os.path.abspath(os.fspath(directory))
    if key in _WARNED_DIRS:
        return
    _WARNED_DIRS.add(key)
    warnings.warn(f"the cache directory {key} cannot be used ({error}): {consequence}; {fix}", CacheWarning,
                  stacklevel=3)


def atomic_write(path: str | os.PathLike, write: Callable[[Any], None]) -> None:
    """Write ``path`` atomically: ``write(fh)`` fills a temporary file in the same directory (created if
    missing), which then replaces ``path`` (``os.replace``).  On any error the temporary file is removed
    and the error re-raised; ``path`` is then unchanged."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def array_checksum(key: str, arrays: Mapping[str, NDArray[Any]], order: tuple[str, ...]) -> str:
    """SHA-256 (hex) of ``key`` and the arrays named in ``order`` (see the module docstring for the bytes)."""
    h = hashlib.sha256(key.encode("utf-8") + b"\0")
    for name in order:
        a = np.asarray(arrays[name], order="C")
        h.update(f"{name}\0{a.dtype.str}\0{a.shape!r}\0".encode("utf-8"))
        h.update(a.tobytes())
    return h.hexdigest()


def save_arrays(path: str | os.PathLike, key: str, arrays: Mapping[str, ArrayLike]) -> None:
    """Write ``arrays`` (float64, in the given order) with ``key`` and their checksum to ``path`` (.npz),
    atomically.  Raises OSError if the file cannot be written."""
    data = {name: np.asarray(a, dtype=np.float64, order="C") for name, a in arrays.items()}
    # Any: np.savez takes the arrays as keywords beside its own allow_pickle: bool, so a dict of arrays cannot be typed
    members: dict[str, Any] = dict(data)
    members[KEY_FIELD] = np.array(key)
    members[CHECKSUM_FIELD] = np.array(array_checksum(key, data, tuple(data)))
    atomic_write(path, lambda fh: np.savez(fh, **members))


def load_arrays(path: str | os.PathLike, key: str,
                spec: Mapping[str, tuple[int, ...]]) -> tuple[dict[str, NDArray[np.float64]] | None, str]:
    """Read and check an array file written by :func:`save_arrays`.

    Parameters
    ----------
    path : path
        The .npz file.
    key : str
        The key the file must carry.
    spec : mapping
        Expected fields, in checksum order, each a float64 array of the given shape.

    Returns
    -------
    (arrays, reason)
        The arrays and "" if every check passes; otherwise None and why the file was refused (not a
        regular file, too large, not a zip file, unexpected or missing members, a member larger than its
        expected size, object or other non-float64 arrays, a wrong shape, non-finite values, a wrong key, a
        wrong checksum).
        Nothing in the file is unpickled: the members are read with ``numpy.load(..., allow_pickle=False)``,
        after their declared sizes have been checked against ``spec``.
    """
    expected = sorted([f"{name}.npy" for name in spec] + [f"{KEY_FIELD}.npy", f"{CHECKSUM_FIELD}.npy"])
    limits = {f"{name}.npy": 8 * int(np.prod(shape, dtype=np.int64)) + _HEADER_SLACK for name, shape in spec.items()}
    limits[f"{KEY_FIELD}.npy"] = 4 * len(key) + _HEADER_SLACK
    limits[f"{CHECKSUM_FIELD}.npy"] = 4 * 64 + _HEADER_SLACK
    try:
        st = os.stat(path)
        if not stat.S_ISREG(st.st_mode):  # a directory, a FIFO (reading it would block), a device
            return None, "it is not a regular file"
        if st.st_size > sum(limits.values()) + len(limits) * _HEADER_SLACK:
            return None, f"it is larger ({st.st_size} bytes) than the expected contents"
        with zipfile.ZipFile(path) as zf:
            infos = zf.infolist()
            names = sorted(i.filename for i in infos)
            if names != expected:
                odd = sorted({n for n in names if names.count(n) > 1 or n not in expected})
                return None, (f"its members differ from the expected ones (missing "
                              f"{sorted(set(expected) - set(names))}, unexpected or repeated {odd})")
            big = [i.filename for i in infos if i.file_size > limits[i.filename]]
            if big:
                return None, f"members larger than expected: {big}"
        arrays: dict[str, NDArray[Any]] = {}
        with np.load(path, allow_pickle=False) as z:
            for name in list(spec) + [KEY_FIELD, CHECKSUM_FIELD]:
                arrays[name] = z[name]
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, zipfile.LargeZipFile) as exc:
        return None, f"unreadable ({type(exc).__name__}: {exc})"
    stored_key, stored_sum = arrays.pop(KEY_FIELD), arrays.pop(CHECKSUM_FIELD)
    for name, a in ((KEY_FIELD, stored_key), (CHECKSUM_FIELD, stored_sum)):
        if a.dtype.kind != "U" or a.shape != ():
            return None, f"{name} is not a string"
    if str(stored_key) != key:
        return None, "it was written for another key"
    for name, shape in spec.items():
        a = arrays[name]
        if a.dtype != np.float64 or a.shape != tuple(shape):
            return None, f"{name} has dtype {a.dtype} and shape {a.shape}, expected float64 {tuple(shape)}"
        if not np.all(np.isfinite(a)):
            return None, f"{name} has non-finite values"
    if str(stored_sum) != array_checksum(key, arrays, tuple(spec)):
        return None, "its checksum does not match its contents"
    return arrays, ""


#: Seconds of a build of a compiled integrator after which it is announced on stderr: one from heyoka's disk cache
#: takes a fraction of a second, a compilation ten seconds or more.
COMPILE_NOTE_AFTER = 2.0


#: Whether the compile note points to ``rocknroller warm`` (not while warm itself compiles).
_WARM_HINT = threading.local()


@contextmanager
def warming() -> Iterator[None]:
    """Inside this context (``rocknroller warm``), the compile note does not tell the user to run warm."""
    _WARM_HINT.off = True
    try:
        yield
    finally:
        _WARM_HINT.off = False


@contextmanager
def compiling(what: str, seconds: float) -> Iterator[None]:
    """Build a compiled integrator inside this context: if the build is still running after ``COMPILE_NOTE_AFTER``
    seconds (a compilation, not a load from heyoka's disk cache), one line on stderr says what is being compiled, how
    long that usually takes (``seconds``, measured on one core) and that it happens once per machine."""
    hint = "" if getattr(_WARM_HINT, "off", False) else "; 'rocknroller warm' compiles all integrators ahead of time"
    with note_after(COMPILE_NOTE_AFTER, f"rocknroller: compiling {what} (once per machine, usually ~{seconds:.0f} s "
                                        f"CPU; kept in heyoka's disk cache{hint})"):
        yield


@contextmanager
def note_after(seconds: float, line: str) -> Iterator[threading.Event]:
    """Print ``line`` on stderr if the context is still running after ``seconds``; the event yielded is set once it
    was printed (for a closing line)."""
    said = threading.Event()

    def note() -> None:
        said.set()
        print(line, file=sys.stderr, flush=True)

    timer = threading.Timer(seconds, note)
    timer.daemon = True
    timer.start()
    try:
        yield said
    finally:
        timer.cancel()
