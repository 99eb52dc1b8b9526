"""What the documentation generates, as plain data (no Sphinx needed).

The Sphinx extension (``__init__.py`` beside this file) turns these into pages; the test
``tests/test_docs.py`` checks that they cover sylva: every turtle opcode of every dialect has a
meaning and a picture word, every built-in example a gallery entry, every dialect a page.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from sylva.turtle import tables as T

#: The page of each dialect, relative to ``docs/``.
DIALECT_PAGES = {
    "lsys": "languages/lsys.rst",
    "cpfg": "languages/cpfg.rst",
    "classic": "languages/classic.rst",
    "engine": "languages/engine.rst",
}

#: The turtle table each dialect's files are drawn with (cpfg draws with ABOP's).
DIALECT_TURTLE = {"lsys": "lsys", "cpfg": "abop", "classic": "classic", "engine": "engine"}

# ----------------------------------------------------------------------------- the grammar


def grammar_path() -> Path:
    """The shipped ``lsys.lark`` file."""
    return Path(str(resources.files("sylva.lsystem.dialects") / "lsys.lark"))


_TOKEN = re.compile(
    r"""\s*(?:
    (?P<string>"(?:[^"\\]|\\.)*"i?)
  | (?P<regex>/(?:[^/\\\n]|\\.)+/[imsx]*)
  | (?P<alias>->\s*[a-z_]\w*)
  | (?P<name>[?_!]*[A-Za-z_]\w*)
  | (?P<op>[\[\]()|*+?])
    )""",
    re.VERBOSE,
)


def _tokens(text: str) -> list[tuple[str, str]]:
    out, i = [], 0
    text = text.rstrip()
    while i < len(text):
        m = _TOKEN.match(text, i)
        if not m or m.end() == i:
            raise ValueError(f"lsys.lark: cannot read {text[i:i + 30]!r}")
        kind = m.lastgroup
        out.append((kind, m.group(kind)))
        i = m.end()
    return out


def _definitions(lark_text: str) -> list[tuple[str, str]]:
    """``(name, body)`` of every rule and terminal, continuation lines joined."""
    defs: list[list[str]] = []
    for raw in lark_text.splitlines():
        line = re.sub(r"\s*//.*$", "", raw)
        if not line.strip() or line.lstrip().startswith("%"):
            continue
        m = re.match(r"([?_!]*[A-Za-z_]\w*)(?:\.\d+)?\s*:(.*)$", line)
        if m and not line[0].isspace():
            defs.append([m.group(1), m.group(2)])
        elif defs:
            defs[-1][1] += " " + line.strip()
        else:
            raise ValueError(f"lsys.lark: a continuation with nothing to continue: {raw!r}")
    return [(n, b) for n, b in defs]


class _Reader:
    """Lark's EBNF (``x*``, ``x+``, ``x?``, ``[x]``, ``-> alias``) as ISO EBNF text."""

    def __init__(self, tokens, literal):
        self.t, self.i, self.literal = tokens, 0, literal

    def peek(self):
        return self.t[self.i] if self.i < len(self.t) else (None, None)

    def expr(self) -> str:
        alts = [self.alt()]
        while self.peek() == ("op", "|"):
            self.i += 1
            alts.append(self.alt())
        return " | ".join(alts)

    def alt(self) -> str:
        items = []
        while True:
            kind, value = self.peek()
            if kind is None or value in ("|", ")", "]"):
                break
            if kind == "alias":  # a tree-building name, no part of the language
                self.i += 1
                continue
            items.append(self.item())
        return " ".join(items)

    def item(self) -> str:
        kind, value = self.peek()
        self.i += 1
        if value == "(":
            inner = self.expr()
            self._expect(")")
            atom, grouped = f"( {inner} )", True
        elif value == "[":
            inner = self.expr()
            self._expect("]")
            atom, grouped = f"[ {inner} ]", True
        elif kind == "name":
            atom, grouped = self.literal(value.lstrip("?!")).lstrip("_"), False
        elif kind in ("string", "regex"):
            atom, grouped = value, False
        else:
            raise ValueError(f"lsys.lark: unexpected {value!r}")
        kind, post = self.peek()
        if kind == "op" and post in "*+?":
            self.i += 1
            body = atom[2:-2] if grouped and atom.startswith("(") else atom
            if post == "*":
                return f"{{ {body} }}"
            if post == "?":
                return f"[ {body} ]"
            first = body if "|" not in body else atom
            return f"{first} {{ {body} }}"
        return atom

    def _expect(self, op):
        if self.peek() != ("op", op):
            raise ValueError(f"lsys.lark: expected {op!r} at token {self.i}")
        self.i += 1


def grammar_ebnf(lark_text: str | None = None) -> tuple[str, str]:
    """The grammar of ``lsys.lark`` as ISO-style EBNF: ``(rules, terminals)``.

    Rules use ``{ x }`` for repetition and ``[ x ]`` for an option; a terminal that is one
    fixed string is written as that string inside the rules, the others (regular
    expressions) are listed in ``terminals``.  Lark's marks that shape only the parse tree
    are dropped: ``?`` and a leading ``_`` (inline the rule) and ``-> alias`` (name a node).
    """
    if lark_text is None:
        lark_text = grammar_path().read_text(encoding="utf-8")
    defs = _definitions(lark_text)
    terms = {n: b.strip() for n, b in defs if n.lstrip("?_!").isupper()}
    fixed = {n: b for n, b in terms.items() if re.fullmatch(r'"(?:[^"\\]|\\.)*"', b)}

    def literal(name: str) -> str:
        return fixed.get(name, name)

    width = max(len(n.lstrip("?")) for n, _ in defs)
    rules, regexes = [], []
    for name, body in defs:
        if name in terms:
            if name not in fixed:
                regexes.append(f"{name:<{width}} = {body.strip()} ;")
            continue
        reader = _Reader(_tokens(body), literal)
        text = reader.expr()
        if reader.i != len(reader.t):
            raise ValueError(f"lsys.lark: rule {name} not read to its end")
        rules.append(f"{name.lstrip('?_'):<{width}} = {text} ;")
    return "\n".join(rules), "\n".join(regexes)


# ------------------------------------------------------------------------- turtle commands


@dataclass(frozen=True)
class Command:
    """What one opcode does, for one dialect's table (``{}`` in texts: the dialect's
    angle setting name)."""

    params: str
    meaning: str


_ANGLE = {"lsys": "rot", "abop": "rot", "classic": "rot (angle:)", "engine": "yaw / pitch"}
_TURN = "``{sym}(a)`` turns by *a* degrees"

#: Meaning of each opcode; a ``(dialect, opcode name)`` key overrides the plain one.
MEANINGS: dict[object, Command] = {
    "DRAW": Command("``F(l)``: length *l*", "Move forward one step and draw a segment; inside "
                    "``{ }`` also record a polygon vertex."),
    ("classic", "DRAW"): Command("", "Move forward one step and draw a segment whose top "
                                 "radius is ``reduction`` times its base radius (a frustum)."),
    "MOVE": Command("``f(l)``: length *l*", "Move forward without drawing; inside ``{ }`` "
                    "also record a polygon vertex."),
    "DRAW_NOREC": Command("``G(l)``", "Move forward and draw, recording no polygon vertex."),
    "MOVE_NOREC": Command("``g(l)``", "Move forward without drawing or recording a vertex."),
    "TURN_LEFT": Command("``+(a)``: *a* degrees", "Turn left about U by the angle (yaw)."),
    "TURN_RIGHT": Command("``-(a)``", "Turn right about U by the angle (yaw)."),
    "PITCH_DOWN": Command("``&(a)``", "Pitch down about L by the angle."),
    "PITCH_UP": Command("``^(a)``", "Pitch up about L by the angle."),
    "ROLL_LEFT": Command("``\\(a)``", "Roll left about H by the angle."),
    "ROLL_RIGHT": Command("``/(a)``", "Roll right about H by the angle."),
    "TURN_AROUND": Command("", "Turn around: 180° about U."),
    "LEVEL": Command("", "Roll about H until L is horizontal (ABOP's ``$``: "
                     "``L = V×H/|V×H|``, ``U = H×L``, V pointing up)."),
    "PUSH": Command("", "Push the turtle's state (position, frame, width, colour…)."),
    "POP": Command("", "Pop the state pushed last: the branch ends, the turtle goes back."),
    "POLY_BEGIN": Command("", "Start a polygon: the positions recorded until the matching "
                          "``}`` are its vertices (where it starts, then after every ``F`` "
                          "and ``f``; only the ``.`` marks when the polygon has any)."),
    "POLY_END": Command("", "Close the polygon and fill it."),
    "POLY_VERTEX": Command("", "Record the turtle's position as a polygon vertex; a polygon "
                           "with ``.`` takes its vertices from the marks only."),
    "CUT": Command("", "Cut: skip the rest of the branch, up to its ``]``."),
    "WIDTH_ADD": Command("``!(w)`` sets the thickness", "Add ``thick_delta`` to the "
                         "thickness (a width, as in seed 001)."),
    "WIDTH_MUL": Command("``!(w)`` sets the width", "Multiply the width by "
                         "``thick_factor`` (0.7); with ``width_step`` (cpfg's line width "
                         "increment) subtract it, as cpfg does."),
    "WIDTH_INC": Command("``#(w)`` sets the width", "Add ``width_step`` (cpfg's line width "
                         "increment, default 0) to the width."),
    "COLOR_ADD": Command("``;(r, g, b)`` sets the colour", "Add ``color_delta`` to the "
                         "colour."),
    "COLOR_NEXT": Command("``;(i)`` sets the index", "Next colour index of the palette "
                          "(bark brown to leaf green, then yellow and white)."),
    "COLOR_PREV": Command("``,(i)`` sets the index", "Previous colour index."),
    "ANGLE_ADD": Command("``~(a)`` sets the angle", "Add ``rot_delta`` to the turning angle."),
    "LENGTH_ADD": Command("``_(l)`` sets the step length", "Add ``len_delta`` to the step "
                          "length (the thesis lost this glyph; sylva chose ``_``)."),
    "SURFACE": Command("``~(s)`` or ``~l(s)``: size *s*", "Draw a predefined surface at the "
                       "turtle's position, oriented by its frame: the Bézier patches of the "
                       "view file's ``surface: l file.s`` (cpfg), sylva's ``~\"leaf\"`` or "
                       "``~\"petal\"``, else sylva's leaf."),
    "ELASTICITY": Command("``_(e)`` sets the elasticity", "cpfg files only: add the view "
                          "file's ``elasticity increment`` to the elasticity of its old "
                          "tropism (``tropism direction:``) for the rest of the branch; "
                          "elsewhere nothing."),
    "SUBCALL": Command("``?(n, s)``: scale *s*", "Call sub-L-system *n* (up to its ``$``); "
                       "what it draws is *s* times as large: lengths, widths, surfaces, "
                       "spheres (cpfg)."),
    "LEAF": Command("", "Draw a leaf at the turtle's pose, without moving."),
    "YAW_LEFT": Command("", "Yaw left by ``yaw`` degrees (the header's first number)."),
    "YAW_RIGHT": Command("", "Yaw right by ``yaw`` degrees."),
    "E_PITCH_UP": Command("", "Pitch up by ``pitch`` degrees (the header's second number)."),
    "E_PITCH_DOWN": Command("", "Pitch down by ``pitch`` degrees."),
    "BLOCK_FORWARD": Command("", "Place a block and step one block size along Front."),
    "BLOCK_UP": Command("", "Place a block and step one block size along Up."),
    "SHRINK": Command("", "Multiply the block size by ``shrink`` (the header's third "
                      "number)."),
    "GROW": Command("", "Divide the block size by ``shrink``."),
    "RESET_SCALE": Command("", "Reset the block size to 1."),
    "BUFFER": Command("", "Switch the output buffer (0 wood, 1 leaves, …): later blocks "
                      "get that buffer's material."),
    "AT": Command("``@O(d)``, ``@v``, ``@M(x,y[,z])``, ``@R(h[,u])``, ``@Ts(e)``, "
                  "``@Ti(d)``, ``@Td(d)``",
                  "cpfg's functions, named by the letter after ``@``: ``@O`` draws a "
                  "sphere of diameter *d*, ``@v`` rolls to vertical (ABOP's ``$``), "
                  "``@M`` moves to a point without drawing, ``@R`` sets the heading (and "
                  "up), ``@Ts``/``@Ti``/``@Td`` set, raise and lower the elasticity of "
                  "tropism for the rest of the branch (cpfg files: ``@Ts(k, e)``, the view "
                  "file's k-th ``tropism:`` or ``torque:`` line); "
                  "``@o(d)`` and ``@c(r)`` (cpfg's disc and circle) draw a sphere of "
                  "diameter *d* / radius *r*; ``@Gs @Gc(n) @Ge(n)`` draw a generalised "
                  "cylinder, n strips of a Hermite curve between control points, "
                  "``@Gt(a, b)`` sets its tangents (cpfg files); ``@Gr``, ``@Tx @Tf``, "
                  "``@! @# @L`` are read and draw nothing."),
}

#: A word that shows each opcode's effect (``{s}``: the symbol itself), per table.
_DEMO = {
    "DRAW": "F{s}F",
    "MOVE": "F{s}F",
    "DRAW_NOREC": "F{s}",
    "MOVE_NOREC": "F{s}F",
    "TURN_LEFT": "F{s}F",
    "TURN_RIGHT": "F{s}F",
    "PITCH_DOWN": "F{s}F",
    "PITCH_UP": "F{s}F",
    "ROLL_LEFT": "F{s}(90)+F",
    "ROLL_RIGHT": "F{s}(90)+F",
    "TURN_AROUND": "F{s}+F",
    "LEVEL": "&F/(60)F{s}+F",
    "PUSH": "F{s}+F]F",
    "POP": "F[+F{s}F",
    "POLY_BEGIN": "{s}.f.+f.+f.+f.}",
    "POLY_END": "{.f.+f.+f.+f.{s}",
    "POLY_VERTEX": "{{s}f{s}+f{s}+f{s}+f{s}}",
    "CUT": "F[+F{s}FFF]F",
    "WIDTH_ADD": "F{s}F{s}F",
    "WIDTH_MUL": "F{s}F{s}F",
    "WIDTH_INC": 'F"{s}"(0.2)F"{s}"(0.3)F',  # a bare # begins a comment in .lsys
    "COLOR_ADD": ";(0.4,0.2,0.1)F{s}F{s}F",
    "COLOR_NEXT": "F{s}F{s}F",
    "COLOR_PREV": ";(5)F{s}F{s}F",
    "ANGLE_ADD": "F+F{s}+F{s}+F",
    "LENGTH_ADD": "F+F{s}+F{s}+F",
    "ELASTICITY": "F+F{s}F",
    "SURFACE": "F{s}",
    "LEAF": "F{s}",
    "YAW_LEFT": "FFF{s}FFF",
    "YAW_RIGHT": "FFF{s}FFF",
    "E_PITCH_UP": "FFF{s}FFF",
    "E_PITCH_DOWN": "FFF{s}FFF",
    "BLOCK_FORWARD": "{s}{s}{s}",
    "BLOCK_UP": "{s}{s}{s}",
    "SHRINK": "FF{s}FF{s}FF",
    "GROW": "xxFF{s}FF{s}FF",
    "RESET_SCALE": "xxFF{s}FF",
    "BUFFER": "FF{s}FF",
    "AT": "FF{s}O(0.8)",
    "SUBCALL": "!(0.3)F{s}(1,0.5)F+F+F",
}
#: Words for one table only (the engine's F steps sideways: its trunks are U).
_DEMO_TABLE = {
    ("engine", "PUSH"): "UU{s}+FF]UU",
    ("engine", "POP"): "UU[+FF{s}UU",
}
# rotations are shown at 45 degrees, the engine's at 90
_SETTINGS = {
    "lsys": "turtle = lsys\nrot = 45\ncolor = 0.35, 0.2, 0.1\n",
    "abop": "turtle = abop\nrot = 45\n",
    "classic": "turtle = classic\nrot = 45\nreduction = 0.7\nradius = 0.15\n",
    "engine": "turtle = engine\nyaw = 90\npitch = 90\nshrink = 0.5\n",
}


@dataclass(frozen=True)
class Row:
    """One row of a turtle table: the symbols with one opcode."""

    table: str
    symbols: tuple[str, ...]
    opcode: str
    command: Command

    @property
    def program(self) -> str:
        """``.lsys`` text whose axiom shows the command (its first symbol)."""
        s = self.symbols[0]
        demo = _DEMO_TABLE.get((self.table, self.opcode), _DEMO[self.opcode])
        word = demo.replace("{s}", _quote(s))
        if self.opcode == "BUFFER":
            word = _DEMO["BUFFER"].replace("{s}", "1")
        return f"{_SETTINGS[self.table]}axiom = {word}\n"


def _quote(symbol: str) -> str:
    return symbol


def turtle_rows(table: str) -> list[Row]:
    """The rows of a turtle table: symbols grouped by opcode, in the table's order."""
    groups: dict[int, list[str]] = {}
    for sym, op in T.TABLES[table].items():
        groups.setdefault(op, []).append(sym)
    rows = []
    for op, syms in groups.items():
        name = T.OPCODE_NAMES[op]
        cmd = MEANINGS.get((table, name)) or MEANINGS[name]
        rows.append(Row(table, tuple(syms), name, cmd))
    return rows


def symbols_text(symbols: tuple[str, ...]) -> str:
    """``0``–``9`` for the digit run, else the symbols separated by spaces."""
    if len(symbols) > 3 and all(s.isdigit() for s in symbols):
        return f"{symbols[0]}–{symbols[-1]}"
    return " ".join(symbols)


# -------------------------------------------------------------------------------- gallery


@dataclass(frozen=True)
class Entry:
    """A gallery entry: a built-in example, the command that renders it, its text."""

    name: str
    title: str
    path: Path

    @property
    def command(self) -> str:
        return f"sylva render {self.name} -o {self.name}.png"

    @property
    def language(self) -> str:
        return "text"


def gallery_textures() -> tuple[str, ...]:
    """The texture presets the gallery shows: those ``sylva gallery`` renders."""
    from sylva.cli.gallery import GALLERY_TEXTURES
    from sylva.texture import PRESETS

    return tuple(n for n in GALLERY_TEXTURES if n in PRESETS)


def gallery_entries() -> list[Entry]:
    """One entry per built-in example, in gallery order."""
    from sylva.data import examples

    return [Entry(e.name, e.title, e.path) for e in examples()]


# ---------------------------------------------------------------------------- command line


def cli_commands() -> dict[str, str]:
    """``{command: its --help text}`` for every ``sylva`` sub-command (argparse's own)."""
    import argparse
    import os

    from sylva.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    old = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = "92"
    try:
        return {name: p.format_help() for name, p in sorted(sub.choices.items())}
    finally:
        if old is None:
            os.environ.pop("COLUMNS", None)
        else:
            os.environ["COLUMNS"] = old


# ------------------------------------------------------------------------------- the API

#: The modules of the API reference, in order, with a line each.
API_MODULES = {
    "sylva": "the curated API: read, write, define and derive L-systems",
    "sylva.plant": "from an L-system to meshes in one call",
    "sylva.environments": "the environments of open L-systems (light, obstacles, the world)",
    "sylva.lsystem": "the language, the programs and the derivation engine",
    "sylva.turtle": "the 3D turtle and its command tables",
    "sylva.geometry": "meshes and scenes",
    "sylva.geometry.exchange": "mesh export (glTF, OBJ, PLY, STL, OpenSCAD, POV-Ray, SVG, USD)",
    "sylva.render": "offscreen rendering, cameras, lights, animations",
    "sylva.texture": "procedural textures",
    "sylva.texture.graph": "texture graphs: nodes, files, the fused kernel, GLSL",
    "sylva.tree": "trees that grow in time (Weber-Penn species, wind)",
    "sylva.world": "voxel worlds",
    "sylva.studio": "the browser workbench",
    "sylva.data": "the built-in examples",
    "sylva.assets": "baking the renderer's materials into images that exports carry",
}


#: The classes each page shows besides the functions (the others are documented where a
#: function returns or takes them, and in the source).
API_CLASSES = {
    "sylva": ("Program", "ModuleString", "Derivation", "SylvaError", "LSystemSyntaxError",
              "LSystemSemanticError", "GrowthLimitError"),
    "sylva.plant": ("Plant",),
    "sylva.environments": ("Light", "Obstacle"),
    "sylva.geometry": ("Scene", "Mesh", "Material"),
    "sylva.render": ("Camera", "Sun", "PointLight", "Sky", "Ground"),
    "sylva.tree": ("Tree", "Wind"),
    "sylva.world": ("World", "WorldConfig"),
    "sylva.studio": ("Limits",),
    "sylva.texture.graph": ("Graph", "Node"),
}


def api_names(module: str) -> tuple[list[str], list[str]]:
    """``(functions, classes)`` a page of the API reference shows.

    The functions of the module's ``__all__`` (for ``sylva.lsystem`` less those that
    ``sylva`` itself exports) and the classes of :data:`API_CLASSES`.  Constants (tables,
    defaults) are described by the pages that use them.
    """
    import importlib
    import inspect

    mod = importlib.import_module(module)
    top = set(importlib.import_module("sylva").__all__) if module == "sylva.lsystem" else set()
    functions = [n for n in mod.__all__ if n not in top
                 and callable(getattr(mod, n)) and not inspect.isclass(getattr(mod, n))]
    classes = list(API_CLASSES.get(module, ()))
    missing = [c for c in classes if c not in mod.__all__]
    if missing:
        raise ValueError(f"{module} does not export {missing}")
    return functions, classes
