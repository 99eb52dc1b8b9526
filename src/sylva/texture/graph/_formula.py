"""The formula language: escape-time fractals in the spirit of Ultra Fractal (private; the
reference is ``docs/reference/texture-graph.rst``).

A formula is parsed by our own Lark grammar and compiled to a numba function of the pixel
``(re, im)`` and a parameter array; no text of it is ever evaluated.  Sections:

``default:``  parameter defaults (``maxiter = 256``, ``start = (0.6, 1.1)``), used as ``@name``
``init:``     statements run once (``z = 0``, ``c = #pixel``)
``loop:``     statements run per iteration
``bailout:``  a condition; iteration goes on while it holds and ``#numiter < @maxiter``
``final:``    statements for points that escaped, setting ``#index`` (default ``#numiter``)
``inside:``   the same for points that did not (``#index`` default -1)

Values are real or complex; ``(a, b)`` is a complex literal, ``|z|`` the squared modulus (as in
Ultra Fractal), ``^`` a power (``z^2`` is ``sqr(z)``), ``if … else … endif`` a conditional and
``;`` starts a comment.  Functions: real, imag, conj, abs (both parts), cabs (modulus), sqr,
sqrt, exp, log, sin, cos, atan2 (the argument), min, max, clamp, floor, if(c, a, b).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np
from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from ._nodes import GraphError

GRAMMAR = r"""
start: _NL* NAME "{" _NL+ section* "}" _NL*
section: SECTION _NL+ stmt*
?stmt: target "=" expr _NL+                                   -> assign
     | "if" expr _NL+ block ("else" _NL+ block)? "endif" _NL+  -> ifstmt
     | expr _NL+                                              -> exprstmt
block: stmt*
target: NAME | SPECIAL
?expr: orx
?orx: andx | orx "||" andx -> or_
?andx: notx | andx "&&" notx -> and_
?notx: cmp | "!" notx -> not_
?cmp: sum | sum CMP sum -> compare
?sum: prod | sum ADDOP prod -> binop
?prod: unary | prod MULOP unary -> binop
?unary: power | "-" unary -> neg
?power: atom | atom "^" unary -> pow
?atom: NUMBER -> number
     | NAME -> name
     | SPECIAL -> special
     | PARAM -> param
     | NAME "(" [expr ("," expr)*] ")" -> call
     | "(" expr "," expr ")" -> complex_
     | "(" expr ")"
     | "|" expr "|" -> modsq
SECTION.2: /(init|loop|bailout|final|inside|default)[ \t]*:/
CMP: "<=" | ">=" | "==" | "!=" | "<" | ">"
ADDOP: "+" | "-"
MULOP: "*" | "/"
SPECIAL: /#[A-Za-z][A-Za-z0-9]*/
PARAM: /@[A-Za-z_][A-Za-z0-9_]*/
NAME: /[A-Za-z_][A-Za-z0-9_]*/
NUMBER: /(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?/
COMMENT: /;[^\n]*/
_NL: /(\r?\n[ \t]*)+/
%ignore /[ \t]+/
%ignore COMMENT
"""

MAX_ITER = 10_000_000
SECTIONS = ("default", "init", "loop", "bailout", "final", "inside")
_FUNCS = {"real": 1, "imag": 1, "conj": 1, "abs": 1, "cabs": 1, "sqr": 1, "sqrt": 1, "exp": 1,
          "log": 1, "sin": 1, "cos": 1, "atan2": 1, "floor": 1, "min": 2, "max": 2,
          "clamp": 3, "if": 3}
R, C, B = "real", "complex", "bool"

BUILTIN = {
    "mandelbrot": """mandelbrot {
default:
  maxiter = 256
  bailout = 256.0
  smooth = 1
init:
  z = 0
  c = #pixel
loop:
  z = sqr(z) + c
bailout:
  |z| < @bailout * @bailout
final:
  #index = #numiter
  if @smooth != 0 && #numiter > 0
    lz = 0.5 * log(|z|)
    #index = #numiter + 1 - clamp(log(max(lz / log(@bailout), 1)) / log(2), 0, 0.999999)
  endif
}
""",
    "julia": """julia {
default:
  maxiter = 256
  bailout = 256.0
  smooth = 1
  c = (-0.8, 0.156)
init:
  z = #pixel
  c = @c
loop:
  z = sqr(z) + c
bailout:
  |z| < @bailout * @bailout
final:
  #index = #numiter
  if @smooth != 0 && #numiter > 0
    lz = 0.5 * log(|z|)
    #index = #numiter + 1 - clamp(log(max(lz / log(@bailout), 1)) / log(2), 0, 0.999999)
  endif
}
""",
    "burning-ship": """burning_ship {
default:
  maxiter = 256
  bailout = 256.0
  smooth = 1
init:
  z = 0
  c = #pixel
loop:
  z = sqr(abs(z)) + c  ; (|Re z| + i |Im z|)^2 + c
bailout:
  |z| < @bailout * @bailout
final:
  #index = #numiter
  if @smooth != 0 && #numiter > 0
    lz = 0.5 * log(|z|)
    #index = #numiter + 1 - clamp(log(max(lz / log(@bailout), 1)) / log(2), 0, 0.999999)
  endif
}
""",
    "barnsley-j1": """barnsleyj1 {
default:
  maxiter = 149
  bailout = 4.0      ; Ultra Fractal's |z| < 4 (|z| is the squared modulus)
  start = (0.6, 1.1)
  smooth = 1
  zz = 0             ; 1: the thesis's z = (z -/+ 1) * z * @start
init:
  z = #pixel
loop:
  if real(z) >= 0
    s = z - 1
  else
    s = z + 1
  endif
  if @zz != 0
    s = s * z
  endif
  z = s * @start
bailout:
  |z| < sqrt(@bailout) * sqrt(@bailout)
final:
  #index = #numiter
  if @smooth != 0 && #numiter > 0
    lz = 0.5 * log(|z|)
    logb = log(sqrt(@bailout))
    if @zz == 0 && cabs(@start) > 1
      f = (lz - logb) / log(cabs(@start))
    else
      f = log(max(lz / logb, 1)) / log(2)
    endif
    #index = #numiter + 1 - clamp(f, 0, 0.999999)
  endif
}
""",
}


@lru_cache(maxsize=1)
def _parser():
    return Lark(GRAMMAR, parser="lalr", propagate_positions=True)


class _Where:
    """Maps formula positions to the file that holds the formula."""

    def __init__(self, text, filename=None, line=1, column=1, block=False):
        self.text, self.filename, self.line, self.column, self.block = (text, filename, line,
                                                                       column, block)

    def error(self, msg, line, column):
        lines = self.text.splitlines()
        src = lines[line - 1] if 0 < line <= len(lines) else None
        fl = self.line + line - 1
        fc = column if (self.block or line > 1) else self.column + column - 1
        return GraphError(msg, filename=self.filename, line=fl, column=fc, source_line=src)


def _describe(expected):
    names = {"_NL": "end of line", "NAME": "a name", "NUMBER": "a number", "SECTION":
             "a section (init:, loop:, bailout:, final:, inside:, default:)", "RBRACE": "'}'",
             "LBRACE": "'{'", "RPAR": "')'", "LPAR": "'('", "EQUAL": "'='", "COMMA": "','",
             "PARAM": "an @parameter", "SPECIAL": "#pixel/#numiter/#index"}
    out = sorted({names.get(e, e.lower()) for e in expected})
    return ", ".join(out[:8]) or "more text"


def parse(text, where: _Where):
    """The parse tree of a formula, or a :class:`GraphError` at its line and column."""
    if not text.endswith("\n"):
        text += "\n"
    try:
        return _parser().parse(text)
    except UnexpectedCharacters as e:
        raise where.error(f"unexpected character {text[e.pos_in_stream]!r} in formula; "
                          f"expected {_describe(e.allowed or [])}", e.line, e.column) from None
    except UnexpectedEOF as e:
        lines = text.splitlines()
        raise where.error(f"formula ends early; expected {_describe(e.expected)}",
                          len(lines), len(lines[-1]) + 1 if lines else 1) from None
    except UnexpectedToken as e:
        tok = e.token
        what = "end of text" if tok.type == "$END" else repr(str(tok).strip() or "newline")
        raise where.error(f"unexpected {what} in formula; expected {_describe(e.expected)}",
                          e.line if e.line > 0 else 1, e.column if e.column > 0 else 1) from None
    except UnexpectedInput as e:  # pragma: no cover - the three above cover Lark's cases
        raise where.error("formula does not parse", e.line, e.column) from None


@dataclass
class FormulaCode:
    """A compiled formula: the numba source and its parameter layout."""

    body: list
    params: dict  # name -> (type, default, slot)
    name: str

    def source(self, fname):
        return "\n".join(["", "", "@njit(cache=True, error_model='numpy')",
                          f"def {fname}(pr, pi, Q, in1, in2, in3):",
                          *("    " + s for s in self.body)])

    def values(self, node):
        """The parameter array for ``node`` (its ``params`` override the defaults)."""
        given = dict(node.param("params") or {})
        n = sum(2 if t == C else 1 for t, _, _ in self.params.values())
        q = np.zeros(max(n, 1))
        for name, (t, default, slot) in self.params.items():
            v = given.pop(name, default)
            try:
                if t == C:
                    z = complex(*v) if isinstance(v, list | tuple) else complex(v)
                    q[slot], q[slot + 1] = z.real, z.imag
                else:
                    if isinstance(v, bool) or not isinstance(v, int | float):
                        raise TypeError
                    q[slot] = float(v)
            except (TypeError, ValueError):
                w = node.where.get("params") or node.where.get("type") or {}
                kind = "a complex number [re, im]" if t == C else "a number"
                raise GraphError(f"formula parameter {name!r} must be {kind}, got {v!r}",
                                 **w) from None
        mi = q[self.params["maxiter"][2]]
        if not 1 <= mi <= MAX_ITER or mi != int(mi):
            w = node.where.get("params") or node.where.get("type") or {}
            raise GraphError(f"formula parameter maxiter must be a whole number from 1 to "
                             f"{MAX_ITER}, got {float(mi):g}", **w)
        if given:
            w = node.where.get("params") or node.where.get("type") or {}
            raise GraphError(f"the formula has no parameter(s) {', '.join(sorted(given))}; "
                             f"its parameters: {', '.join(self.params) or 'none'}", **w)
        return q


class _Compiler:
    def __init__(self, where):
        self.where = where
        self.vars = {"z": C, "c": C}
        self.params = {}
        self.lines = []
        self.n = 0
        self.ind = 1
        self.kinds = {}

    def err(self, msg, tree):
        meta = getattr(tree, "meta", None)
        line = getattr(tree, "line", None) or getattr(meta, "line", 1) or 1
        col = getattr(tree, "column", None) or getattr(meta, "column", 1) or 1
        return self.where.error(msg, line, col)

    def emit(self, s):
        self.lines.append("    " * self.ind + s)

    def tmp(self, expr, kind="0.0"):
        self.n += 1
        self.emit(f"t{self.n} = {expr}")
        self.kinds[self.n] = kind
        return f"t{self.n}"

    def ctmp(self, re_, im_):
        a = self.tmp(re_)
        return a, self.tmp(im_)

    # ---- expressions: (type, code) with code a name (real/bool) or a pair (complex)
    def expr(self, t):
        if isinstance(t, Token):
            raise self.err("unexpected token", t)
        d = t.data
        if d == "number":
            return R, repr(float(t.children[0]))
        if d == "name":
            name = str(t.children[0])
            if name not in self.vars:
                raise self.err(f"unknown variable {name!r}; assign it first (known: "
                               f"{', '.join(sorted(self.vars))})", t.children[0])
            return self.vars[name], (f"u_{name}_r", f"u_{name}_i") if self.vars[name] == C \
                else f"u_{name}"
        if d == "special":
            s = str(t.children[0]).lower()
            if s == "#pixel":
                return C, ("pr", "pi")
            if s == "#numiter":
                return R, "float(n)"
            if s == "#index":
                return R, "index"
            if s in ("#in1", "#in2", "#in3"):
                return R, s[1:]
            raise self.err(f"unknown {s}; expected #pixel, #numiter, #index or #in1..#in3 "
                           "(the node's inputs)", t.children[0])
        if d == "param":
            name = str(t.children[0])[1:]
            if name not in self.params:
                raise self.err(f"unknown parameter @{name}; declare it in default:",
                               t.children[0])
            typ, _, slot = self.params[name]
            return typ, (f"Q[{slot}]", f"Q[{slot + 1}]") if typ == C else f"Q[{slot}]"
        if d == "complex_":
            a = self.real(t.children[0])
            b = self.real(t.children[1])
            return C, (a, b)
        if d == "modsq":
            typ, v = self.expr(t.children[0])
            if typ == B:
                raise self.err("|...| needs a number", t)
            if typ == R:
                return R, self.tmp(f"{v} * {v}")
            return R, self.tmp(f"{v[0]} * {v[0]} + {v[1]} * {v[1]}")
        if d == "neg":
            typ, v = self.num(t.children[0])
            if typ == R:
                return R, self.tmp(f"-{v}")
            return C, self.ctmp(f"-{v[0]}", f"-{v[1]}")
        if d == "binop":
            return self.binop(str(t.children[1]), t.children[0], t.children[2], t)
        if d == "pow":
            base, ex = t.children
            if isinstance(ex, Tree) and ex.data == "number" and float(ex.children[0]) == 2.0:
                return self.call("sqr", [base], t)
            ta, a = self.num(base)
            tb, b = self.num(ex)
            if ta == R and tb == R:
                return R, self.tmp(f"{a} ** {b}")
            za = f"complex({a[0]}, {a[1]})" if ta == C else f"complex({a}, 0.0)"
            zb = f"complex({b[0]}, {b[1]})" if tb == C else f"complex({b}, 0.0)"
            w = self.tmp(f"{za} ** {zb}", "0j")
            return C, self.ctmp(f"{w}.real", f"{w}.imag")
        if d == "compare":
            a = self.real(t.children[0])
            b = self.real(t.children[2])
            return B, self.tmp(f"{a} {t.children[1]} {b}", "False")
        if d in ("and_", "or_"):
            a = self.cond(t.children[0])
            b = self.cond(t.children[1])
            return B, self.tmp(f"{a} {'and' if d == 'and_' else 'or'} {b}", "False")
        if d == "not_":
            return B, self.tmp(f"not {self.cond(t.children[0])}", "False")
        if d == "call":
            name = str(t.children[0])
            args = [a for a in t.children[1:] if a is not None]
            return self.call(name, args, t)
        raise self.err(f"unsupported expression {d}", t)  # pragma: no cover

    def num(self, t):
        typ, v = self.expr(t)
        if typ == B:
            raise self.err("a condition cannot be used as a number", t)
        return typ, v

    def real(self, t):
        typ, v = self.expr(t)
        if typ != R:
            raise self.err(f"expected a real number here, got a {typ} value (use real(), "
                           "imag() or cabs())", t)
        return v

    def cond(self, t):
        typ, v = self.expr(t)
        if typ != B:
            raise self.err("expected a condition (a comparison) here", t)
        return v

    def binop(self, op, ta_, tb_, t):
        ta, a = self.num(ta_)
        tb, b = self.num(tb_)
        if ta == R and tb == R:
            return R, self.tmp(f"{a} {op} {b}")
        if op in "+-":
            if ta == C and tb == C:
                return C, self.ctmp(f"{a[0]} {op} {b[0]}", f"{a[1]} {op} {b[1]}")
            if ta == C:
                return C, self.ctmp(f"{a[0]} {op} {b}", a[1])
            return C, self.ctmp(f"{a} {op} {b[0]}", b[1] if op == "+" else f"-{b[1]}")
        if op == "*":
            if ta == C and tb == C:
                return C, self.ctmp(f"{a[0]} * {b[0]} - {a[1]} * {b[1]}",
                                    f"{a[0]} * {b[1]} + {a[1]} * {b[0]}")
            if ta == C:
                return C, self.ctmp(f"{a[0]} * {b}", f"{a[1]} * {b}")
            return C, self.ctmp(f"{a} * {b[0]}", f"{a} * {b[1]}")
        if tb == R:
            return C, self.ctmp(f"{a[0]} / {b}", f"{a[1]} / {b}")
        if ta == R:
            a = (a, "0.0")
        d = self.tmp(f"{b[0]} * {b[0]} + {b[1]} * {b[1]}")
        return C, self.ctmp(f"({a[0]} * {b[0]} + {a[1]} * {b[1]}) / {d}",
                            f"({a[1]} * {b[0]} - {a[0]} * {b[1]}) / {d}")

    def call(self, name, args, t):
        if name not in _FUNCS:
            raise self.err(f"unknown function {name!r}; expected one of: "
                           f"{', '.join(sorted(_FUNCS))}", t)
        if len(args) != _FUNCS[name]:
            raise self.err(f"{name}() takes {_FUNCS[name]} argument(s), got {len(args)}", t)
        if name == "if":
            c = self.cond(args[0])
            ta, a = self.num(args[1])
            tb, b = self.num(args[2])
            if ta != tb:
                raise self.err("both branches of if() must be real or both complex", t)
            if ta == R:
                return R, self.tmp(f"{a} if {c} else {b}")
            return C, self.ctmp(f"{a[0]} if {c} else {b[0]}", f"{a[1]} if {c} else {b[1]}")
        if name in ("min", "max", "clamp"):
            v = [self.real(a) for a in args]
            if name == "clamp":
                return R, self.tmp(f"min(max({v[0]}, {v[1]}), {v[2]})")
            return R, self.tmp(f"{name}({v[0]}, {v[1]})")
        typ, v = self.num(args[0])
        if typ == R:
            table = {"real": "{v}", "imag": "0.0", "conj": "{v}", "abs": "abs({v})",
                     "cabs": "abs({v})", "sqr": "{v} * {v}", "sqrt": "math.sqrt({v})",
                     "exp": "math.exp({v})", "log": "math.log({v})", "sin": "math.sin({v})",
                     "cos": "math.cos({v})", "atan2": "math.atan2(0.0, {v})",
                     "floor": "math.floor({v})"}
            return R, self.tmp(table[name].format(v=v))
        a, b = v
        if name == "real":
            return R, a
        if name == "imag":
            return R, b
        if name == "cabs":
            return R, self.tmp(f"math.hypot({a}, {b})")
        if name == "atan2":
            return R, self.tmp(f"math.atan2({b}, {a})")
        if name == "conj":
            return C, (a, self.tmp(f"-{b}"))
        if name == "abs":
            return C, self.ctmp(f"abs({a})", f"abs({b})")
        if name == "sqr":
            return C, self.ctmp(f"{a} * {a} - {b} * {b}", f"2.0 * {a} * {b}")
        if name == "floor":
            return C, self.ctmp(f"math.floor({a})", f"math.floor({b})")
        fn = {"sqrt": "np.sqrt", "exp": "np.exp", "log": "np.log", "sin": "np.sin",
              "cos": "np.cos"}[name]
        w = self.tmp(f"{fn}(complex({a}, {b}))", "0j")
        return C, self.ctmp(f"{w}.real", f"{w}.imag")

    # ---- statements
    def stmts(self, items, section):
        for s in items:
            self.stmt(s, section)

    def stmt(self, s, section):
        if s.data == "assign":
            tgt = s.children[0].children[0]
            name = str(tgt)
            typ, v = self.num(s.children[1])
            if tgt.type == "SPECIAL":
                if name.lower() != "#index":
                    raise self.err(f"cannot assign {name}; only #index", tgt)
                if section not in ("final", "inside"):
                    raise self.err("#index is set in final: or inside:", tgt)
                if typ != R:
                    raise self.err("#index must be a real number", s.children[1])
                self.emit(f"index = {v}")
                return
            if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):  # pragma: no cover
                raise self.err("bad name", tgt)
            have = self.vars.get(name)
            if have is None:
                self.vars[name] = have = typ
            if have == R and typ == C:
                raise self.err(f"{name!r} is real; it cannot take a complex value", tgt)
            if have == C:
                re_, im_ = v if typ == C else (v, "0.0")
                self.emit(f"u_{name}_r = {re_}")
                self.emit(f"u_{name}_i = {im_}")
            else:
                self.emit(f"u_{name} = {v}")
        elif s.data == "ifstmt":
            c = self.cond(s.children[0])
            self.emit(f"if {c}:")
            self.ind += 1
            self.emit("pass")
            self.stmts(s.children[1].children, section)
            self.ind -= 1
            if len(s.children) > 2 and s.children[2] is not None:
                self.emit("else:")
                self.ind += 1
                self.emit("pass")
                self.stmts(s.children[2].children, section)
                self.ind -= 1
        else:
            raise self.err("a bare expression is only allowed as the bailout: condition", s)


def _literal(t):
    """A default value: a number, or a complex (re, im) of numbers (possibly negative)."""
    if isinstance(t, Tree) and t.data == "number":
        return float(t.children[0])
    if isinstance(t, Tree) and t.data == "neg":
        v = _literal(t.children[0])
        return None if v is None or isinstance(v, complex) else -v
    if isinstance(t, Tree) and t.data == "complex_":
        a, b = (_literal(x) for x in t.children)
        if isinstance(a, float) and isinstance(b, float):
            return complex(a, b)
    return None


def compile_formula(text, where: _Where) -> FormulaCode:
    tree = parse(text, where)
    comp = _Compiler(where)
    sections = {}
    for sec in tree.children[1:]:
        if not isinstance(sec, Tree):
            continue
        name = str(sec.children[0]).rstrip(": \t")
        if name in sections:
            raise comp.err(f"section {name}: appears twice", sec.children[0])
        sections[name] = (sec.children[0], [c for c in sec.children[1:] if c is not None])
    slot = 0
    for s in sections.get("default", (None, []))[1]:
        tgt = s.children[0].children[0] if s.data == "assign" else None
        val = _literal(s.children[1]) if tgt is not None else None
        if tgt is None or tgt.type != "NAME" or val is None:
            raise comp.err("default: holds parameter = number or (re, im) lines", s)
        typ = C if isinstance(val, complex) else R
        comp.params[str(tgt)] = (typ, [val.real, val.imag] if typ == C else val, slot)
        slot += 2 if typ == C else 1
    if "maxiter" not in comp.params:
        comp.params["maxiter"] = (R, 100.0, slot)
    if "bailout" not in sections and "loop" in sections:
        raise comp.err("a formula with a loop: needs a bailout: section (the condition to go "
                       "on)", sections["loop"][0])
    bail = sections.get("bailout", (None, []))[1]
    if "bailout" in sections and (len(bail) != 1 or bail[0].data != "exprstmt"):
        raise comp.err("bailout: holds one condition", sections["bailout"][0])
    comp.emit("u_z_r = 0.0")
    comp.emit("u_z_i = 0.0")
    comp.emit("u_c_r = 0.0")
    comp.emit("u_c_i = 0.0")
    comp.emit("index = 0.0")
    comp.emit("n = 0")
    decl = len(comp.lines)
    comp.stmts(sections.get("init", (None, []))[1], "init")
    comp.emit(f"maxiter = int({comp.expr(Tree('param', [Token('PARAM', '@maxiter')]))[1]})")
    if not bail:  # a custom node: no iteration, final: computes #index
        comp.emit("index = 0.0")
        comp.stmts(sections.get("final", (None, []))[1], "final")
        comp.emit("return index")
        return _finish(comp, decl, tree)
    comp.emit("while True:")
    comp.ind += 1
    b = comp.cond(bail[0].children[0])
    comp.emit(f"if not {b} or n >= maxiter:")
    comp.emit("    break")
    comp.stmts(sections.get("loop", (None, []))[1], "loop")
    comp.emit("n += 1")
    comp.ind -= 1
    comp.emit(f"if {b}:")
    comp.ind += 1
    comp.emit("index = -1.0")
    comp.stmts(sections.get("inside", (None, []))[1], "inside")
    comp.emit("return index")
    comp.ind -= 1
    comp.emit("index = float(n)")
    comp.stmts(sections.get("final", (None, []))[1], "final")
    comp.emit("return index")
    return _finish(comp, decl, tree)


def _finish(comp, decl, tree) -> FormulaCode:
    # every variable starts at 0 (numba needs one type per name through every branch)
    init = []
    for name, typ in comp.vars.items():
        if name in ("z", "c"):
            continue
        init += [f"    u_{name}_r = 0.0", f"    u_{name}_i = 0.0"] if typ == C \
            else [f"    u_{name} = 0.0"]
    # temporaries read after a loop or branch also need a value on every path
    temps = [f"    t{k} = {comp.kinds[k]}" for k in range(1, comp.n + 1)]
    body = comp.lines[:decl] + init + temps + comp.lines[decl:]
    return FormulaCode([s[4:] for s in body], comp.params, str(tree.children[0]))


def for_node(node) -> FormulaCode:
    """The compiled formula of a ``formula`` node or of a built-in fractal node."""
    if node.type != "formula":
        return compile_formula(BUILTIN[node.type], _Where(BUILTIN[node.type],
                                                          f"<{node.type}>", 1, 1, True))
    src, path = node.param("source"), node.param("file")
    if (src is None) == (path is None):
        raise GraphError("a formula node needs either source (the formula text) or file",
                         **(node.where.get("type") or {}))
    if path is not None:
        try:
            text = Path(path).read_text(encoding="utf-8")
        except OSError as exc:
            raise GraphError(f"cannot read formula file {path}: {exc.strerror or exc}",
                             **(node.where.get("file") or {})) from None
        return compile_formula(text, _Where(text, str(path), 1, 1, True))
    if not isinstance(src, str):
        raise GraphError("formula source must be text", **(node.where.get("source") or {}))
    w = node.where.get("source") or {}
    return compile_formula(src, _Where(src, w.get("filename", "<formula>"),
                                       w.get("text_line", w.get("line", 1)),
                                       w.get("text_column", w.get("column", 1)),
                                       w.get("block", True)))
