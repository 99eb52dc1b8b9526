"""The Studio's Tree and World modes: Weber–Penn trees and voxel worlds, by the public API.

Tree mode lists the species (:func:`sylva.tree.species_names`), shows every parameter a
species file may set in the groups and with the ranges and meanings of the annotated example
(:func:`sylva.tree.species.example_text`), and grows the edited parameters with
:func:`sylva.tree` (a species file written to a temporary folder and checked there, so a bad
value comes back with the field it was in and its allowed range).  World mode generates a
world with :func:`sylva.world` and shows its biome map beside the 3D view.  Both are drawn by
the same viewer as the L-systems: their scene as binary glTF.
"""

from __future__ import annotations

import io
import math
import re
import tempfile
import time
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

from ..errors import LSystemSyntaxError, SylvaError

__all__ = ["Grown", "grow_tree", "grow_world", "species_fields", "species_list", "tree_schema"]

MAX_WORLD = 256  # columns along x and z
MAX_AGE = 1000.0
MAX_WIND = 10.0

_ENTRY = re.compile(r"^\s*([A-Za-z_0-9]+)\s*=\s*(.*?)\s*(?:#\s*(.*))?$")
_BLOCK = re.compile(r"^\s*\[\s*(global|level\s+\d+)\s*\]\s*(?:#\s*(.*))?$")
_RANGE = re.compile(r"^([\[(])\s*(-?[\d.]+|-inf)\s*,\s*(-?[\d.]+|inf)\s*\]\s*(.*)$")
_DOTS = re.compile(r"^(-?\d+)\s*…\s*(\d+)\s*(.*)$")


@dataclass
class Grown:
    """A tree or world of a session: its scene, GLB and what the client shows."""

    kind: str  # "tree" or "world"
    name: str
    scene: object
    glb: bytes
    background: tuple
    stats: dict
    obj: object = None  # the TreePlant or WorldView
    key: tuple = ()
    extra: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)

    def export(self, fmt: str) -> bytes:
        from ._work import scene_bytes

        return self.glb if fmt == "glb" else scene_bytes(self.scene, fmt)


def _glb(scene) -> bytes:
    from ..geometry.exchange import write_glb

    buf = io.BytesIO()
    write_glb(scene, buf)
    return buf.getvalue()


# --------------------------------------------------------------------------- the schema
def _parse_range(comment: str) -> dict:
    """``[lo, hi] meaning`` / ``(lo, hi] …`` / ``lo…hi …`` / ``text: …`` → field fields."""
    m = _RANGE.match(comment)
    if m:
        lo = -math.inf if m.group(2) == "-inf" else float(m.group(2))
        hi = math.inf if m.group(3) == "inf" else float(m.group(3))
        return {"kind": "number", "lo": lo if math.isfinite(lo) else None,
                "hi": hi if math.isfinite(hi) else None, "open_lo": m.group(1) == "(",
                "doc": m.group(4).strip()}
    m = _DOTS.match(comment)
    if m and m.group(3).startswith("or "):  # LeafShape: a number or a name
        return {"kind": "choice", "doc": comment}
    if m:
        return {"kind": "integer", "lo": float(m.group(1)), "hi": float(m.group(2)),
                "open_lo": False, "doc": m.group(3).strip()}
    if comment.startswith("text:"):
        return {"kind": "text", "doc": comment[5:].strip()}
    if comment.startswith(("true", "true/false")):
        return {"kind": "bool", "doc": comment}
    return {"kind": "choice", "doc": comment}


@lru_cache(maxsize=1)
def tree_schema() -> dict:
    """Every key of a species file, grouped as the annotated example groups them:
    ``{"global": [{group, keys: [field]}], "level": [field], "leaves": [field]}``, each
    field ``{key, kind, lo, hi, open_lo, doc}``."""
    from ..tree.species import example_text

    groups: list[dict] = []
    level: list[dict] = []
    leaves: list[dict] = []
    block = None
    last = None
    for line in example_text().splitlines():
        b = _BLOCK.match(line)
        if b:
            block = b.group(1).replace(" ", "")
            if block == "global":
                groups.append({"group": "Weber & Penn 1995", "keys": []})
            last = None
            continue
        if block is None:
            continue
        if line.lstrip().startswith("# --") and block == "global":
            groups.append({"group": line.split("--", 1)[1].split(":")[0].strip(),
                           "keys": []})
            continue
        e = _ENTRY.match(line)
        if e:
            f = {"key": e.group(1), **_parse_range((e.group(3) or "").strip())}
            last = f
            if block == "global":
                groups[-1]["keys"].append(f)
            elif block == "level3":
                leaves.append(f)
            elif f["key"] not in {x["key"] for x in level}:
                level.append(f)
            else:
                last = None  # a later level's comment on a key already described
            continue
        if last is not None and line.lstrip().startswith("#") and line.startswith(" "):
            last["doc"] += " " + line.strip().lstrip("#").strip()
    # the leaf block's keys are described where they first appear (a level, or [global])
    described = {f["key"]: f for f in level} | {f["key"]: f for g in groups for f in g["keys"]}
    leaves = [{**described[f["key"]], "key": f["key"]} if not f["doc"] and f["key"] in described
              else f for f in leaves]
    return {"global": groups, "level": level, "leaves": leaves}


@lru_cache(maxsize=1)
def species_list() -> list[dict]:
    """The species with their names and descriptions."""
    from ..tree import species_info, species_names

    out = []
    for n in species_names():
        try:
            info = species_info(n)
        except SylvaError:
            continue
        out.append({"species": n, "name": info["Name"], "description": info["Description"]})
    return out


def species_fields(name: str) -> dict:
    """The values a species file sets: ``{"blocks": {"global": {key: text}, "level0": …},
    "extra": {block: [line]}}`` — ``extra`` keeps the lines no field shows (paper names
    such as ``1DownAngle`` and ``ScaleV``), which are written back as they were."""
    from ..tree.species import species_text

    if not isinstance(name, str) or name not in {s["species"] for s in species_list()}:
        raise SylvaError(f"unknown species {name!r}; expected one of "
                         + ", ".join(s["species"] for s in species_list()))
    text, _ = species_text(name)
    schema = tree_schema()
    known_global = {f["key"] for g in schema["global"] for f in g["keys"]}
    known_level = {f["key"] for f in schema["level"]} | {f["key"] for f in schema["leaves"]}
    blocks: dict[str, dict] = {}
    extra: dict[str, list] = {}
    block = None
    for line in text.splitlines():
        b = _BLOCK.match(line)
        if b:
            block = b.group(1).replace(" ", "")
            blocks.setdefault(block, {})
            continue
        e = _ENTRY.match(line)
        if block is None or not e or line.lstrip().startswith("#"):
            continue
        key, value = e.group(1), e.group(2)
        known = known_global if block == "global" else known_level
        if key in known:
            blocks[block][key] = value
        else:
            extra.setdefault(block, []).append(f"{key} = {value}")
    return {"species": name, "blocks": blocks, "extra": extra}


def _species_file(blocks: dict, extra: dict) -> tuple[str, dict]:
    """The species text of the fields, and which field each line holds."""
    if not isinstance(blocks, dict) or not isinstance(extra or {}, dict):
        raise SylvaError("blocks must map block names to {key: value}")
    lines: list[str] = []
    where: dict[int, tuple[str, str]] = {}
    names = sorted(blocks, key=lambda b: (b != "global", int(b[5:]) if b[5:].isdigit() else 0))
    for b in names:
        if b != "global" and not re.fullmatch(r"level\d{1,2}", b):
            raise SylvaError(f"unknown block {b!r}: expected global or levelN")
        fields = blocks[b]
        if not isinstance(fields, dict):
            raise SylvaError(f"block {b} must map keys to values")
        lines.append("[global]" if b == "global" else f"[level {b[5:]}]")
        for key, value in fields.items():
            if not isinstance(key, str) or not re.fullmatch(r"[A-Za-z_][A-Za-z_0-9]{0,40}", key):
                raise SylvaError(f"{b}: {str(key)[:40]!r} is no parameter name")
            if isinstance(value, bool) or not isinstance(value, (str, int, float)):
                raise SylvaError(f"{b}.{key} must be a number or a text")
            value = str(value).strip()
            if not value:
                continue
            if "\n" in value or "\r" in value or len(value) > 200:
                raise SylvaError(f"{b}.{key} must be one short line")
            lines.append(f"{key} = {value}")
            where[len(lines)] = (b, key)
        for line in (extra or {}).get(b, []):
            if isinstance(line, str) and "\n" not in line and len(line) < 200:
                lines.append(line)
    return "\n".join(lines) + "\n", where


def grow_tree(session, *, blocks: dict, extra: dict, age: float, seed: int, wind: float,
              leaves: bool = True) -> Grown:
    """Grow the tree of the edited parameters at ``age`` with ``wind`` (``sylva.tree``)."""
    import sylva

    if not (isinstance(age, (int, float)) and 0 < age <= MAX_AGE):
        raise SylvaError(f"age must be in (0, {MAX_AGE:g}] years")
    if not (isinstance(wind, (int, float)) and 0 <= wind <= MAX_WIND):
        raise SylvaError(f"wind must be in [0, {MAX_WIND:g}]")
    text, where = _species_file(blocks, extra)
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="sylva-studio-tree-") as tmp:
        path = Path(tmp) / "species.txt"
        path.write_text(text, encoding="utf-8")
        try:
            plant = sylva.tree(str(path), age=float(age), seed=int(seed), wind=float(wind),
                               leaves=bool(leaves))
        except LSystemSyntaxError as exc:
            field_ = where.get(exc.line)
            raise FieldError(exc.message, field_) from None
    grow_ms = (time.perf_counter() - t0) * 1e3
    t1 = time.perf_counter()
    scene = plant.scene
    glb = _glb(scene)
    stats = plant.stats
    name = stats["name"].replace(" ", "_") or "tree"
    return Grown("tree", name, scene, glb, (0.62, 0.78, 0.94), stats, plant,
                 timings={"grow_ms": grow_ms, "mesh_ms": (time.perf_counter() - t1) * 1e3})


class FieldError(SylvaError):
    """A bad value in a Tree-mode field: ``field`` is ``(block, key)`` (or ``None``)."""

    def __init__(self, message: str, field_) -> None:
        self.field = field_
        super().__init__(message)


def grow_world(session, *, seed: int, size: int, plants: bool) -> Grown:
    """Generate a world (``sylva.world``) and its biome map."""
    import sylva

    if isinstance(size, bool) or not isinstance(size, int) or not 8 <= size <= MAX_WORLD:
        raise FieldError(f"size must be a whole number of columns in [8, {MAX_WORLD}]",
                         ("world", "size"))
    t0 = time.perf_counter()
    chunk = 16 if size <= 64 else 32
    view = sylva.world(seed=int(seed), size=size, chunk=chunk, plants=bool(plants),
                       grass=False, workers=1)
    grow_ms = (time.perf_counter() - t0) * 1e3
    t1 = time.perf_counter()
    scene = view.scene
    glb = _glb(scene)
    buf = io.BytesIO()
    view.biome_map().save(buf, format="PNG")
    return Grown("world", f"world-{seed}-{size}", scene, glb, (0.62, 0.78, 0.94), view.stats,
                 view, extra={"biomes": buf.getvalue()},
                 timings={"grow_ms": grow_ms, "mesh_ms": (time.perf_counter() - t1) * 1e3})
