"""The whole suite's hooks for ``pytest -n`` (pytest-xdist, ``make test``'s way).

* Each worker process serialises numba's disk-cache writes (the workers compile into one
  cache: :func:`sylva._jit.serialise_cache_saves`).
* On the workers, the slowest modules come first in the collection, the others after
  them in their usual order: ``--dist loadfile --no-loadscope-reorder`` hands whole modules
  out in collection order, and a long module that started last would finish alone.
  Serial runs keep the usual order.
"""

from __future__ import annotations

# The slowest modules, slowest first: wall seconds (setup included) of `make test`'s run on
# both cores after `sylva warmup` (`pytest -p _test_times -n 2 --dist loadfile`, with
# benchmarks/ on PYTHONPATH; 2026-12-02, load 0.4 at the start, quiet 2-core VM; 2,805
# tests in 193 s, the two workers 177 s each in tests).  The other 133 modules take
# 0-6 s each.
SLOW_FIRST = (
    "tests/studio/test_browser.py",  # 57 s (Chromium)
    "tests/geometry/test_clients.py",  # 35 s (Blender, POV-Ray, OpenSCAD, node)
    "tests/test_cold_start.py",  # 32 s
    "tests/widgets/test_frontend.py",  # 25 s
    "tests/studio/test_fuzz.py",  # 24 s
    "tests/world/test_cluster.py",  # 21 s
    "tests/cli/test_write_failures.py",  # 16 s
    "tests/cli/test_gallery.py",  # 12 s
    "tests/studio/test_attack.py",  # 12 s
    "tests/studio/test_api.py",  # 11 s
    "tests/studio/test_memory.py",  # 8 s
    "tests/world/test_tiles.py",  # 8 s
    "tests/geometry/test_textured_clients.py",  # 7 s
    "tests/studio/test_texture_browser.py",  # 7 s
    "tests/test_parallel_cache.py",  # 6 s
    "tests/widgets/test_notebook.py",  # 6 s
)


def _worker(config) -> bool:
    return hasattr(config, "workerinput")


def pytest_configure(config):
    if _worker(config):
        from sylva._jit import serialise_cache_saves

        serialise_cache_saves()


def pytest_collection_modifyitems(session, config, items):
    if not _worker(config):
        return
    rank = {path: i for i, path in enumerate(SLOW_FIRST)}
    # a stable sort: each module's tests keep their order (and their fixtures' grouping)
    items.sort(key=lambda item: rank.get(item.nodeid.split("::", 1)[0], len(rank)))
