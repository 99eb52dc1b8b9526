"""Numba's cold start, seen from sylva (private).

Five things, none of which imports numba until it is needed:

* :func:`lazy` — a stand-in for a kernel module that imports it on first use, so that
  ``import sylva`` does not import numba (half a second) or any kernel module;
* :func:`announce` — tells the user on stderr, once per kernel module and with progress,
  that a first run compiles kernels (a fresh install has none cached), instead of a silent
  wait of tens of seconds;
* :data:`KERNEL_MODULES` — every module of compiled kernels, by the name the message uses
  (``sylva warmup`` compiles them ahead);
* :func:`road` and :func:`small` — the interpreted road: on a cold cache, small work runs
  the kernels' own Python source (numba's ``DISABLE_JIT``, in a copy of the module) instead
  of waiting for them to compile.  The first image of a small plant then comes in a second
  or two; the kernels compile (with the message above) the first time work is large enough
  for compiling to pay, or ahead in ``sylva warmup``;
* :func:`serialise_cache_saves` — numba's cache writes made safe for several processes
  compiling into one cache.
"""

from __future__ import annotations

import contextlib
import contextvars
import importlib
import importlib.abc
import importlib.util
import os
import sys
import threading
import time
from types import ModuleType

__all__ = [
    "KERNEL_MODULES",
    "announce",
    "cold",
    "compiled",
    "interpreted",
    "interpreting",
    "lazy",
    "road",
    "serialise_cache_saves",
    "small",
]

#: Every module that defines numba kernels, and what the progress message calls it.
KERNEL_MODULES = {
    "sylva.lsystem._kernels": "derivation",
    "sylva.turtle._kernels": "turtle",
    "sylva.geometry._kernels": "mesh",
    "sylva.geometry._simd": "mesh",
    "sylva.texture._kernels": "noise",
    "sylva.texture._gridkernels": "noise",
    "sylva.texture._gridkernels32": "noise",
    "sylva.texture._simplex32": "noise",
    "sylva.texture._lattice4_32": "noise",
    "sylva.texture._cellkernels": "noise",
    "sylva.texture._sampling": "texture",
    "sylva.texture._raster": "texture",
    "sylva.texture._fractal_kernels": "fractal",
    "sylva.tree._kernels": "tree",
    "sylva.world._kernels": "world",
    "sylva._light_kernels": "light",
}


class _Lazy(ModuleType):
    """A module object that imports the real module at the first attribute access and
    then holds its attributes itself (later accesses cost what a module's do)."""

    def __init__(self, name: str):
        super().__init__(name)
        self.__dict__["_lazy_lock"] = threading.Lock()

    def __getattr__(self, attr: str):
        with self.__dict__["_lazy_lock"]:
            real = importlib.import_module(self.__name__)
            self.__dict__.update(
                {k: v for k, v in vars(real).items() if k not in ("__name__", "__spec__")}
            )
        try:
            return self.__dict__[attr]
        except KeyError:
            raise AttributeError(f"module {self.__name__!r} has no attribute {attr!r}") from None


def lazy(name: str) -> ModuleType:
    """``name`` as a module that is imported when first used (or the module itself when
    it is imported already)."""
    return sys.modules.get(name) or _Lazy(name)


# ----------------------------------------------------------------------- the message
_state = {"on": False, "listener": None}
_lock = threading.Lock()


def _count_kernels(modname: str) -> int:
    """The kernels of a module that compile on their own (``inline="always"`` ones are
    compiled into their callers)."""
    mod = sys.modules.get(modname)
    if mod is None:
        return 0
    from numba.core.registry import CPUDispatcher

    n = 0
    for v in vars(mod).values():
        if isinstance(v, CPUDispatcher) and v.targetoptions.get("inline", "never") != "always":
            n += 1
    return n


class _Progress:
    """Counts the kernels of each sylva kernel module as numba compiles them."""

    def __init__(self, stream=None):
        self._stream = stream  # None: whatever sys.stderr is at the time of writing
        self.done: dict[str, set] = {}
        self.total: dict[str, int] = {}
        self.announced: set[str] = set()
        self.t0 = None
        self.line = False

    @property
    def stream(self):
        return self._stream if self._stream is not None else sys.stderr

    def _write(self, text: str) -> None:
        # a message must never break a compile (a closed or redirected stream, a test's
        # capture that has ended …)
        try:
            self.stream.write(text)
            self.stream.flush()
        except (OSError, ValueError, AttributeError):
            pass

    def _tty(self) -> bool:
        try:
            return bool(self.stream.isatty())
        except (OSError, ValueError, AttributeError):
            return False

    def start(self, dispatcher) -> None:
        mod = getattr(dispatcher.py_func, "__module__", "")
        label = KERNEL_MODULES.get(mod)
        if label is None:
            return
        with _lock:
            if self.t0 is None:
                self.t0 = time.perf_counter()
            if label not in self.total:
                self.total[label] = sum(
                    _count_kernels(m) for m, lb in KERNEL_MODULES.items() if lb == label
                )
                self.done[label] = set()
            done = self.done[label]
            done.add(dispatcher.py_func.__qualname__)
            k = len(done)
            n = max(self.total[label], k)
            text = f"compiling sylva's {label} kernels, once: {k}/{n}"
            if self._tty():
                self._write(f"\r{text} ({dispatcher.py_func.__name__})\x1b[K")
                self.line = True
            elif label not in self.announced:
                self._write(
                    f"sylva: {text} (a first run compiles what it uses and caches it; "
                    "`sylva warmup` compiles everything ahead)\n"
                )
            self.announced.add(label)

    def finish(self) -> None:
        if self.line:
            secs = time.perf_counter() - (self.t0 or time.perf_counter())
            self._write(f"\rcompiled sylva's kernels in {secs:.0f} s (cached now)\x1b[K\n")
            self.line = False


def _register(prog: _Progress) -> None:
    from numba.core import event

    class _Listener(event.Listener):
        def on_start(self, ev):
            prog.start(ev.data["dispatcher"])

        def on_end(self, ev):
            pass

    event.register("numba:compile", _Listener())


_after: list = []  # callables to run once numba has been imported (after_numba)


def _run_after() -> None:
    with _lock:
        todo, _after[:] = list(_after), []
    for fn in todo:
        try:
            fn()
        except Exception as exc:  # never the user's ``import numba`` that fails for it
            import warnings

            warnings.warn(f"sylva: {getattr(fn, '__name__', fn)!s} after numba's import "
                          f"failed: {exc}", RuntimeWarning, stacklevel=2)  # fmt: skip


class _AfterNumba(importlib.abc.MetaPathFinder):
    """Runs the :func:`after_numba` callables once numba has been imported (by whatever
    needs it), so that a command that compiles nothing does not import numba for them."""

    def find_spec(self, name, path=None, target=None):
        if name != "numba":
            return None
        if self in sys.meta_path:
            sys.meta_path.remove(self)
        spec = importlib.util.find_spec(name)
        if spec is None or spec.loader is None:
            return spec
        loader = spec.loader

        class _Loader(importlib.abc.Loader):
            def create_module(self, spec):
                return loader.create_module(spec)

            def exec_module(self, module):
                loader.exec_module(module)
                _run_after()

        spec.loader = _Loader()
        return spec


def after_numba(fn) -> None:
    """Call ``fn()`` now if numba is imported, else right after numba's first import (in
    the order of the calls); never imports numba itself."""
    with _lock:
        if "numba" not in sys.modules:
            _after.append(fn)
            if not any(isinstance(f, _AfterNumba) for f in sys.meta_path):
                sys.meta_path.insert(0, _AfterNumba())
            return
    fn()


def announce(stream=None) -> _Progress:
    """From now on, write to ``stream`` (default: ``sys.stderr`` at each write) when numba
    starts compiling a sylva kernel module's kernels, once per module on a file and with
    progress on a terminal; idempotent.  Does not import numba (the message starts when
    numba is imported)."""
    with _lock:
        prog = _state["listener"]
        if prog is not None:
            return prog
        prog = _Progress(stream)
        _state["listener"] = prog
    after_numba(lambda: _register(prog))
    return prog


# ------------------------------------------------------------------- the interpreted road
# "" (compiled; sized roads decide by size), "cold" (interpreted while the kernels are not
# compiled), "all" (interpreted), "off" (compiled, whatever the size: warm-ups)
_small: contextvars.ContextVar[str] = contextvars.ContextVar("sylva_small_work", default="")
_copies: dict[str, ModuleType] = {}
_copy_lock = threading.RLock()


def interpreted(name: str, deps: tuple[str, ...] = ()) -> ModuleType:
    """A copy of the kernel module ``name`` whose kernels are their plain Python functions.

    The copy executes the module's source with numba's ``DISABLE_JIT`` on (``njit`` then
    returns the function it decorates), while the sylva kernel modules in ``deps`` that it
    imports are themselves interpreted copies (each dep's copy with the deps listed before
    it).  A module may name, in ``_INTERPRETED``, Python stand-ins for kernels or names
    that cannot run as Python, or not on whole arrays (numba intrinsics, ``math``):
    ``{name: stand-in}``.  The real module is not touched; copies are made once per
    process.
    """
    with _copy_lock:
        mod = _copies.get(name)
        if mod is not None:
            return mod
        for i, dep in enumerate(deps):  # a dep may import those before it (in that order)
            interpreted(dep, deps[:i])
        from numba.core import config

        spec = importlib.util.find_spec(name)
        mod = importlib.util.module_from_spec(spec)
        saved = {d: sys.modules.get(d) for d in deps}
        # ``from . import dep`` reads the package's attribute, not sys.modules
        parents = {d: sys.modules.get(d.rpartition(".")[0]) for d in deps}
        attrs = {d: vars(p).get(d.rpartition(".")[2]) for d, p in parents.items() if p}
        old = config.DISABLE_JIT
        config.DISABLE_JIT = True
        try:
            for d in deps:
                sys.modules[d] = _copies[d]
                if parents[d] is not None:
                    setattr(parents[d], d.rpartition(".")[2], _copies[d])
            spec.loader.exec_module(mod)
        finally:
            config.DISABLE_JIT = old
            for d, m in saved.items():
                if m is None:
                    sys.modules.pop(d, None)
                else:
                    sys.modules[d] = m
            for d, p in parents.items():
                if p is None:
                    continue
                leaf = d.rpartition(".")[2]
                if attrs.get(d) is None:
                    p.__dict__.pop(leaf, None)
                else:
                    setattr(p, leaf, attrs[d])
        for kernel, stand_in in getattr(mod, "_INTERPRETED", {}).items():
            setattr(mod, kernel, getattr(mod, stand_in))
        _copies[name] = mod
        return mod


def _kernels_of(mod: ModuleType) -> list:
    """The kernels of ``mod`` that compile on their own (its own, not imported ones)."""
    from numba.core.registry import CPUDispatcher

    return [v for v in vars(mod).values()
            if isinstance(v, CPUDispatcher) and v.py_func.__module__ == mod.__name__
            and v.targetoptions.get("inline", "never") != "always"]  # fmt: skip


def _kernel_cached(fn) -> bool:
    """Whether the kernel ``fn`` is compiled in this process or in numba's disk cache."""
    try:
        if fn.signatures:
            return True
        cache = getattr(fn, "_cache", None)
        return cache is None or bool(cache._cache_file._load_index())
    except Exception:  # numba's cache internals changed: take the compiled road
        return True


def _largest(args) -> int:
    n = 0
    for a in args:
        size = getattr(a, "size", None)
        if isinstance(size, int) and hasattr(a, "dtype"):
            n = max(n, size)
        elif isinstance(a, tuple):
            n = max(n, _largest(a))
    return n


class _Road(ModuleType):
    """A kernel module, or its interpreted copy while :func:`small` work runs on a cold
    cache, attribute by attribute: an attribute whose kernels (itself, or those its code
    calls) are all compiled or cached is the compiled one.  With ``size``, each
    kernel also decides by itself, call by call: while it is not compiled, a call whose
    largest array has at most ``size`` elements runs interpreted."""

    def __init__(self, name: str, deps: tuple[str, ...], size: int | None = None):
        super().__init__(name)
        self.__dict__.update(_road_name=name, _road_deps=deps, _road_cold={},
                             _road_size=size)  # fmt: skip

    def _sized(self, attr: str, fn):
        """``fn`` (a kernel) behind a per-call choice of road, kept in place of the
        attribute so that later accesses cost nothing."""
        d = self.__dict__
        size, state = d["_road_size"], {"warm": None}

        def call(*args):
            env, mode = os.environ.get("SYLVA_JIT", ""), _small.get()
            if env != "never" and mode != "all":
                if mode == "off" or env == "always":
                    return fn(*args)
                warm = state["warm"]
                if warm is None or (not warm and fn.signatures):
                    warm = state["warm"] = _kernel_cached(fn)
                if warm or _largest(args) > size:
                    return fn(*args)
            with _quiet():
                return getattr(interpreted(d["_road_name"], d["_road_deps"]), attr)(*args)

        call.__name__ = call.__qualname__ = attr
        call.__doc__ = fn.__doc__
        call.__wrapped__ = fn
        d[attr] = call
        return call

    def _pick(self, attr: str):
        """The attribute from the compiled module or from its interpreted copy."""
        d = self.__dict__
        real = sys.modules.get(d["_road_name"]) or importlib.import_module(d["_road_name"])
        value = getattr(real, attr)
        mode = _small.get()
        if mode in ("", "off") or not callable(value):
            return value
        if mode == "cold":
            cold = d["_road_cold"].get(attr)
            if cold is None:  # read numba's disk cache once; later, what compiled here
                cold = d["_road_cold"][attr] = [
                    k for k in _needs(value, real) if not _kernel_cached(k)
                ]
            if all(k.signatures for k in cold):
                return value
        return getattr(interpreted(d["_road_name"], d["_road_deps"]), attr)

    def __getattr__(self, attr: str):
        d = self.__dict__
        if attr.startswith("__"):
            raise AttributeError(attr)
        if d["_road_size"] is not None:
            real = importlib.import_module(d["_road_name"])
            fn = getattr(real, attr)
            if _is_kernel(fn):
                return self._sized(attr, fn)
        return self._pick(attr)


def _needs(value, module: ModuleType) -> list:
    """The kernels that calling ``value`` (an attribute of ``module``) runs: itself if it
    is one, else those its code names in the module, through the module's plain functions
    (a kernel's own callees are compiled into it)."""
    if _is_kernel(value):
        return [value]
    out, seen, todo = [], set(), [value]
    while todo:
        f = todo.pop()
        code = getattr(f, "__code__", None)
        if code is None or id(f) in seen:
            continue
        seen.add(id(f))
        codes = [code]
        while codes:
            c = codes.pop()
            codes.extend(x for x in c.co_consts if hasattr(x, "co_names"))
            for name in c.co_names:
                g = vars(module).get(name)
                if _is_kernel(g):
                    out.append(g)
                elif getattr(g, "__module__", None) == module.__name__:
                    todo.append(g)
    return out


def interpreting(kernels: ModuleType, *attrs: str) -> bool:
    """Whether any of ``attrs`` of the :func:`road` ``kernels`` is its interpreted copy's
    here and now (work split over threads should then stay in one: the copy holds the
    GIL, and the threads would not see this context's choice)."""
    if not isinstance(kernels, _Road):
        return False
    real = importlib.import_module(kernels.__name__)
    return any(kernels._pick(a) is not getattr(real, a) for a in attrs)


_warm: dict[int, bool] = {}


def cold(kernel, work: int, size: int) -> bool:
    """Whether a call that would run ``kernel`` (a numba dispatcher) on ``work`` units
    should take an interpreted road instead: while the kernel is neither compiled in this
    process nor in numba's disk cache and ``work`` is at most ``size`` (outside
    :func:`compiled`); always under ``SYLVA_JIT=never``, never under ``SYLVA_JIT=always``.
    For callers that run a kernel module's source on whole arrays (the lattice noises)
    rather than through :func:`road`."""
    env, mode = os.environ.get("SYLVA_JIT", ""), _small.get()
    if env == "never" or mode == "all":
        return True
    if env == "always" or mode == "off" or work > size:
        return False
    warm = _warm.get(id(kernel))
    if warm is None or (not warm and kernel.signatures):
        warm = _warm[id(kernel)] = _kernel_cached(kernel)
    return not warm


def _is_kernel(fn) -> bool:
    from numba.core.registry import CPUDispatcher

    return isinstance(fn, CPUDispatcher)


def road(name: str, deps: tuple[str, ...] = (), *, size: int | None = None) -> ModuleType:
    """The kernel module ``name`` as its users should hold it: compiled, except inside
    :func:`small` on a cold cache, where it is :func:`interpreted` (``deps``: the sylva
    kernel modules it imports kernels from); with ``size``, also any call of a kernel not
    compiled yet whose largest array has at most ``size`` elements.  Nothing is imported
    until the first attribute access.  ``SYLVA_JIT=always`` turns the interpreted road
    off, ``SYLVA_JIT=never`` takes it for all work (the tests compare the roads)."""
    with _copy_lock:
        r = _roads.get(name)
        if r is None:
            r = _roads[name] = _Road(name, deps, size)
        return r


_roads: dict[str, _Road] = {}


@contextlib.contextmanager
def small(is_small: bool):
    """Work inside is small enough (``is_small``) to run interpreted while its kernels are
    not compiled yet: a fraction of a second in Python against tens of seconds of
    compiling."""
    mode = os.environ.get("SYLVA_JIT", "")
    if mode == "never":
        token = _small.set("all")
    elif _small.get() == "off":
        token = _small.set("off")
    else:
        token = _small.set("cold" if is_small and mode != "always" else "")
    try:
        if _small.get() in ("cold", "all"):
            with _quiet():
                yield
        else:
            yield
    finally:
        _small.reset(token)


@contextlib.contextmanager
def compiled():
    """Inside, every kernel takes its compiled road whatever the size of the work (a
    warm-up that runs tiny work to compile the kernels)."""
    token = _small.set("off")
    try:
        yield
    finally:
        _small.reset(token)


def _quiet():
    """Compiled kernels wrap integer arithmetic (the hashes count on it) and divide floats
    by zero without a word; their Python source, run by NumPy scalars, would warn."""
    import numpy as np

    return np.errstate(over="ignore", divide="ignore", invalid="ignore")


# ----------------------------------------------------------- numba's cache, many processes
def serialise_cache_saves() -> None:
    """Make numba's disk-cache writes safe when several processes compile into one cache
    (``sylva warmup``'s workers, the test suite on ``pytest -n``); idempotent.

    numba writes each cache file whole (a temporary file, then a rename), but it saves a
    new signature as read index, add an entry, write index, write data, unlocked: two
    processes that save two signatures of one kernel at once both take data file 1, and
    the index can end up naming the other signature's code for a signature (numba
    0.68, ``numba/core/caching.py``, ``IndexDataCacheFile.save``).  Here each save holds
    an exclusive ``flock`` of the cache folder, so that the second process reads the
    index the first wrote.  Loads take no lock (both files are replaced whole).
    """
    try:
        import fcntl
    except ImportError:  # not POSIX: numba's own saves
        return
    from numba.core import caching

    real = caching.IndexDataCacheFile.save
    if getattr(real, "_sylva_serialised", False):
        return

    def save(self, key, data):
        try:
            fd = os.open(self._cache_path, os.O_RDONLY)
        except OSError:  # a folder that cannot be opened: numba's own (unlocked) save
            return real(self, key, data)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)
            real(self, key, data)
        finally:
            os.close(fd)  # closing the folder releases the lock

    save._sylva_serialised = True
    save.__wrapped__ = real
    caching.IndexDataCacheFile.save = save
