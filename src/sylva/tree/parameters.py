"""Parameters and parameter spaces (seed 002 §4.10, the Rose parametric subsystem).

A parameter is identified by ``(name, type, space)``.  Three types exist: 32-bit integers,
floats with a *deviation* and a *fixed random value*, and text.  The fixed random value of
a float is drawn **once, when the parameter is registered in a space**, uniformly in
``[value - |deviation|, value + |deviation|]`` (the seed leaves the distribution open; this
is our choice).  The draw is seeded by ``(seed, space key, parameter name)``, so it does not
depend on the order of registration and the same seed gives the same tree everywhere.
A negative deviation is kept with its sign: components read it as a *special mode* (the
Weber–Penn ``nDownAngleV < 0`` rule is one, see :mod:`sylva.tree.weber_penn`).

Spaces: one **global** space, one space **per level** and one space **per slot**.
:meth:`ParameterManager.resolve` searches them in the order slot (nearest toward the root)
→ level of the asking component → global.

Examples
--------
>>> pm = ParameterManager.from_text('[global]\\nScale = 10 ± 2\\n[level 1]\\nBranches = 40\\n',
...                                 seed=7)
>>> p = pm.global_space.get("Scale")
>>> 8.0 <= p.fixed <= 12.0, p.fixed == ParameterManager.from_text(
...     '[global]\\nScale = 10 ± 2\\n', seed=7).global_space.get("Scale").fixed
(True, True)
>>> pm.level(1).value("Branches")
40
"""

from __future__ import annotations

import os
import re
import zlib
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import LSystemSyntaxError, SylvaError
from ._config import parse_blocks

__all__ = [
    "FloatParameter",
    "IntParameter",
    "ParameterError",
    "ParameterManager",
    "ParameterSpace",
    "TextParameter",
]

_INT32 = (-(2**31), 2**31 - 1)


class ParameterError(SylvaError, KeyError):
    """A missing parameter, or one of the wrong type."""

    def __str__(self) -> str:  # KeyError quotes its message; we do not
        return str(self.args[0]) if self.args else ""


@dataclass
class IntParameter:
    """A 32-bit signed integer (counts: branches, leaves, animation frames)."""

    name: str
    value: int
    kind = "int"

    def __post_init__(self) -> None:
        v = int(self.value)
        if not _INT32[0] <= v <= _INT32[1]:
            raise ParameterError(f"integer parameter {self.name!r} = {v} does not fit 32 bits")
        self.value = v


@dataclass
class FloatParameter:
    """A float with a deviation and a fixed random value.

    Attributes
    ----------
    value : float
        The initial (mean) value; components may update it during simulation.
    deviation : float
        Usually the largest displacement from ``value``; negative for special modes.
    fixed : float
        Drawn once at registration in ``[value - |deviation|, value + |deviation|]`` and never
        changed afterwards (NaN until registered).
    """

    name: str
    value: float
    deviation: float = 0.0
    fixed: float = float("nan")
    kind = "float"

    def sample(self, rng: np.random.Generator) -> float:
        """A fresh draw in ``value ± |deviation|`` from ``rng`` (per-component variation)."""
        d = abs(self.deviation)
        # rng.uniform(-d, d) bit for bit: -d + (d - -d) * next_double (sylva.tree._streams)
        return float(self.value + (-d + (d + d) * rng.random() if d else 0.0))


@dataclass
class TextParameter:
    """Any string (material names, texture names, enumerations)."""

    name: str
    value: str
    kind = "text"


Parameter = IntParameter | FloatParameter | TextParameter


def _name_key(name: str) -> int:
    return zlib.crc32(name.encode("utf-8"))


@dataclass
class ParameterSpace:
    """A store of parameters with lookup by name and registration (``ParameterSpace``).

    Parameters
    ----------
    key : tuple of int
        Identifies the space for seeding: ``(0,)`` global, ``(1, n)`` level ``n``,
        ``(2, component id, slot index)`` a slot.
    seed : int
        Simulation seed; fixed random values come from ``(seed, key, name)``.
    """

    key: tuple[int, ...] = (0,)
    seed: int = 0
    _items: dict[str, Parameter] = field(default_factory=dict, repr=False)

    def register(self, param: Parameter, *, replace: bool = True) -> Parameter:
        """Register ``param``; a float gets its fixed random value now (once).

        Re-registering a name replaces the parameter (and draws again) unless ``replace`` is
        false, in which case the existing parameter is returned.
        """
        if param.name in self._items and not replace:
            return self._items[param.name]
        if isinstance(param, FloatParameter):
            d = abs(param.deviation)
            if d:
                rng = np.random.default_rng([self.seed & 0xFFFFFFFF, *self.key,
                                             _name_key(param.name)])
                param.fixed = float(param.value + rng.uniform(-d, d))
            else:
                param.fixed = float(param.value)
        self._items[param.name] = param
        return param

    def set_int(self, name: str, value: int) -> IntParameter:
        return self.register(IntParameter(name, value))

    def set_float(self, name: str, value: float, deviation: float = 0.0) -> FloatParameter:
        return self.register(FloatParameter(name, float(value), float(deviation)))

    def set_text(self, name: str, value: str) -> TextParameter:
        return self.register(TextParameter(name, str(value)))

    def update(self, name: str, value) -> None:
        """Change a registered value (readers see it at once; a float keeps its fixed value)."""
        p = self._items.get(name)
        if p is None:
            raise ParameterError(f"cannot update {name!r}: it is not registered in this space")
        p.value = type(p.value)(value)

    def get(self, name: str, kind: str | None = None) -> Parameter | None:
        """The parameter ``name`` (of ``kind`` when given), or ``None``."""
        p = self._items.get(name)
        if p is None or (kind is not None and p.kind != kind):
            return None
        return p

    def value(self, name: str, default=None):
        p = self._items.get(name)
        return default if p is None else p.value

    def __contains__(self, name: object) -> bool:
        return name in self._items

    def __iter__(self) -> Iterator[Parameter]:
        return iter(self._items.values())

    def __len__(self) -> int:
        return len(self._items)


_LEVEL_NAME = re.compile(r"^(\d+)([A-Za-z_]\w*)$")


class ParameterManager:
    """The global space, the per-level spaces and the name mapping; loads configurations.

    Names written the Weber–Penn way are mapped on loading: ``1DownAngle`` in any block goes
    to level 1 as ``DownAngle``; ``XV`` (or ``nXV``) sets the deviation of ``X`` when ``X`` is
    a float in the same target space, so paper tables can be pasted as they are.

    Parameters
    ----------
    seed : int
        The simulation seed (fixed random values and everything grown from them).
    """

    def __init__(self, seed: int = 0) -> None:
        self.seed = int(seed)
        self.global_space = ParameterSpace((0,), self.seed)
        self._levels: dict[int, ParameterSpace] = {}
        self.source: str | None = None

    # -- spaces -----------------------------------------------------------------------------
    def level(self, n: int) -> ParameterSpace:
        """The space of level ``n`` (created empty on first use)."""
        n = int(n)
        if n not in self._levels:
            self._levels[n] = ParameterSpace((1, n), self.seed)
        return self._levels[n]

    @property
    def levels(self) -> list[int]:
        return sorted(self._levels)

    def slot_space(self, component_id: int, slot_index: int) -> ParameterSpace:
        """A new per-slot space keyed by its owner's id and the slot index."""
        return ParameterSpace((2, int(component_id), int(slot_index)), self.seed)

    # -- lookup -----------------------------------------------------------------------------
    def resolve(self, name: str, component=None, *, level: int | None = None,
                kind: str | None = None) -> Parameter | None:
        """Find ``name``: slot spaces from ``component`` toward the root, then the level space
        (``level`` or the component's), then the global space; ``None`` when absent."""
        if component is not None:
            p = component.slot_parameter(name, kind)
            if p is not None:
                return p
            if level is None:
                level = component.level
        if level is not None and level in self._levels:
            p = self._levels[level].get(name, kind)
            if p is not None:
                return p
        return self.global_space.get(name, kind)

    def _need(self, name, component, level, kind):
        p = self.resolve(name, component, level=level, kind=kind)
        if p is None:
            where = f"level {level}" if level is not None else "the global space"
            raise ParameterError(f"missing {kind} parameter {name!r} (looked in slots, {where})")
        return p

    def float(self, name: str, component=None, *, level: int | None = None,
              default: float | None = None) -> FloatParameter:
        """A float parameter (an int is promoted); ``default`` builds one when absent."""
        p = self.resolve(name, component, level=level)
        if p is None and default is not None:
            return FloatParameter(name, float(default), 0.0, float(default))
        if p is not None and p.kind == "int":
            return FloatParameter(name, float(p.value), 0.0, float(p.value))
        return self._need(name, component, level, "float")

    def int(self, name: str, component=None, *, level: int | None = None,
            default: int | None = None) -> int:
        p = self.resolve(name, component, level=level)
        if p is None and default is not None:
            return int(default)
        if p is not None and p.kind == "float" and float(p.value).is_integer():
            return int(p.value)
        return self._need(name, component, level, "int").value

    def text(self, name: str, component=None, *, level: int | None = None,
             default: str | None = None) -> str:
        p = self.resolve(name, component, level=level, kind="text")
        if p is None and default is not None:
            return default
        return self._need(name, component, level, "text").value

    # -- configuration files ----------------------------------------------------------------
    @classmethod
    def from_text(cls, text: str, seed: int = 0, filename: str | None = None) -> ParameterManager:
        pm = cls(seed)
        pm.load_text(text, filename)
        return pm

    @classmethod
    def from_file(cls, path: str | os.PathLike, seed: int = 0) -> ParameterManager:
        path = Path(path)
        pm = cls(seed)
        pm.load_text(path.read_text(encoding="utf-8"), str(path))
        return pm

    def load_text(self, text: str, filename: str | None = None) -> None:
        """Read ``[global]`` and ``[level N]`` blocks (see :mod:`sylva.tree._config`)."""
        self.source = filename
        pending: dict[tuple[int | None, str], list] = {}
        order: list[tuple[int | None, str]] = []
        for block in parse_blocks(text, filename):
            if block.kind == "global":
                base_level = None
            elif block.kind == "level":
                arg = (block.argument or "").strip()
                if not arg.isdigit():
                    raise LSystemSyntaxError.at(
                        f"expected '[level N]' with a level number N >= 0, got {arg!r}",
                        text, block.line, 1, filename,
                    )
                base_level = int(arg)
            else:
                raise LSystemSyntaxError.at(
                    f"unknown block [{block.kind}]: expected [global] or [level N]",
                    text, block.line, 1, filename,
                )
            for e in block.entries:
                level, name = base_level, e.name
                m = _LEVEL_NAME.match(name)
                if m:
                    level, name = int(m.group(1)), m.group(2)
                if e.kind == "vector":
                    raise LSystemSyntaxError.at(
                        f"{e.name}: expected one number, text or 'number ± deviation'",
                        text, e.line, e.column, filename,
                    )
                key = (level, name)
                if key not in pending:
                    order.append(key)
                pending[key] = [e, level, name]
        # "XV" entries become deviations of "X" when X is a number in the same space
        for key in list(order):
            e, level, name = pending[key]
            base = (level, name[:-1])
            if name.endswith("V") and base in pending and pending[base][0].kind in ("int", "float"):
                if e.kind not in ("int", "float"):
                    raise LSystemSyntaxError.at(
                        f"{e.name}: a deviation must be a number", text, e.line, e.column, filename
                    )
                b = pending[base][0]
                pending[base][0] = type(b)(b.name, "float", float(b.value), float(e.value),
                                           b.line, b.column)
                order.remove(key)
        for key in order:
            e, level, name = pending[key]
            space = self.global_space if level is None else self.level(level)
            if e.kind == "int":
                space.register(IntParameter(name, e.value))
            elif e.kind == "float":
                space.register(FloatParameter(name, e.value, e.deviation))
            elif e.kind == "bool":
                space.register(IntParameter(name, int(e.value)))
            else:
                space.register(TextParameter(name, e.value))

    def dumps(self) -> str:
        """The configuration as text in the block format (loads back to the same values)."""
        def line(p: Parameter) -> str:
            if p.kind == "text":
                return f'{p.name} = "{p.value}"'
            if p.kind == "int":
                return f"{p.name} = {p.value}"
            if p.deviation:
                return f"{p.name} = {p.value!r} ± {p.deviation!r}"
            return f"{p.name} = {float(p.value)!r}"

        out = ["[global]", *(line(p) for p in self.global_space)]
        for n in self.levels:
            out += ["", f"[level {n}]", *(line(p) for p in self._levels[n])]
        return "\n".join(out) + "\n"
