"""The bounded in-memory cache (``numerics.cache.MemoryCache``) shared by threads."""

from __future__ import annotations

import sys
import threading
from types import SimpleNamespace

import numpy as np

from rocknroller.numerics.cache import MemoryCache


def test_memory_cache_is_safe_under_threads():
    """Threads storing, reading and counting at once (the atlas and threaded ensembles share the tables' caches):
    without a lock a store's evictions interleaved with another thread's byte count, and 7 of 8 threads died with
    "OrderedDict mutated during iteration".  With a fine thread switch interval the interleavings are many; no
    thread may fail, and the budget holds at the end."""
    values = [SimpleNamespace(a=np.zeros(100)) for _ in range(64)]  # 800 bytes each
    cache = MemoryCache(4 * 800)
    errors: list[str] = []

    def worker(k: int) -> None:
        try:
            for i in range(5000):
                key = (7 * k + i) % 64
                cache[key] = values[key]
                cache.get((key + 3) % 64)
                assert cache.nbytes <= cache.max_bytes
        except Exception as exc:  # noqa: BLE001 - any failure of a thread is the test's failure
            errors.append(repr(exc))

    interval = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)
    try:
        threads = [threading.Thread(target=worker, args=(k,)) for k in range(8)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
    finally:
        sys.setswitchinterval(interval)
    assert errors == [] and len(cache) == 4 and cache.nbytes == 4 * 800
