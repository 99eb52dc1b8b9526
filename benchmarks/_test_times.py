"""A pytest plugin for ``benchmarks/cold_test.py``: each test's wall and CPU seconds and
the kernels numba compiles while the tests run, written as JSON to ``$SYLVA_TEST_TIMES``.

CPU seconds are this process's (all its threads) plus those of the children it waited
for (``RUSAGE_CHILDREN``: POV-Ray, node, Blender ...).  Under pytest-xdist each worker
writes its own file, ``$SYLVA_TEST_TIMES.<worker id>`` (``gw0``, ``gw1`` ...), with its
process's CPU seconds at the end (``proc_cpu``); the controller writes the plain path.
"""

from __future__ import annotations

import json
import os
import resource
import time

import pytest

_tests: list[dict] = []
_compiles: list[dict] = []
_state = {"test": "(collection)", "collect": 0.0, "t0": 0.0}


def _cpu() -> float:
    me = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def pytest_configure(config):
    from numba.core import event as ev

    stack = []

    class _Listener(ev.Listener):
        def on_start(self, event):
            stack.append([time.process_time(), 0.0])

        def on_end(self, event):
            t0, inner = stack.pop()
            dt = time.process_time() - t0
            if stack:
                stack[-1][1] += dt
            f = event.data["dispatcher"].py_func
            _compiles.append({"module": f.__module__, "name": f.__qualname__,
                              "args": str(event.data["args"]), "self": dt - inner,
                              "test": _state["test"]})  # fmt: skip

    ev.register("numba:compile", _Listener())
    _state["t0"] = time.perf_counter()


def pytest_collection_finish(session):
    # (not called in xdist's controller, which collects nothing: 0 there)
    _state["collect"] = time.perf_counter() - _state["t0"]


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    _state["test"] = item.nodeid
    rec = {"id": item.nodeid, "setup": 0.0}
    w, c = time.perf_counter(), _cpu()
    yield
    rec["wall"], rec["cpu"] = time.perf_counter() - w, _cpu() - c
    _tests.append(rec)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_setup(item):
    w = time.perf_counter()
    yield
    _setup[item.nodeid] = time.perf_counter() - w


_setup: dict[str, float] = {}


def _loaded() -> list[dict]:
    """Every sylva kernel signature loaded from numba's disk cache in this session (a
    kernel compiled into a caller is loaded with it, not on its own)."""
    import sys

    from numba.core.registry import CPUDispatcher

    out = []
    for name, mod in list(sys.modules.items()):
        if not name.startswith("sylva.") or mod is None:
            continue
        for v in list(vars(mod).values()):
            if isinstance(v, CPUDispatcher) and v.py_func.__module__ == name:
                for sig, n in v._cache_hits.items():
                    out.append({"module": name, "name": v.py_func.__qualname__,
                                "args": str(sig), "hits": n})  # fmt: skip
    return out


def pytest_sessionfinish(session, exitstatus):
    for t in _tests:
        t["setup"] = _setup.get(t["id"], 0.0)
    loaded = _loaded()
    path = os.environ.get("SYLVA_TEST_TIMES")
    worker = os.environ.get("PYTEST_XDIST_WORKER")
    if path:
        with open(f"{path}.{worker}" if worker else path, "w") as fh:
            json.dump({"tests": _tests, "compiles": _compiles, "loaded": loaded,
                       "collect_wall": _state["collect"], "worker": worker,
                       "proc_cpu": _cpu()}, fh)  # fmt: skip
