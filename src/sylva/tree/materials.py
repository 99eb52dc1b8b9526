"""The name-keyed material database (seed 002 §5.3–5.4).

Every material has a unique name and an identifier (its index); components refer to
materials by name through text parameters (``BarkMaterial``, ``LeafMaterial``), so bark and
leaves can be changed without touching components or geometry.  Attributes: colour, texture,
billboard flag, alpha test with threshold, double-sided flag, plus roughness and a colour
variation used to tint leaves.

File format (the block format of :mod:`sylva.tree._config`, our design — the thesis's §5.7
is not in the seed)::

    [material leaf.aspen]
    color = 0.30 0.52 0.14          # linear RGB (a fourth number is alpha)
    texture = "leaf"                # procedural texture name or an image path
    alpha_test = 0.5                # threshold; omit (or 0) for none
    double_sided = true
    billboard = false
    roughness = 0.7
    variation = 0.12                # per-leaf colour jitter (0: none)

Examples
--------
>>> db = MaterialDatabase.default()
>>> db["bark"].double_sided, db["leaf"].double_sided
(False, True)
>>> db.id_of("leaf") == db.names().index("leaf")
True
"""

from __future__ import annotations

import os
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path

from ..errors import LSystemSyntaxError, SylvaError
from ..geometry.mesh import Material
from ._config import parse_blocks

__all__ = ["MaterialDatabase", "MaterialError", "MaterialSpec"]


class MaterialError(SylvaError, KeyError):
    """An unknown material name."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


@dataclass(frozen=True)
class MaterialSpec:
    """One entry of the database.

    Attributes
    ----------
    name : str
    color : tuple of 4 float
        Linear RGBA.
    texture : str or None
    billboard : bool
        Polygons always face the camera.  Kept in the database for components to read;
        :class:`~sylva.geometry.mesh.Material` has no such field, so exporters and the
        offscreen renderer draw the polygons as they are.
    alpha_test : float or None
        Pixels with texture alpha below this are not drawn.
    double_sided : bool
    roughness : float
    variation : float
        Amplitude of the per-leaf (or per-stem) colour jitter.
    """

    name: str
    color: tuple[float, float, float, float] = (0.8, 0.8, 0.8, 1.0)
    texture: str | None = None
    billboard: bool = False
    alpha_test: float | None = None
    double_sided: bool = False
    roughness: float = 0.8
    variation: float = 0.0

    def to_material(self) -> Material:
        """The :class:`sylva.geometry.mesh.Material` that exporters and the renderer read."""
        return Material(self.name, tuple(float(c) for c in self.color), self.roughness, 0.0,
                        self.texture, self.double_sided, self.alpha_test,
                        billboard=bool(self.billboard))


_FIELDS = {
    "color": "vector", "texture": "text", "billboard": "bool", "alpha_test": "number",
    "double_sided": "bool", "roughness": "number", "variation": "number",
}


class MaterialDatabase:
    """Materials by unique name; the identifier is the registration index."""

    def __init__(self, materials=()) -> None:
        self._items: dict[str, MaterialSpec] = {}
        for m in materials:
            self.register(m)

    def register(self, spec: MaterialSpec) -> int:
        """Add or replace ``spec``; returns its identifier."""
        self._items[spec.name] = spec
        return self.id_of(spec.name)

    def __getitem__(self, name: str) -> MaterialSpec:
        try:
            return self._items[name]
        except KeyError:
            raise MaterialError(
                f"unknown material {name!r}: expected one of {', '.join(self._items)}"
            ) from None

    def get(self, name: str, fallback: str | None = None) -> MaterialSpec:
        """``name``, else the material ``fallback`` (e.g. ``"bark"`` for ``"bark.oak"``)."""
        if name in self._items:
            return self._items[name]
        if fallback is not None and fallback in self._items:
            return replace(self._items[fallback], name=name)
        return self[name]

    def __contains__(self, name: object) -> bool:
        return name in self._items

    def __len__(self) -> int:
        return len(self._items)

    def names(self) -> list[str]:
        return list(self._items)

    def id_of(self, name: str) -> int:
        return self.names().index(self[name].name)

    # -- files -------------------------------------------------------------------------------
    @classmethod
    def from_text(cls, text: str, filename: str | None = None) -> MaterialDatabase:
        db = cls()
        db.load_text(text, filename)
        return db

    @classmethod
    def from_file(cls, path: str | os.PathLike) -> MaterialDatabase:
        path = Path(path)
        return cls.from_text(path.read_text(encoding="utf-8"), str(path))

    @classmethod
    def default(cls) -> MaterialDatabase:
        """The materials shipped with sylva (``sylva/tree/materials.txt``)."""
        text = resources.files(__package__).joinpath("materials.txt").read_text("utf-8")
        return cls.from_text(text, "materials.txt")

    def load_text(self, text: str, filename: str | None = None) -> None:
        for block in parse_blocks(text, filename):
            if block.kind != "material" or not block.argument:
                raise LSystemSyntaxError.at(
                    f"expected '[material NAME]', got [{block.kind}]", text, block.line, 1, filename
                )
            kw: dict = {}
            for e in block.entries:
                want = _FIELDS.get(e.name)
                if want is None:
                    raise LSystemSyntaxError.at(
                        f"unknown material attribute {e.name!r}: expected one of "
                        + ", ".join(_FIELDS), text, e.line, 1, filename,
                    )
                ok = (
                    (want == "vector" and e.kind == "vector" and len(e.value) in (3, 4))
                    or (want == "text" and e.kind == "text")
                    or (want == "bool" and e.kind in ("bool", "int"))
                    or (want == "number" and e.kind in ("int", "float"))
                )
                if not ok:
                    what = {"vector": "3 or 4 numbers", "text": "a quoted text",
                            "bool": "true or false", "number": "a number"}[want]
                    raise LSystemSyntaxError.at(
                        f"{e.name}: expected {what}", text, e.line, e.column, filename
                    )
                v = e.value
                if want == "vector":
                    v = tuple(v) + ((1.0,) if len(v) == 3 else ())
                elif want == "bool":
                    v = bool(v)
                elif want == "text":
                    pass
                elif e.name == "alpha_test":
                    v = float(v) if float(v) > 0 else None
                else:
                    v = float(v)
                kw[e.name] = v
            self.register(MaterialSpec(block.argument.strip(), **kw))

    def dumps(self) -> str:
        out = []
        for m in self._items.values():
            out.append(f"[material {m.name}]")
            out.append("color = " + " ".join(f"{c:.4g}" for c in m.color))
            if m.texture:
                out.append(f'texture = "{m.texture}"')
            if m.alpha_test is not None:
                out.append(f"alpha_test = {m.alpha_test:.4g}")
            out.append(f"double_sided = {'true' if m.double_sided else 'false'}")
            out.append(f"billboard = {'true' if m.billboard else 'false'}")
            out.append(f"roughness = {m.roughness:.4g}")
            out.append(f"variation = {m.variation:.4g}")
            out.append("")
        return "\n".join(out)
