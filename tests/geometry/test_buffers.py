"""The buffer pool: memory is reused only when nothing refers to it, and a turtle + mesh
built in reused (dirty) memory equals one built in fresh memory."""

from __future__ import annotations

import threading

import numpy as np
import pytest

from sylva.geometry import buffers
from sylva.geometry.build import build_branches
from sylva.lsystem.lstring import Alphabet, ModuleString
from sylva.turtle import interpret

from .words import expand

BIG = (1_000_000, 3)  # 12 MB of float32: pooled


@pytest.fixture(autouse=True)
def _fresh_pool():
    buffers.release()
    old = buffers.set_limit(1 << 30)
    yield
    buffers.set_limit(old)
    buffers.release()


def _span(a: np.ndarray) -> tuple[int, int]:
    return a.ctypes.data, a.ctypes.data + a.nbytes


def test_memory_is_reused_only_after_every_view_is_gone():
    a = buffers.empty(BIG, np.float32)
    ptr = a.ctypes.data
    view = a[::2]
    del a
    b = buffers.empty(BIG, np.float32)
    assert b.ctypes.data != ptr  # a view of the first block is alive
    del view
    c = buffers.empty((2_000_000,), np.float64)  # 16 MB does not fit a 15 MB block
    assert c.ctypes.data != ptr
    d = buffers.empty((800_000, 3), np.float32)
    assert d.ctypes.data == ptr
    assert d.shape == (800_000, 3) and d.dtype == np.float32 and d.flags.c_contiguous
    assert d.flags.writeable


def test_blocks_handed_out_together_never_overlap():
    got: list[np.ndarray] = []
    lock = threading.Lock()

    def worker():
        for k in range(4):
            a = buffers.empty((500_000 + 1000 * k, 3), np.float32)
            with lock:
                got.append(a)

    threads = [threading.Thread(target=worker) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    spans = sorted(_span(a) for a in got)
    assert len(spans) == 16
    assert all(spans[k][1] <= spans[k + 1][0] for k in range(len(spans) - 1))


def test_limit_release_and_small_arrays():
    assert buffers.empty((10, 3), np.float32).base is None  # small: plain numpy
    a = buffers.empty(BIG, np.float32)
    used, free = buffers.held()
    assert used >= a.nbytes and free == 0
    del a
    used, free = buffers.held()
    assert used == 0 and free >= 12_000_000
    buffers.release()
    assert buffers.held() == (0, 0)
    buffers.set_limit(0)  # off: every array is numpy's own
    b = buffers.empty(BIG, np.float32)
    assert b.flags.owndata and buffers.held() == (0, 0)
    with pytest.raises(ValueError, match=">= 0"):
        buffers.set_limit(-1)


def test_free_blocks_beyond_the_limit_are_given_back():
    buffers.set_limit(40_000_000)
    blocks = [buffers.empty((2_500_000, 3), np.float32) for _ in range(4)]  # 4 x ~37 MB
    del blocks
    buffers.empty((10, 3), np.float32)
    buffers.empty((100,), np.uint8)
    a = buffers.empty((4_000_000, 3), np.float32)  # fits none: a new block, the free trimmed
    used, free = buffers.held()
    assert used >= a.nbytes and free <= 40_000_000


def _in_pool(a: np.ndarray) -> bool:
    lo, hi = _span(a)
    return any(
        row[0].ctypes.data <= lo and hi <= row[0].ctypes.data + row[1] for row in buffers._blocks
    )


def _poison_free_blocks():
    for row in buffers._blocks:
        if buffers._refs(row) <= buffers._FREE_REFS:
            row[0][:] = 0xFF  # NaN in floats, huge in integers


def test_turtle_and_mesh_in_reused_memory_equal_fresh_ones():
    text = expand("X", {"X": "F[&+X]/[&-X]\\[^X]FX", "F": "FF"}, 9)  # 262,000 segments
    alphabet = Alphabet()
    table = np.zeros(128, np.int32)
    for ch in sorted(set(text)):
        table[ord(ch)] = alphabet.id(ch)
    word = ModuleString(alphabet, table[np.frombuffer(text.encode(), np.uint8)])

    def build():
        g = interpret(word, dialect="abop", rot=28.0, thick=0.05, thick_factor=0.85)
        m = build_branches(g, detail=8)  # 5 M triangles
        return g, m

    buffers.set_limit(0)
    g0, m0 = build()
    assert g0.seg_start.nbytes > buffers.MIN_BYTES  # every record and mesh array is pooled
    buffers.set_limit(1 << 30)
    g1, m1 = build()
    del g1, m1
    _poison_free_blocks()
    g2, m2 = build()
    assert all(_in_pool(a) for a in (g2.seg_start, g2.seg_end, m2.vertices, m2.indices))
    for name in ("seg_start", "seg_end", "seg_radius", "seg_parent", "seg_ref"):
        np.testing.assert_array_equal(getattr(g2, name), getattr(g0, name))
    for name in ("vertices", "normals", "uvs", "indices"):
        np.testing.assert_array_equal(getattr(m2, name), getattr(m0, name))


@pytest.mark.skipif(not hasattr(__import__("os"), "fork"), reason="needs fork")
def test_a_forked_child_allocates_and_trims():
    import os
    import warnings

    keep = buffers.empty(BIG, np.float32)
    keep[:] = 1.0
    with warnings.catch_warnings():  # Python >= 3.12 warns of fork() beside threads
        warnings.simplefilter("ignore", DeprecationWarning)
        pid = os.fork()
    if pid == 0:  # the child: the pool works, its timer can be armed again
        try:
            a = buffers.empty(BIG, np.float32)
            ok = a.ctypes.data != keep.ctypes.data and buffers._timer is not None
            del a
            buffers.release()
            os._exit(0 if ok and buffers.held()[1] == 0 else 1)
        except BaseException:
            os._exit(2)
    _, status = os.waitpid(pid, 0)
    assert os.WEXITSTATUS(status) == 0


def test_the_limit_from_the_environment(monkeypatch):
    monkeypatch.setenv("SYLVA_BUFFER_POOL", "123456789")
    assert buffers._default_limit() == 123456789
    monkeypatch.setenv("SYLVA_BUFFER_POOL", "lots")
    with pytest.warns(RuntimeWarning, match="number of bytes"):
        assert 0 < buffers._default_limit() <= 2 << 30
