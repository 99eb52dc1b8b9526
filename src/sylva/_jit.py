"""Numba's cold start, seen from sylva (private).

Three things, none of which imports numba until it is needed:

* :func:`lazy` — a stand-in for a kernel module that imports it on first use, so that
  ``import sylva`` does not import numba (half a second) or any kernel module;
* :func:`announce` — tells the user on stderr, once per kernel module and with progress,
  that a first run compiles kernels (a fresh install has none cached), instead of a silent
  wait of tens of seconds;
* :data:`KERNEL_MODULES` — every module of compiled kernels, by the name the message uses
  (``sylva warmup`` compiles them ahead).
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
import threading
import time
from types import ModuleType

__all__ = ["KERNEL_MODULES", "announce", "lazy"]

#: Every module that defines numba kernels, and what the progress message calls it.
KERNEL_MODULES = {
    "sylva.lsystem._kernels": "derivation",
    "sylva.turtle._kernels": "turtle",
    "sylva.geometry._kernels": "mesh",
    "sylva.geometry._simd": "mesh",
    "sylva.texture._kernels": "noise",
    "sylva.texture._gridkernels": "noise",
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


class _AfterNumba(importlib.abc.MetaPathFinder):
    """Registers the listener once numba has been imported (by whatever needs it), so that
    a command that compiles nothing does not import numba for the message's sake."""

    def __init__(self, prog: _Progress):
        self.prog = prog

    def find_spec(self, name, path=None, target=None):
        if name != "numba":
            return None
        sys.meta_path.remove(self)
        spec = importlib.util.find_spec(name)
        if spec is None or spec.loader is None:
            return spec
        loader, prog = spec.loader, self.prog

        class _Loader(importlib.abc.Loader):
            def create_module(self, spec):
                return loader.create_module(spec)

            def exec_module(self, module):
                loader.exec_module(module)
                _register(prog)

        spec.loader = _Loader()
        return spec


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
        if "numba" in sys.modules:
            _register(prog)
        else:
            sys.meta_path.insert(0, _AfterNumba(prog))
        return prog
