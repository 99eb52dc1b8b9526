"""The help panels: what each symbol makes the turtle do, and the special variables.

The symbol table is read from the turtle's command tables (:data:`sylva.turtle.TABLES`), so
it always says what the interpreter really does; the words are seed 001's Tables 1–3.
"""

from __future__ import annotations

__all__ = ["help_tables"]

_OPCODE_TEXT = {
    "DRAW": "Move forward by the step length, drawing a segment (X(x): by x).",
    "MOVE": "Move forward by the step length without drawing (X(x): by x).",
    "DRAW_NOREC": "Draw forward without recording a polygon vertex.",
    "MOVE_NOREC": "Move forward without recording a polygon vertex.",
    "TURN_LEFT": "Yaw, positive direction, by the turning angle (X(a): by a degrees).",
    "TURN_RIGHT": "Yaw, negative direction, by the turning angle (X(a): by a degrees).",
    "PITCH_DOWN": "Pitch, negative direction (down) by the angle (X(a): by a degrees).",
    "PITCH_UP": "Pitch, positive direction (up) by the angle (X(a): by a degrees).",
    "ROLL_LEFT": "Roll, positive direction, by the angle (X(a): by a degrees).",
    "ROLL_RIGHT": "Roll, negative direction, by the angle (X(a): by a degrees).",
    "TURN_AROUND": "Turn around: yaw by 180 degrees.",
    "LEVEL": "Roll until the turtle is level (left vector horizontal), as in ABOP.",
    "PUSH": "Push the turtle state on the stack (start a branch).",
    "POP": "Pop the turtle state from the stack (end a branch).",
    "POLY_BEGIN": "Start a polygon.",
    "POLY_END": "End the polygon and fill it.",
    "POLY_VERTEX": "Record a polygon vertex at the turtle's position.",
    "CUT": "Cut the rest of the branch.",
    "WIDTH_ADD": "Add thick_delta to the thickness (X(x): set the thickness to x).",
    "WIDTH_MUL": "Multiply the width by thick_factor, or subtract width_step (cpfg) "
                 "(X(w): set the width to w).",
    "WIDTH_INC": "Add width_step to the width, cpfg's line width increment (X(w): set the "
                 "width to w).",
    "COLOR_ADD": "Add color_delta to the colour (X(r, g, b): set the colour).",
    "COLOR_NEXT": "Next colour index (X(i): set the index to i).",
    "COLOR_PREV": "Previous colour index (X(i): set the index to i).",
    "ANGLE_ADD": "Add rot_delta to the turning angle (X(x): set the angle to x).",
    "LENGTH_ADD": "Add len_delta to the step length (X(x): set the length to x).",
    "SURFACE": "Draw a predefined surface, a leaf (X(s): scaled by s).",
    "SUBCALL": "Call a sub-L-system up to its $ (X(n, s): drawn s times as large).",
    "LEAF": "Draw a leaf at the turtle, without moving.",
    "YAW_LEFT": "Yaw left by the yaw angle.",
    "YAW_RIGHT": "Yaw right by the yaw angle.",
    "E_PITCH_UP": "Pitch up by the pitch angle.",
    "E_PITCH_DOWN": "Pitch down by the pitch angle.",
    "BLOCK_FORWARD": "Place blocks along the front direction.",
    "BLOCK_UP": "Place blocks along the up direction.",
    "SHRINK": "Shrink the block size by the shrink factor.",
    "GROW": "Enlarge the block size by the shrink factor.",
    "RESET_SCALE": "Reset the block size.",
    "BUFFER": "Switch the output buffer (material) to this digit.",
}

_VARIABLE_TEXT = {
    "axiom": "The initial word (mandatory).",
    "ignore": "Symbols skipped when contexts are matched.",
    "detail": "Sides of each segment's prism (floored; below 3: a flat strip).",
    "bg": "Background colour, RGB in 0…1.",
    "len": "Initial step length.",
    "thick": "Initial thickness.",
    "rot": "Initial turning angle in degrees.",
    "color": "Initial colour, RGB in 0…1.",
    "len_delta": "Added to the length by the length-change symbol.",
    "thick_delta": "Added to the thickness by !.",
    "rot_delta": "Added to the angle by ~.",
    "color_delta": "Added to the colour by ;.",
    "steps": "Derivation steps the file asks for.",
    "seed": "Seed of the random choices of stochastic rules.",
    "thick_factor": "Factor applied to the width by !.",
    "color_index": "Initial colour index.",
    "leaf_size": "Size of the predefined leaf surface.",
    "reduction": "Radius factor applied by each F.",
    "yaw": "Yaw angle in degrees.",
    "pitch": "Pitch angle in degrees.",
    "shrink": "Block size factor of x and X.",
    "scale": "Initial block size.",
    "angle_var": "Random variation of the angles.",
}


def _fmt(v) -> str:
    if isinstance(v, (tuple, list)):
        return ", ".join(_fmt(x) for x in v)
    if isinstance(v, float):
        return f"{v:g}" if v != int(v) else f"{v:.1f}"
    return str(v)


def help_tables(turtle: str) -> dict:
    """``{"turtle", "symbols": [{symbol, command, meaning}], "variables": [{name, default,
    meaning}]}`` for the command table ``turtle``."""
    from ..turtle import DEFAULTS, TABLES
    from ..turtle.tables import OPCODE_NAMES

    if turtle not in TABLES:
        turtle = "lsys"
    symbols = []
    for sym, op in TABLES[turtle].items():
        name = OPCODE_NAMES.get(op, str(op))
        text = _OPCODE_TEXT.get(name, name.replace("_", " ").lower()).replace("X", sym, 1)
        symbols.append({"symbol": sym, "command": name.lower(), "meaning": text})
    variables = [
        {"name": "axiom", "default": "", "meaning": _VARIABLE_TEXT["axiom"]},
        {"name": "ignore", "default": "", "meaning": _VARIABLE_TEXT["ignore"]},
    ]
    for name, v in DEFAULTS.get(turtle, {}).items():
        variables.append({"name": name, "default": _fmt(v),
                          "meaning": _VARIABLE_TEXT.get(name, "")})
    return {"turtle": turtle, "symbols": symbols, "variables": variables}
