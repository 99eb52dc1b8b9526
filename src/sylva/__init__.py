"""sylva: grow plants, their textures and the worlds they stand in.

One line grows, renders, saves or shows a plant, a tree or a world:

>>> import sylva
>>> plant = sylva.grow("axiom = X\\nX -> F[+X][-X]FX\\nF -> FF", 3)
>>> plant.stats["modules"]
143
>>> plant.render(size=(80, 60)).size
(80, 60)
>>> sylva.tree("fan_palm", age=1.0, leaves=False).stats["name"]
'fan palm'

:func:`grow` takes a :class:`Program`, a path, a built-in example's name, L-system text, a
tree species or a tree file; ``.render()``, ``.save(path)`` (any format, by extension),
``.animate(path)``, ``.show()`` (the notebook view of :mod:`sylva.widgets`) and ``.stats``
work the same on what :func:`grow`, :func:`tree` and :func:`world` return.  ``sylva.tree``
and ``sylva.world`` are also the subpackages of the tree model and the voxel worlds: calling
them is the one-line API, their attributes are the full one.

The language itself:

>>> program = sylva.loads("axiom = X\\nX -> F[+X][-X]FX\\nF -> FF")
>>> len(sylva.derive(program, 3))
143
"""

import sys as _sys
import types as _types

from . import _jit
from .errors import GrowthLimitError, LSystemSemanticError, LSystemSyntaxError, SylvaError
from .lsystem import (
    Derivation,
    ModuleString,
    Program,
    define,
    dumps,
    iterate,
    load,
    load_all,
    loads,
    render_word,
)

# every sylva process (CLI subprocesses, Dask workers, the studio, the tests' workers) may
# compile into one numba cache with others: its saves take the cache folder's lock
_jit.after_numba(_jit.serialise_cache_saves)

__all__ = [
    "Derivation",
    "GrowthLimitError",
    "LSystemSemanticError",
    "LSystemSyntaxError",
    "ModuleString",
    "Program",
    "SylvaError",
    "define",
    "derive",
    "dumps",
    "grow",
    "iterate",
    "load",
    "load_all",
    "loads",
    "render_word",
    "tree",
    "world",
]
__version__ = "0.1.0"


class _TreePackage(_types.ModuleType):
    """``sylva.tree``: the tree subpackage, and called, :func:`sylva.grown.tree`."""

    def __call__(self, *args, **kwargs):
        """Grow a tree of a species: see :func:`sylva.grown.tree`."""
        from .grown import tree

        return tree(*args, **kwargs)


class _WorldPackage(_types.ModuleType):
    """``sylva.world``: the world subpackage, and called, :func:`sylva.grown.world`."""

    def __call__(self, *args, **kwargs):
        """Generate a voxel world: see :func:`sylva.grown.world`."""
        from .grown import world

        return world(*args, **kwargs)


_CALLABLE = {"tree": _TreePackage, "world": _WorldPackage}


class _Sylva(_types.ModuleType):
    # The import system binds a subpackage to its parent with setattr: this is where
    # sylva.tree and sylva.world become callable, however (and whenever) they are imported.
    def __setattr__(self, name, value):
        cls = _CALLABLE.get(name)
        if cls is not None and type(value) is _types.ModuleType:
            value.__class__ = cls
        super().__setattr__(name, value)


_sys.modules[__name__].__class__ = _Sylva


def _register_ipython() -> None:
    # in a notebook (IPython already loaded) scenes and meshes display as images
    ipython = _sys.modules.get("IPython")
    shell = getattr(ipython, "get_ipython", lambda: None)() if ipython else None
    if shell is not None and hasattr(shell, "display_formatter"):
        from ._shown import register_ipython

        register_ipython(shell)


_register_ipython()


def derive(program, steps=None, *, seed=None, limit=None, lineage=False, environment=None):
    """The word after ``steps`` derivation steps: :func:`sylva.lsystem.derive`, and for a
    program with query modules (``?P ?H ?U ?L``) the turtle answers them between steps,
    for one with communication modules (``?E``) the ``environment`` (default: the
    program's own; :func:`sylva.plant.derive`)."""
    from .lsystem import DEFAULT_MODULE_LIMIT
    from .lsystem.environment import has_communication, has_queries

    limit = DEFAULT_MODULE_LIMIT if limit is None else limit
    if has_queries(program) or has_communication(program):
        from .plant import derive as _derive

        return _derive(program, steps, seed=seed, limit=limit, lineage=lineage,
                       environment=environment)  # fmt: skip
    from .lsystem import derive as _derive

    return _derive(program, steps, seed=seed, limit=limit, lineage=lineage)


def __getattr__(name: str):
    # lazy: the renderer, the tree model and the worlds load on first use
    if name == "grow":
        from .grown import grow

        globals()["grow"] = grow
        return grow
    if name in _CALLABLE:
        import importlib

        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
