"""The random streams of the tree's components, made sooner (private).

Every stem run, bud and leaf set draws from its own stream,
``np.random.default_rng([seed, *key])``: a PCG64 generator seeded through NumPy's
``SeedSequence``.  A tree makes thousands of them, and the ``SeedSequence`` (hashing the
entropy in Python-facing code, a lock, an ``errstate``) costs several times what the
generator's draws do.  :func:`stream` makes the same generator, the same stream bit for bit,
from the seed hash computed by a compiled kernel
(:func:`sylva.tree._kernels.seed_state`).

The cold-start road of :mod:`sylva._jit`: while that kernel is not compiled (a fresh
install's first run), the stream comes from ``default_rng`` itself — the same numbers, with
no compile to wait for, until a process has made enough streams for compiling to pay (a
few mature trees); ``sylva warmup`` (inside :func:`sylva._jit.compiled`) and
``SYLVA_JIT=always`` compile it, ``SYLVA_JIT=never`` never uses it.
"""

from __future__ import annotations

import contextlib
import contextvars
import os

import numpy as np
from numpy.random.bit_generator import ISeedSequence

from ._kernels import seed_state

__all__ = ["decided", "stream", "uniform"]

_WORD = 1 << 32
_PAYS = 20_000  # streams made without the kernel, after which compiling it pays (~5 trees)
_state = {"fast": None, "slow": 0}  # fast None: not decided yet in this process
# True inside :func:`decided` once the compiled hash is taken (no look-ups per stream)
_taken: contextvars.ContextVar[bool] = contextvars.ContextVar("sylva_tree_streams",
                                                              default=False)


class _Hashed(ISeedSequence):
    """A seed sequence whose state is already hashed (what ``PCG64`` asks of it)."""

    __slots__ = ("state",)

    def __init__(self, state: np.ndarray) -> None:
        self.state = state

    def generate_state(self, n_words, dtype=np.uint32):
        if n_words != 4 or np.dtype(dtype) != np.uint64:
            raise ValueError("a hashed seed only seeds a PCG64")
        return self.state


def _fast() -> bool:
    """Whether :func:`stream` takes the compiled hash (decided once, except in warm-ups)."""
    env = os.environ.get("SYLVA_JIT", "")
    if not env and _state["fast"]:
        return True  # decided (the common case: skip the look-ups below)
    from .. import _jit

    if env == "never":
        return False
    if env == "always" or _jit._small.get() == "off":
        return True
    if _state["fast"] is None:
        _state["fast"] = _jit._kernel_cached(seed_state)
    if not _state["fast"]:
        _state["slow"] += 1
        _state["fast"] = _state["slow"] >= _PAYS  # work enough now for a compile to pay
    return _state["fast"]


@contextlib.contextmanager
def decided():
    """Inside: :func:`stream` takes the compiled hash without asking :func:`_fast` each
    time, when it is taken at the start (a tree's growth makes thousands of streams; the
    environment look-up was a fifth of each).  Either road gives the same streams."""
    token = _taken.set(True) if _fast() else None
    try:
        yield
    finally:
        if token is not None:
            _taken.reset(token)


def stream(*words: int) -> np.random.Generator:
    """``np.random.default_rng(list(words))``: the same generator, from the compiled hash.

    ``words`` are non-negative integers (a seed masked to 32 bits and a component's key).
    """
    if (_taken.get() or _fast()) and min(words) >= 0 and max(words) < _WORD:
        state = seed_state(np.array(words, np.int64))
        return np.random.Generator(np.random.PCG64(_Hashed(state)))
    return np.random.default_rng(list(words))


def uniform(rng: np.random.Generator, low: float = 0.0, high: float = 1.0) -> float:
    """``rng.uniform(low, high)`` bit for bit, at a third of its cost.

    NumPy draws it as ``low + (high - low) * next_double`` (``random_uniform`` of its
    distributions), the same double :meth:`~numpy.random.Generator.random` returns, from one
    step of the stream; the Python arithmetic is the same IEEE operations without the
    argument broadcasting of ``uniform`` (``tests/tree/test_streams.py`` holds the two equal).
    """
    return low + (high - low) * rng.random()
