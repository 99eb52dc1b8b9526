"""GLSL of the formula language (private): escape-time fractals and formula nodes.

The formula compiler (:mod:`._formula`) writes a numba function as lines of a small, fixed
form: one assignment, ``if``/``else``/``while True:`` block, ``break`` or ``return`` a line;
operands are single names or numbers (every sub-expression is a temporary ``tN``); a
complex value is a pair of real names, and the few complex library calls (power, ``sqrt``,
``exp``, ``log``, ``sin``, ``cos``) go through a ``complex`` temporary.  This module
translates those lines, never user text (user names are already ``u_NAME``), into a GLSL
function ``float NAME(float pr, float pi, float in1, float in2, float in3)``: complex
temporaries become ``vec2`` with the helpers below, the parameter array becomes constants,
and indentation becomes braces.  GLSL runs it in float32; the CPU kernel in float64.
"""

from __future__ import annotations

import math
import re

__all__ = ["COMPLEX_HELPERS", "formula_glsl"]

COMPLEX_HELPERS = """
vec2 sylva_cmul(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }
vec2 sylva_cexp(vec2 z) { return exp(z.x) * vec2(cos(z.y), sin(z.y)); }
vec2 sylva_clog(vec2 z) { return vec2(log(length(z)), atan(z.y, z.x)); }
vec2 sylva_csqrt(vec2 z) {
    float r = length(z);
    float a = sqrt(max(0.5 * (r + z.x), 0.0));
    float b = sqrt(max(0.5 * (r - z.x), 0.0));
    return vec2(a, z.y < 0.0 ? -b : b);
}
vec2 sylva_csin(vec2 z) {
    float e = exp(z.y), f = exp(-z.y);
    return vec2(sin(z.x) * 0.5 * (e + f), cos(z.x) * 0.5 * (e - f));
}
vec2 sylva_ccos(vec2 z) {
    float e = exp(z.y), f = exp(-z.y);
    return vec2(cos(z.x) * 0.5 * (e + f), -sin(z.x) * 0.5 * (e - f));
}
vec2 sylva_cpow(vec2 a, vec2 b) {
    if (a.x == 0.0 && a.y == 0.0) return (b.x == 0.0 && b.y == 0.0) ? vec2(1.0, 0.0) : vec2(0.0);
    return sylva_cexp(sylva_cmul(b, sylva_clog(a)));
}
"""

_ATOM = r"[A-Za-z0-9_.\[\]+-]+"
_ASSIGN = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*) (=|\+=) (.*)$")


def _fl(v: float) -> str:
    v = float(v)
    if not math.isfinite(v):
        raise ValueError(f"a GLSL constant must be finite, got {v}")
    s = repr(v)
    return s if ("." in s or "e" in s) else s + ".0"


def _expr(e: str, q) -> str:
    """One right-hand side of the numba lines as GLSL."""
    e = re.sub(r"\bnp\.(sqrt|exp|log|sin|cos)\(complex\((" + _ATOM + r"), (" + _ATOM +
               r")\)\)", r"sylva_c\1(vec2(\2, \3))", e)
    e = re.sub(r"complex\((" + _ATOM + r"), (" + _ATOM + r")\) \*\* complex\((" + _ATOM +
               r"), (" + _ATOM + r")\)", r"sylva_cpow(vec2(\1, \2), vec2(\3, \4))", e)
    e = re.sub(r"(" + _ATOM + r") \*\* (" + _ATOM + r")", r"pow(\1, \2)", e)
    e = re.sub(r"(" + _ATOM + r") if (" + _ATOM + r") else (" + _ATOM + r")",
               r"(\2 ? \1 : \3)", e)
    e = re.sub(r"\bmath\.hypot\((" + _ATOM + r"), (" + _ATOM + r")\)",
               r"length(vec2(\1, \2))", e)
    e = e.replace("math.atan2(", "atan(")
    e = re.sub(r"\bmath\.(sqrt|exp|log|sin|cos|floor)\(", r"\1(", e)
    e = re.sub(r"\.real\b", ".x", e)
    e = re.sub(r"\.imag\b", ".y", e)
    e = re.sub(r"\bnot ", "!", e)
    e = e.replace(" and ", " && ").replace(" or ", " || ")
    e = re.sub(r"\bTrue\b", "true", e)
    e = re.sub(r"\bFalse\b", "false", e)
    # the parameters last: the patterns above take Q[k] as one operand
    e = re.sub(r"\bQ\[(\d+)\]", lambda m: f"({_fl(q[int(m.group(1))])})", e)
    if re.search(r"\b(math|np|complex)\b|\*\*| if | else ", e):  # pragma: no cover
        raise ValueError(f"formula line without a GLSL form: {e}")
    return e


def _type(name: str, rhs: str) -> str:
    if name in ("n", "maxiter"):
        return "int"
    if rhs == "0j":
        return "vec2"
    if rhs == "False":
        return "bool"
    return "float"


def formula_glsl(code, q, fname: str) -> str:
    """The GLSL function ``fname`` of the compiled formula ``code`` with the parameter
    values ``q`` (:meth:`~._formula.FormulaCode.values`) as constants."""
    out = [f"float {fname}(float pr, float pi, float in1, float in2, float in3) {{"]
    declared: set[str] = set()
    depth = 0  # open blocks
    # the formula's own names (u_NAME, u_NAME_r, u_NAME_i) as fv0, fv1, ...: GLSL reserves
    # names with "__" in them (a user's x_ would make u_x__r)
    names: dict[str, str] = {}
    own = re.compile(r"\bu_[A-Za-z0-9_]+")

    def rename(m):
        return names.setdefault(m.group(0), f"fv{len(names)}")

    for raw in (own.sub(rename, line) for line in code.body):
        ind = (len(raw) - len(raw.lstrip(" "))) // 4
        line = raw.strip()
        if line == "else:":
            while depth > ind + 1:  # blocks nested in the if's own block
                depth -= 1
                out.append("    " * depth + "    }")
            out.append("    " * ind + "    } else {")
            continue
        while depth > ind:
            depth -= 1
            out.append("    " * depth + "    }")
        pad = "    " * (ind + 1)
        if line == "pass":
            continue
        if line == "while True:":
            out.append(pad + "while (true) {")
            depth += 1
        elif line.startswith("if ") and line.endswith(":"):
            out.append(f"{pad}if ({_expr(line[3:-1], q)}) {{")
            depth += 1
        elif line == "break":
            out.append(pad + "break;")
        elif line.startswith("return "):
            out.append(f"{pad}return {_expr(line[7:], q)};")
        else:
            m = _ASSIGN.match(line)
            if m is None:  # pragma: no cover - the compiler writes no other line
                raise ValueError(f"formula line without a GLSL form: {line}")
            name, op, rhs = m.groups()
            if name not in declared:
                declared.add(name)
                typ = _type(name, rhs)
                value = {"vec2": "vec2(0.0)", "bool": "false"}.get(typ) if rhs in (
                    "0j", "False") else _expr(rhs, q)
                out.append(f"{pad}{typ} {name} = {value};")
            else:
                out.append(f"{pad}{name} {op} {_expr(rhs, q)};")
    while depth > 0:
        depth -= 1
        out.append("    " * depth + "    }")
    out.append("}")
    return "\n".join(out)
