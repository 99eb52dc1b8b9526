"""The whole suite's hooks for ``pytest -n`` (pytest-xdist, ``make test``'s way).

* Each worker process serialises numba's disk-cache writes (the workers compile into one
  cache: :func:`sylva._jit.serialise_cache_saves`).
* On the workers, the slowest modules come first in the collection, the others after
  them in their usual order: ``--dist loadfile --no-loadscope-reorder`` hands whole modules
  out in collection order, and a long module that started last would finish alone.
  Serial runs keep the usual order.
"""

from __future__ import annotations

# The slowest modules, slowest first: wall seconds of the serial suite after `sylva warmup`
# (`python benchmarks/cold_test.py pytest --cache DIR`, 2026-12-02, at load 6-8 on the
# 2-core VM; 1,238 s in all, 399 CPU s).  The other 127 modules take 0-19 s each.
SLOW_FIRST = (
    "tests/studio/test_browser.py",  # 118 s (Chromium)
    "tests/texture/test_graph.py",  # 111 s
    "tests/test_cold_start.py",  # 85 s
    "tests/texture/test_graph_glsl.py",  # 77 s
    "tests/world/test_cluster.py",  # 52 s
    "tests/test_docs.py",  # 48 s
    "tests/geometry/test_clients.py",  # 46 s (Blender, POV-Ray, OpenSCAD, node)
    "tests/cli/test_gallery.py",  # 43 s
    "tests/cli/test_write_failures.py",  # 33 s
    "tests/widgets/test_frontend.py",  # 31 s
    "tests/studio/test_fuzz.py",  # 26 s
    "tests/world/test_tiles.py",  # 24 s
    "tests/widgets/test_notebook.py",  # 21 s
    "tests/test_architecture.py",  # 21 s
    "tests/studio/test_attack.py",  # 21 s
    "tests/texture/test_graph_kernel_reuse.py",  # 20 s
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
