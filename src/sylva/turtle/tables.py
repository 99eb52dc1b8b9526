"""Command tables: what each symbol of each dialect makes the turtle do.

Every dialect maps symbol names to *opcodes* of one shared interpreter
(:mod:`sylva.turtle._kernels`).  A table is plain data: ``{symbol: opcode}`` plus, for the
buffer switches of seed 004, ``{symbol: argument}``.  :func:`compile_table` turns a table into
``int32``/``float64`` arrays indexed by the symbol ids of a word's alphabet.

Tables
------
``abop`` (ABOP / cpfg)
    ``F`` draw, ``f`` move (both record a polygon vertex inside ``{ }``), ``G`` draw and ``g``
    move without recording one, ``+ -`` turn left/right about U, ``& ^`` pitch down/up about L,
    ``\\ /`` roll left/right about H, ``|`` turn around, ``$`` level (``L = V×H/|V×H|``, ``U =
    H×L``, ``V`` up), ``[ ]`` push/pop, ``{ } .`` polygons, ``%`` cut the rest of the branch,
    ``!`` width ×``thick_factor`` (``!(w)`` sets the width; with the setting ``width_step``,
    cpfg's ``line width increment``, ``!`` subtracts it, as cpfg does, and ``#`` adds it; ``#(w)``
    sets the width), ``; '`` next colour index (``;(i)``
    sets it), ``,`` previous colour index, ``~`` a predefined surface (``~(s)`` or ``~l(s)``
    scales it: the surface ``l`` of the view file, sylva's ``~"leaf"`` / ``~"petal"``, else
    sylva's leaf; :mod:`sylva.geometry.surfaces`), ``?(n, s)`` a sub-L-system's call whose
    drawing is scaled by ``s`` (lengths, widths, surfaces and spheres, until its ``$``; the
    width at the call is multiplied by ``s``). Parameters override the defaults: ``+(30)`` turns
    30°, ``F(2)`` draws 2 units. ``@`` calls one of cpfg's functions, named by the modules after
    it: ``@O(d)`` a sphere of diameter ``d`` (default the width), ``@v`` roll to vertical
    (``$``), ``@M(x,y[,z])`` move to a point, ``@R(hx, hy[, hz[, ux, uy, uz]])`` set the heading
    (and up), ``@Ts @Ti @Td`` set, increase, decrease the elasticity of tropism (ABOP §2.3:
    after every ``F f G g`` the frame turns by ``e·|H × T|`` about ``H × T``; settings
    ``tropism``, ``elasticity``, ``elasticity_step``).  Programs read from cpfg write ``@Ts(1,
    e)`` (the index of a view file's ``tropism:`` or ``torque:`` line first, cpfg's
    spelling; :mod:`sylva.turtle._movements`), the others ``@Ts(e)`` (L-Py's).  In cpfg's
    files ``_`` adds ``elasticity_step`` to the elasticity of the view file's ``tropism
    direction:`` and ``_(e)`` sets it (cpfg's old tropism); elsewhere ``_`` does nothing.
``lsys`` (seed 001, LSysVis Table 3)
    ``F f [ ] + - ^ & \\ / | $`` as above (Table 3 calls ``+``/``-`` yaw, ``^``/``&`` pitch
    and ``\\``/``/`` roll; we keep ABOP's signs), ``!`` adds ``thick_delta`` (``!(x)`` sets
    the thickness), ``~`` adds ``rot_delta`` (``~(x)`` sets the angle), ``;`` adds
    ``color_delta`` (``;(r,g,b)`` sets the colour), ``_`` adds ``len_delta`` (``_(x)`` sets
    the length).  The thesis lost the glyph of the length command; we chose ``_`` (seed
    001 §9.1).  ``{ } .`` (the thesis's future work) make polygons whose vertices are the
    turtle's positions, as in ABOP; ``@`` and tropism as in ``abop``.
``classic`` (seed 000)
    ``F`` draws a segment and multiplies the radius by ``reduction`` (a frustum whose top is
    ``reduction`` times its base), ``f`` moves, ``+ - & ^ / \\ |`` rotate by ``angle``, ``[ ]``,
    and ``L`` draws a leaf at the turtle's pure transform: without moving and without taper.
``engine`` (seed 004)
    ``F f`` place blocks along Front, ``U u`` along Up (the F/U block rule), ``x X S``
    shrink, enlarge, reset the block size, ``+ -`` yaw, ``^ &`` pitch (no roll),
    ``[ ]``, and ``0``–``9`` switch the output buffer.

Examples
--------
>>> TABLES["abop"]["+"] == TURN_LEFT, TABLES["engine"]["+"] == YAW_LEFT
(True, True)
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

__all__ = [
    "ARGS",
    "DEFAULTS",
    "OPCODE_NAMES",
    "PALETTE",
    "TABLES",
    "compile_table",
]

# --------------------------------------------------------------------------- opcodes
NOP = 0
DRAW = 1  # F: move and draw; records a polygon vertex in polygon mode
MOVE = 2  # f: move without drawing; records a polygon vertex in polygon mode
DRAW_NOREC = 3  # G
MOVE_NOREC = 4  # g
TURN_LEFT = 5  # +  about U
TURN_RIGHT = 6  # -
PITCH_DOWN = 7  # &  about L
PITCH_UP = 8  # ^
ROLL_LEFT = 9  # \  about H
ROLL_RIGHT = 10  # /
TURN_AROUND = 11  # |
LEVEL = 12  # $
PUSH = 13  # [
POP = 14  # ]
POLY_BEGIN = 15  # {
POLY_END = 16  # }
POLY_VERTEX = 17  # .
CUT = 18  # %
WIDTH_ADD = 19  # ! (lsys): += thick_delta, !(x) sets
WIDTH_MUL = 20  # ! (abop): *= thick_factor, !(x) sets
COLOR_ADD = 21  # ; (lsys): += color_delta, ;(r,g,b) sets
COLOR_NEXT = 22  # ; ' (abop): colour index + 1, ;(i) sets
COLOR_PREV = 23  # , (abop): colour index - 1, ,(i) sets
ANGLE_ADD = 24  # ~ (lsys): += rot_delta, ~(x) sets
LENGTH_ADD = 25  # _ (lsys): += len_delta, _(x) sets
SURFACE = 26  # ~ (abop): a predefined surface (leaf)
LEAF = 27  # L (classic): leaf at the pure transform
YAW_LEFT = 28  # engine +
YAW_RIGHT = 29  # engine -
E_PITCH_UP = 30  # engine ^
E_PITCH_DOWN = 31  # engine &
BLOCK_FORWARD = 32  # engine F f
BLOCK_UP = 33  # engine U u
SHRINK = 34  # engine x
GROW = 35  # engine X
RESET_SCALE = 36  # engine S
BUFFER = 37  # engine 0-9 (argument: the buffer)
AT = 38  # @ (abop, lsys): cpfg's functions, named by the next module (argument: AT_*)
SUBCALL = 39  # ? (abop): a sub-L-system's call ?(n, s) or end: the width times s
WIDTH_INC = 40  # # (abop): += width_step (cpfg's line width increment), #(w) sets
ELASTICITY = 41  # _ (abop, cpfg's files only): += elasticity_step, _(e) sets the elasticity

# the functions after ``@``: each is the argument of the letter that names it
AT_SPHERE = 1  # @O(d): a sphere of diameter d (default: the width)
AT_VERTICAL = 2  # @v: roll to vertical (ABOP's $)
AT_MOVE = 3  # @M(x, y[, z]): move to a point without drawing
AT_HEADING = 4  # @R(hx, hy[, hz[, ux, uy, uz]]): set the heading (and up)
AT_T = 5  # @T followed by s, i or d: the elasticity of tropism
AT_TS = 6  # @Ts: set it
AT_TI = 7  # @Ti: increase it
AT_TD = 8  # @Td: decrease it
AT_CIRCLE = 9  # @c(r) / @o(d): cpfg's circle and disc, drawn as a sphere of that size
AT_G = 10  # @G followed by s, c, e, t or r: cpfg's generalised cylinders (_gcylinder)
AT_NOP = 11  # @! @# @L: cpfg's sides, contour and label settings (read, no drawing)
AT_TX = 12  # @Tx @Tf: cpfg's texture and tropism-function settings (read, no drawing)
#: The letters after ``@`` and their functions (``T`` and ``G`` take one more letter).
AT_FUNCTIONS: Mapping[str, int] = {
    "O": AT_SPHERE, "v": AT_VERTICAL, "M": AT_MOVE, "R": AT_HEADING, "T": AT_T,
    "o": AT_SPHERE, "c": AT_CIRCLE, "G": AT_G, "!": AT_NOP, "#": AT_NOP, "L": AT_NOP,
}  # fmt: skip
AT_SUBFUNCTIONS: Mapping[str, int] = {"s": AT_TS, "i": AT_TI, "d": AT_TD, "x": AT_TX,
                                      "f": AT_TX}  # fmt: skip

OPCODE_NAMES = {
    v: k
    for k, v in list(globals().items())
    if k.isupper() and isinstance(v, int) and not k.startswith("AT_")
}

# --------------------------------------------------------------------------- tables
_ROT = {
    "+": TURN_LEFT,
    "-": TURN_RIGHT,
    "&": PITCH_DOWN,
    "^": PITCH_UP,
    "\\": ROLL_LEFT,
    "/": ROLL_RIGHT,
    "|": TURN_AROUND,
}

TABLES: Mapping[str, Mapping[str, int]] = {
    "abop": {
        "F": DRAW,
        "f": MOVE,
        "G": DRAW_NOREC,
        "g": MOVE_NOREC,
        **_ROT,
        "$": LEVEL,
        "[": PUSH,
        "]": POP,
        "{": POLY_BEGIN,
        "}": POLY_END,
        ".": POLY_VERTEX,
        "%": CUT,
        "!": WIDTH_MUL,
        "#": WIDTH_INC,
        ";": COLOR_NEXT,
        "'": COLOR_NEXT,
        ",": COLOR_PREV,
        "~": SURFACE,
        "@": AT,
        "?": SUBCALL,
        "_": ELASTICITY,
    },
    "lsys": {
        "F": DRAW,
        "f": MOVE,
        **_ROT,
        "$": LEVEL,
        "[": PUSH,
        "]": POP,
        "{": POLY_BEGIN,
        "}": POLY_END,
        ".": POLY_VERTEX,
        "!": WIDTH_ADD,
        "~": ANGLE_ADD,
        ";": COLOR_ADD,
        "_": LENGTH_ADD,
        "@": AT,
    },
    "classic": {
        "F": DRAW,
        "f": MOVE,
        **_ROT,
        "[": PUSH,
        "]": POP,
        "L": LEAF,
    },
    "engine": {
        "F": BLOCK_FORWARD,
        "f": BLOCK_FORWARD,
        "U": BLOCK_UP,
        "u": BLOCK_UP,
        "x": SHRINK,
        "X": GROW,
        "S": RESET_SCALE,
        "+": YAW_LEFT,
        "-": YAW_RIGHT,
        "^": E_PITCH_UP,
        "&": E_PITCH_DOWN,
        "[": PUSH,
        "]": POP,
        **{str(d): BUFFER for d in range(10)},
    },
}

_AT_ARGS = {k: float(v) for k, v in (*AT_FUNCTIONS.items(), *AT_SUBFUNCTIONS.items())}
ARGS: Mapping[str, Mapping[str, float]] = {
    "engine": {str(d): float(d) for d in range(10)},
    "abop": _AT_ARGS,
    "lsys": _AT_ARGS,
}

# Default colour table of the ABOP dialect (cpfg colour indices), linear RGB: a ramp from bark
# to leaf green (``'``/``;`` step along it level by level, as in ABOP Fig. 1.25), then two
# flower colours.
PALETTE: tuple[tuple[float, float, float], ...] = (
    (0.30, 0.18, 0.08),  # 0 bark
    (0.33, 0.25, 0.09),
    (0.32, 0.33, 0.10),
    (0.27, 0.40, 0.11),
    (0.20, 0.45, 0.12),
    (0.14, 0.48, 0.12),  # 5 leaf green
    (0.95, 0.80, 0.20),  # 6 yellow
    (0.95, 0.95, 0.92),  # 7 white
)

# Dialect defaults.  ``thick`` is a width (diameter) as in seed 001; ``radius`` a radius.
DEFAULTS: Mapping[str, Mapping[str, object]] = {
    "lsys": {  # seed 001 Table 1
        "len": 1.0,
        "thick": 0.2,
        "rot": 90.0,
        "color": (0.0, 0.0, 0.0),
        "len_delta": -0.1,
        "thick_delta": -0.1,
        "rot_delta": 10.0,
        "color_delta": (-0.1, -0.1, -0.1),
        "detail": 25,
        "bg": (0.9, 0.9, 0.9),
    },
    "abop": {
        "len": 1.0,
        "thick": 0.1,
        "rot": 90.0,
        "thick_factor": 0.7,
        "color_index": 0,
        "leaf_size": 1.0,
        "detail": 8,
    },
    "classic": {  # seed 000: unit F; radius and reduction as in Table 3.1
        "len": 1.0,
        "rot": 90.0,
        "reduction": 1.0,
        "leaf_size": 1.0,
        "detail": 12,
    },
    "engine": {  # seed 004
        "yaw": 90.0,
        "pitch": 90.0,
        "shrink": 0.7,
        "scale": 1.0,
        "angle_var": 0.0,
    },
}


def compile_table(
    table: Mapping[str, int],
    names: Sequence[str],
    args: Mapping[str, float] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Opcode and argument arrays for an alphabet.

    Parameters
    ----------
    table : mapping of str to int
        Symbol name -> opcode.
    names : sequence of str
        The alphabet's names (``names[i]`` is the symbol with id ``i``).
    args : mapping of str to float, optional
        Symbol name -> opcode argument (the buffer of ``0``–``9``).

    Returns
    -------
    ops : int32[len(names)]
        Opcode of each symbol id (0, no operation, for symbols without meaning).
    arg : float64[len(names)]
        Argument of each symbol id.

    Examples
    --------
    >>> ops, arg = compile_table(TABLES["engine"], ["[", "]", "F", "A", "3"], ARGS["engine"])
    >>> ops.tolist(), arg.tolist()
    ([13, 14, 32, 0, 37], [0.0, 0.0, 0.0, 0.0, 3.0])
    """
    ops = np.zeros(len(names), np.int32)
    arg = np.zeros(len(names), np.float64)
    args = args or {}
    for i, name in enumerate(names):
        op = table.get(name)
        if op is not None:
            ops[i] = op
        arg[i] = args.get(name, 0.0)
    return ops, arg
