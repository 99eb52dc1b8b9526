"""What a species file may say: every key, its block, its kind and its allowed range.

:func:`check_species` reads a species file's blocks (:func:`~sylva.tree._config.parse_blocks`)
and refuses, with the file, line and column, anything the tree model would otherwise have to
guess at or clamp: an unknown key, a value of the wrong kind or outside its range (the range
is in the message), a deviation that would take the value out of its range, a ``[level N]``
beyond ``Levels`` or a missing one.  ``[level 0]`` … ``[level Levels-1]`` are the stems;
``[level Levels]`` (the crown leaves' ``DownAngle``, ``Rotate`` and their own leaf keys) may be
left out.  The leaf keys (``LeafScale``, ``LeafDensity``, ``LeafTurn``, ``LeafFall`` …, scope
"both") may be set in ``[global]`` or in ``[level N]`` for the leaves of level N, the leaves on
the stems of level N − 1 (:mod:`sylva.tree.leaves`).

The table :data:`KEYS` is the reference for the annotated example
(``sylva tree --example``, :func:`sylva.tree.species.example_text`).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from ..errors import LSystemSyntaxError
from ._config import parse_blocks

__all__ = ["KEYS", "Key", "check_species"]

INF = math.inf


@dataclass(frozen=True)
class Key:
    """One species key: ``scope`` "global", "level" or "both", ``kind`` "int", "float", "text",
    "choice" or "bool"; ``lo``/``hi`` the closed range (``open_lo``: ``lo`` itself is out);
    ``dev`` whether a ``± deviation`` is allowed; ``choices`` for text choices."""

    scope: str
    kind: str
    lo: float = -INF
    hi: float = INF
    open_lo: bool = False
    dev: bool = False
    choices: tuple = ()
    doc: str = ""


def _k(scope, kind, lo=-INF, hi=INF, *, open_lo=False, dev=False, choices=(), doc=""):
    return Key(scope, kind, lo, hi, open_lo, dev, choices, doc)


G, L, B = "global", "level", "both"  # both: [global], or a level for its own leaves
KEYS: dict[str, Key] = {
    # -- identity
    "Name": _k(G, "text", doc="the species' name"),
    "Source": _k(G, "text", doc="where its numbers come from"),
    "Description": _k(G, "text", doc="what a person sees"),
    # -- Weber & Penn 1995, global
    "Shape": _k(G, "int", 0, 8, doc="crown shape 0 conical … 7 flame, 8 the pruning envelope"),
    "BaseSize": _k(G, "float", 0, 0.99, doc="bare part of the trunk (fraction of its length)"),
    "Scale": _k(G, "float", 0, 200, open_lo=True, dev=True, doc="tree size (m) ± ScaleV"),
    "ZScale": _k(G, "float", 0, 10, open_lo=True, dev=True, doc="vertical squash ± ZScaleV"),
    "Levels": _k(G, "int", 1, 5, doc="stem levels (the leaves sit on the last)"),
    "Ratio": _k(G, "float", 0, 0.5, open_lo=True, doc="trunk radius / trunk length"),
    "RatioPower": _k(G, "float", 0, 5, doc="child radius exponent"),
    "Lobes": _k(G, "int", 0, 32, doc="lobes around the trunk"),
    "LobeDepth": _k(G, "float", 0, 1, doc="depth of the trunk's lobes"),
    "Flare": _k(G, "float", 0, 10, doc="trunk flare at the ground"),
    "Scale0": _k(G, "float", 0, 10, open_lo=True, dev=True, doc="trunk radius scale (0Scale)"),
    "BaseSplits": _k(G, "int", 0, 64, doc="clones the trunk splits into at its base"),
    "Leaves": _k(G, "float", 0, 10000, doc="leaves per stem of the last level"),
    "LeafShape": _k(G, "choice", 0, 9, choices=("blade", "ellipse", "disc", "triangle", "palm",
                                               "square", "hexagon", "needles", "oak", "ovate"),
                    doc="0…9 or a name (sylva.tree.meshing.LEAF_SHAPES)"),
    "LeafScale": _k(B, "float", 0, 10, open_lo=True, dev=True, doc="leaf length (m)"),
    "LeafScaleX": _k(B, "float", 0, 10, open_lo=True, doc="leaf width / length"),
    "AttractionUp": _k(G, "float", -10, 10, doc="bend toward (>0) or away from the sky"),
    "PruneRatio": _k(G, "float", 0, 1, doc="how much of the pruning to apply"),
    "PruneWidth": _k(G, "float", 0, 5, open_lo=True, doc="envelope half-width / Scale"),
    "PruneWidthPeak": _k(G, "float", 0, 1, doc="height of the envelope's widest point"),
    "PrunePowerLow": _k(G, "float", 0, 10, doc="envelope curvature below the peak"),
    "PrunePowerHigh": _k(G, "float", 0, 10, doc="envelope curvature above the peak"),
    # -- sylva's additions, global
    "Age": _k(G, "float", 0, 1000, open_lo=True, doc="age of the grown tree (years)"),
    "LeafDelay": _k(G, "float", 0, 100, doc="years from a shoot passing to its leaf"),
    "LeafUnfold": _k(G, "float", 0, 100, open_lo=True, doc="years a leaf takes to unfold"),
    "LeafDensity": _k(B, "float", 0, 100, doc="multiplies Leaves ([level N]: that level's "
                                              "leaves, juvenile ones too)"),
    "LeafArrangement": _k(G, "choice", choices=("spiral", "fan"),
                          doc="'fan': the leaves fan out at the stem's tip (the paper's Leaves<0)"),
    "FanAngle": _k(G, "float", 0, 360, doc="spread of a fan of leaves (degrees)"),
    "BarkMaterial": _k(G, "text", doc="material name (sylva.tree.materials)"),
    "LeafMaterial": _k(B, "text", doc="material name"),
    "GroundClearance": _k(G, "float", 0, 100, doc="metres a drooping stem keeps off the ground"),
    "GrowthCurve": _k(G, "choice", choices=("cubic", "linear", "sqrt"), doc="elongation in time"),
    "ThickenCurve": _k(G, "choice", choices=("cubic", "linear", "sqrt"), doc="thickening"),
    "Season": _k(G, "choice", choices=("spring", "summer", "autumn", "winter"),
                 doc="the season the tree is shown in"),
    "Deciduous": _k(G, "bool", doc="whether its leaves change with the season"),
    "AutumnMaterial": _k(B, "text", doc="the leaves' material in autumn"),
    # -- the leaves' parameter space (sylva.tree.leaves): global, or per level for its leaves
    "LeafScaleYoung": _k(B, "float", 0, 10, open_lo=True,
                         doc="leaf size on a seedling, in LeafScale (1: the same at every age)"),
    "LeafAdultAge": _k(B, "float", 0, 1000, open_lo=True,
                       doc="tree age (years) from which new leaves are LeafScale long"),
    "SpringLeafScale": _k(B, "float", 0, 1, doc="a deciduous tree's leaf size in spring"),
    "LeafTurn": _k(B, "float", 0, 1, doc="in autumn: the fraction of leaves turned"),
    "LeafFall": _k(B, "float", 0, 1, doc="in autumn: the fraction fallen (1: bare)"),
    "JuvenileBranches": _k(G, "float", 0, 10, doc="branches on a young trunk's bare base, "
                                                  "relative to the crown's density"),
    "ShedTime": _k(G, "float", 0, 100, open_lo=True, doc="years a juvenile branch takes to go"),
    "JuvenileLag": _k(G, "float", 0, 1, open_lo=True,
                      doc="a young tree's crown base, in BaseSize (1: no lag, palms)"),
    "JuvenileLeafLife": _k(G, "float", 0, 100, doc="years young shoots keep their leaves"),
    "JuvenileLeafSpacing": _k(G, "float", 0, 100, open_lo=True,
                              doc="their spacing, in LeafScale"),
    "JuvenileTrunkLeaves": _k(G, "bool", doc="whether a young trunk carries leaves"),
    # -- Weber & Penn 1995, per level
    "Length": _k(L, "float", 0, 10, dev=True, doc="length (relative, see the paper) ± LengthV"),
    "Taper": _k(L, "float", 0, 3, doc="0–1 cone, 1–2 round end, 2–3 periodic"),
    "SegSplits": _k(L, "float", 0, 10, doc="clones per segment"),
    "SplitAngle": _k(L, "float", -180, 180, dev=True, doc="split angle ± SplitAngleV"),
    "CurveRes": _k(L, "int", 1, 100, doc="segments per stem"),
    "Curve": _k(L, "float", -3600, 3600, dev=True,
                doc="curvature (degrees) ± CurveV (CurveV >= 0: the helix is not modelled)"),
    "CurveBack": _k(L, "float", -3600, 3600, doc="curvature of the second half"),
    "DownAngle": _k(L, "float", -180, 180, dev=True,
                    doc="angle from the parent ± DownAngleV (negative: the paper's mode)"),
    "Rotate": _k(L, "float", -360, 360, dev=True,
                 doc="rotation about the parent ± RotateV (negative: two ranks)"),
    "Branches": _k(L, "float", 0, 10000, doc="children per stem"),
    # -- sylva's additions, per level
    "GrowTime": _k(L, "float", 0, 1000, open_lo=True, doc="years to full length"),
    "ThickenTime": _k(L, "float", 0, 1000, open_lo=True, doc="years to full thickness"),
    "BudDelay": _k(L, "float", 0, 100, doc="years from a shoot passing a bud to its break"),
    "Sides": _k(L, "int", 3, 64, doc="ring resolution"),
}

# the deviations a paper table may write as their own key (XV or nXV)
_DEV_NAMES = {k + "V" for k, v in KEYS.items() if v.dev} | {"ScaleV0"}
_LEVEL_NAME = re.compile(r"^(\d+)([A-Za-z_]\w*)$")


def _range(key: Key) -> str:
    if key.kind == "choice" and not math.isfinite(key.hi):
        return "one of " + ", ".join(repr(c) for c in key.choices)
    if key.kind == "choice":
        return f"{key.lo:g}…{key.hi:g} or one of " + ", ".join(repr(c) for c in key.choices)
    if key.kind == "bool":
        return "true, false, 0 or 1"
    lo = "-inf" if not math.isfinite(key.lo) else f"{key.lo:g}"
    hi = "inf" if not math.isfinite(key.hi) else f"{key.hi:g}"
    return f"{'(' if key.open_lo else '['}{lo}, {hi}]" + (" (an integer)" if key.kind == "int"
                                                         else "")


def _in(key: Key, x: float) -> bool:
    return (x > key.lo if key.open_lo else x >= key.lo) and x <= key.hi


def check_species(text: str, filename: str | None = None) -> None:
    """Raise :class:`~sylva.errors.LSystemSyntaxError` (a ``SylvaError``, with file, line,
    column and the allowed range) at the first thing in a species file that is not allowed.

    Examples
    --------
    >>> check_species('[global]\\nLevels = 1\\n[level 0]\\nLength = 1\\n')
    >>> check_species('[global]\\nLevels = 1\\nBaseSize = 2\\n[level 0]\\n')
    Traceback (most recent call last):
    ...
    sylva.errors.LSystemSyntaxError: ...BaseSize = 2 is out of range: expected [0, 0.99]...
    """
    def fail(msg, line, col):
        raise LSystemSyntaxError.at(msg, text, line, col, filename)

    blocks = parse_blocks(text, filename)
    levels_seen: dict[int, int] = {}
    levels_entry = None
    for block in blocks:
        if block.kind == "level":
            arg = (block.argument or "").strip()
            if not arg.isdigit():
                fail(f"expected '[level N]' with a level number N >= 0, got {arg!r}",
                     block.line, 1)
            levels_seen.setdefault(int(arg), block.line)
        elif block.kind != "global":
            fail(f"unknown block [{block.kind}]: expected [global] or [level N]", block.line, 1)
        for e in block.entries:
            name = e.name
            m = _LEVEL_NAME.match(name)
            in_level = block.kind == "level"
            if m:
                levels_seen.setdefault(int(m.group(1)), e.line)
                name, in_level = m.group(2), True
            if name in _DEV_NAMES and name not in KEYS:
                base = KEYS["Scale0" if name == "ScaleV0" else name[:-1]]
                if e.kind not in ("int", "float"):
                    fail(f"{e.name}: a deviation must be a number", e.line, e.column)
                if name == "CurveV" and e.value < 0:
                    fail(f"{e.name} = {e.value:g}: a negative CurveV (the paper's helix) is not "
                         "modelled: expected [0, inf)", e.line, e.column)
                if abs(e.value) > base.hi - base.lo:
                    fail(f"{e.name} = {e.value:g} is out of range: expected at most "
                         f"{base.hi - base.lo:g}", e.line, e.column)
                continue
            key = KEYS.get(name)
            if key is None:
                near = [k for k in KEYS if k.lower() == name.lower()]
                hint = f" (did you mean {near[0]!r}?)" if near else ""
                fail(f"unknown key {e.name!r}{hint}: expected one of the keys of "
                     "`sylva tree --example`", e.line, 1 + text.splitlines()[e.line - 1].find(
                         e.name))
            where = "a [level N] block" if key.scope == L else "the [global] block"
            if key.scope != B and (key.scope == L) != in_level:
                fail(f"{e.name} belongs in {where}", e.line, e.column)
            _check_value(key, e, fail)
            if name == "Levels":
                levels_entry = e
    n_levels = int(levels_entry.value) if levels_entry is not None else 3
    for lv, line in sorted(levels_seen.items()):
        if lv > n_levels:
            fail(f"[level {lv}] is beyond Levels = {n_levels}: expected levels 0…{n_levels} "
                 f"(0…{n_levels - 1} stems, {n_levels} the leaves)", line, 1)
    missing = [lv for lv in range(n_levels) if lv not in levels_seen]
    if missing:
        line, col = (levels_entry.line, levels_entry.column) if levels_entry else (1, 1)
        fail(f"missing [level {missing[0]}]: Levels = {n_levels} needs [level 0] … "
             f"[level {n_levels - 1}] (one block per stem level)", line, col)


def _check_value(key: Key, e, fail) -> None:
    name = e.name
    if key.kind == "text":
        if e.kind != "text":
            fail(f"{name}: expected a quoted text", e.line, e.column)
        return
    if key.kind == "bool":
        if e.kind == "bool" or (e.kind == "int" and e.value in (0, 1)):
            return
        fail(f"{name} = {e.value!r}: expected {_range(key)}", e.line, e.column)
    if key.kind == "choice":
        if e.kind == "text":
            if e.value.strip().lower() in key.choices or (
                    name == "LeafShape" and e.value.strip().lower() in
                    ("default", "pointed", "oval", "round", "circle", "hex")):
                return
            fail(f"{name} = {e.value!r} is not allowed: expected {_range(key)}",
                 e.line, e.column)
        if e.kind == "int" and math.isfinite(key.hi) and key.lo <= e.value <= key.hi:
            return
        fail(f"{name} = {e.value!r} is out of range: expected {_range(key)}", e.line, e.column)
    if e.kind not in ("int", "float"):
        fail(f"{name}: expected a number in {_range(key)}", e.line, e.column)
    if key.kind == "int" and (e.kind != "int"):
        fail(f"{name} = {e.value!r}: expected a whole number in {_range(key)}",
             e.line, e.column)
    if not _in(key, float(e.value)):
        fail(f"{name} = {e.value:g} is out of range: expected {_range(key)}", e.line, e.column)
    if e.deviation:
        if not key.dev:
            fail(f"{name} takes no deviation (± …)", e.line, e.column)
        if name == "Curve" and e.deviation < 0:
            fail(f"{name}: a negative deviation (the paper's helix) is not modelled: "
                 "expected ± d with d >= 0", e.line, e.column)
        if abs(e.deviation) > key.hi - key.lo:
            fail(f"{name}: deviation {e.deviation:g} is out of range: expected at most "
                 f"{key.hi - key.lo:g}", e.line, e.column)
        if name in ("Scale", "ZScale", "Scale0", "LeafScale") and \
                float(e.value) - abs(e.deviation) <= 0:
            fail(f"{name} = {e.value:g} ± {e.deviation:g} can be <= 0: expected a deviation "
                 f"below {e.value:g}", e.line, e.column)
