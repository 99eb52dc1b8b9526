"""Reuse of the memory behind large result arrays (turtle records, meshes).

A fresh array from the operating system costs its pages twice: the kernel zeroes every page
on first touch, then the builder writes it.  On the 2-core machines sylva is measured on,
writing 640 MB into fresh pages takes about twice as long as writing it into pages already
touched.  Builders that make hundreds of megabytes again and again — the studio re-deriving
on every edit, a growth animation meshing frame after frame, a world growing plant after
plant — take their large arrays from this pool instead of :func:`numpy.empty`.

The pool keeps every block it has handed out.  A block is reused only when nothing but the
pool refers to it any more: a :class:`~sylva.geometry.Mesh` or turtle record that is still
alive, or any view of its arrays, keeps its memory.  Free blocks are given back to the
operating system when they have stayed unused for :data:`IDLE_SECONDS`, when the free blocks
together exceed the limit (:func:`set_limit`, by default a quarter of the machine's memory
and at most 2 GiB; ``SYLVA_BUFFER_POOL`` in bytes overrides it, 0 turns the pool off), and on
:func:`release`.  Arrays below :data:`MIN_BYTES` come from NumPy as usual.

Examples
--------
>>> import numpy as np
>>> release()   # no free blocks of earlier work: the pool hands out a fresh one
>>> a = empty((2_000_000, 3), np.float32)
>>> a.shape, a.dtype.name
((2000000, 3), 'float32')
>>> ptr = a.ctypes.data
>>> b = empty((2_000_000, 3), np.float32)   # a is alive: another block
>>> b.ctypes.data != ptr
True
>>> del a
>>> c = empty((1_500_000, 3), np.float32)   # a's block, its pages already touched
>>> c.ctypes.data == ptr
True
>>> release()
"""

from __future__ import annotations

import os
import sys
import threading
import time
import warnings

import numpy as np

__all__ = ["IDLE_SECONDS", "MIN_BYTES", "empty", "held", "release", "set_limit"]

MIN_BYTES = 4 << 20
"""Arrays smaller than this are not pooled (the C allocator reuses small blocks itself)."""

IDLE_SECONDS = 10.0
"""A free block unused for this long is given back to the operating system."""

_GROW = 1.25  # a new block has room to spare: a plant one step bigger reuses it
_lock = threading.Lock()
_blocks: list[list] = []  # [raw uint8 array, capacity, time found free or 0.0]
_timer: threading.Timer | None = None


def _refs(row: list) -> int:
    """References to the block of ``row``, as counted here (the count differs between
    Python versions; :data:`_FREE_REFS` is measured by this same function)."""
    return sys.getrefcount(row[0])


_FREE_REFS = _refs([np.empty(1, np.uint8)])  # only the pool's row refers to a free block


def _default_limit() -> int:
    env = os.environ.get("SYLVA_BUFFER_POOL")
    if env is not None:
        try:
            return max(int(env), 0)
        except ValueError:
            warnings.warn(
                f"SYLVA_BUFFER_POOL must be a number of bytes, got {env!r}: using the default",
                RuntimeWarning,
                stacklevel=2,
            )
    try:
        total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        total = 8 << 30
    return min(total // 4, 2 << 30)


_limit = _default_limit()


def set_limit(nbytes: int) -> int:
    """Hold at most ``nbytes`` of free blocks (0 turns the pool off); returns the old limit."""
    global _limit
    if nbytes < 0:
        raise ValueError(f"the pool's limit must be >= 0 bytes, got {nbytes}")
    with _lock:
        old, _limit = _limit, int(nbytes)
        _trim(time.monotonic(), 0.0 if nbytes == 0 else None)
    return old


def held() -> tuple[int, int]:
    """``(bytes in use, bytes free)`` of the pool's blocks."""
    used = free = 0
    with _lock:
        for row in _blocks:
            if _refs(row) <= _FREE_REFS:
                free += row[1]
            else:
                used += row[1]
    return used, free


def release() -> None:
    """Give every free block back to the operating system now."""
    with _lock:
        _trim(time.monotonic(), 0.0)


def empty(shape, dtype) -> np.ndarray:
    """An uninitialised C-contiguous array, like :func:`numpy.empty`, from a free block of
    the pool when one is large enough."""
    dtype = np.dtype(dtype)
    shape = (int(shape),) if np.ndim(shape) == 0 else tuple(int(k) for k in shape)
    nbytes = int(np.prod(shape, dtype=np.int64)) * dtype.itemsize
    if nbytes < MIN_BYTES or _limit == 0:
        return np.empty(shape, dtype)
    with _lock:
        best = None
        for row in _blocks:
            if (
                nbytes <= row[1] <= 2 * nbytes
                and (best is None or row[1] < best[1])
                and _refs(row) <= _FREE_REFS
            ):
                best = row
        if best is None:
            cap = int(nbytes * _GROW)
            best = [np.empty(cap, np.uint8), cap, 0.0]
            _blocks.append(best)
        best[2] = 0.0
        out = best[0][:nbytes].view(dtype).reshape(shape)  # the block is in use from here
        if len(_blocks) > 1:
            _trim(time.monotonic(), None)
        _arm()
    return out


def _trim(now: float, idle: float | None) -> None:
    """Drop free blocks found free ``idle`` seconds ago or longer (``None``: only beyond the
    limit), then the oldest free ones while the free bytes exceed the limit.  Holds _lock."""
    free = []
    for k, row in enumerate(_blocks):
        if _refs(row) <= _FREE_REFS:
            if row[2] == 0.0:
                row[2] = now
            free.append(k)
        else:
            row[2] = 0.0
    drop = set()
    if idle is not None:
        drop = {k for k in free if now - _blocks[k][2] >= idle}
    kept = [k for k in free if k not in drop]
    total = sum(_blocks[k][1] for k in kept)
    for k in sorted(kept, key=lambda k: _blocks[k][2]):
        if total <= _limit:
            break
        drop.add(k)
        total -= _blocks[k][1]
    if drop:
        _blocks[:] = [row for k, row in enumerate(_blocks) if k not in drop]


def _arm() -> None:
    """Start the idle check, unless it runs.  Holds _lock."""
    global _timer
    if _timer is None:
        _timer = threading.Timer(IDLE_SECONDS / 2, _tick)
        _timer.daemon = True
        _timer.start()


def _after_fork() -> None:
    """A forked child has no timer thread and may hold a copy of a taken lock: start clean
    (its copies of the blocks stay in the pool; the next check trims them)."""
    global _lock, _timer
    _lock = threading.Lock()
    _timer = None


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_after_fork)


def _tick() -> None:
    global _timer
    with _lock:
        _timer = None
        _trim(time.monotonic(), IDLE_SECONDS)
        if _blocks:
            _arm()
