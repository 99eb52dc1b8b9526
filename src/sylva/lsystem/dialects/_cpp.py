"""The subset of the C preprocessor that cpfg files use, with every character's origin kept.

cpfg runs its L-system files through ``cpp`` before reading them.  This module does the part
of that which cpfg's published models use, without running a C compiler:

* comments ``/* … */`` and ``//`` (removed first, as C does, so a ``#define`` may end with
  one);
* ``#define NAME body`` and ``#define NAME(a, b) body`` (object- and function-like macros;
  the body runs to the end of the line, a trailing ``\\`` continues it), ``#undef NAME``;
* ``#include "file"`` / ``#include <file>``, relative to the including file's folder (the
  current folder for a text without a file name), nested at most :data:`INCLUDE_DEPTH`
  deep;
* ``#ifdef``, ``#ifndef``, ``#if``, ``#elif``, ``#else``, ``#endif``; ``#if`` takes a
  constant expression (sylva's expressions with cpfg's ``^`` power, ``defined(NAME)``,
  names that are not macros count 0, as in C).

A line is a directive only when ``#`` is its first non-blank character: a ``#`` anywhere
else is text (cpfg's width-increment module ``F#F``).  Stringification (``#a``) and token
pasting (``##``) are not done: a ``#`` in a body stays the module ``#``.  Other
directives (``#pragma``, ``#line``, ``#error``) are errors that name them.

Macros whose body is a constant number expression are *constants* (:attr:`Result.constants`):
the reader writes them as ``NAME = value`` so that a program keeps its named constants, and
they are not substituted into the text.  Every other macro is substituted where its name
appears as a C identifier (so ``#define A B`` leaves ``FA`` alone, as cpp does).

Each output line keeps, per character, the file, line and column it came from; text that a
macro made points at the macro's name where it was used.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from ...errors import LSystemSyntaxError, SylvaError

__all__ = ["INCLUDE_DEPTH", "Line", "Result", "preprocess", "strip_comments"]

#: The deepest nesting of ``#include`` (a file that includes itself stops here).
INCLUDE_DEPTH = 16
#: The most nested macro expansions of one name (recursion is cut off before, as in C).
_EXPANSION_DEPTH = 64

_DIRECTIVE = re.compile(r"\s*#\s*([A-Za-z_]\w*)?(.*)\Z", re.DOTALL)
#: A line that starts with cpfg's module ``#`` (the width), not a directive: ``#(0.1) F``.
_MODULE_HASH = re.compile(r"\s*#\s*[(#!;,\[\]{}+\-&^\\/|$@~.]")
_TOKEN = re.compile(r"(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[A-Za-z_]\w*|.", re.DOTALL)
_IDENT = re.compile(r"[A-Za-z_]\w*\Z")
_DEFINED = re.compile(r"\bdefined\s*(?:\(\s*([A-Za-z_]\w*)\s*\)|([A-Za-z_]\w*))")

Origin = tuple[str | None, int, int]  # file, 1-based line, 1-based column


@dataclass
class Line:
    """A line of preprocessed text; ``origin[i]`` is where ``text[i]`` came from (one more
    entry, for the end of the line)."""

    text: str
    origin: list[Origin]
    define: str | None = None  # the name of a constant: ``text`` is its value

    def at(self, column: int) -> Origin:
        """The origin of 1-based ``column`` (clamped to the line)."""
        return self.origin[max(0, min(column - 1, len(self.origin) - 1))]

    def slice(self, start: int, end: int | None = None) -> Line:
        end = len(self.text) if end is None else end
        tail = self.origin[min(end, len(self.origin) - 1)]
        return Line(self.text[start:end], self.origin[start:end] + [tail])

    def __add__(self, other: Line) -> Line:
        return Line(self.text + other.text, self.origin[:-1] + other.origin)


@dataclass
class _Macro:
    name: str
    params: tuple[str, ...] | None  # None: object-like
    body: str


@dataclass
class Result:
    """The preprocessed lines, the constants among the macros (name, body line) in order of
    definition, and each source line's text by (file, line)."""

    lines: list[Line]
    constants: list[tuple[str, Line]] = field(default_factory=list)
    sources: dict[tuple[str | None, int], str] = field(default_factory=dict)
    values: dict[str, float] = field(default_factory=dict)  # of the constants

    def error(self, message: str, origin: Origin, cls=LSystemSyntaxError) -> SylvaError:
        file, line, column = origin
        return cls(message, filename=file, line=line, column=column,
                   source_line=self.sources.get((file, line)))  # fmt: skip


def strip_comments(text: str) -> str:
    """``/* … */`` and ``//`` comments blanked out, line breaks kept (so are columns)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        else:
            out.append(text[i])
            i += 1
    return "".join(out)


def _line(text: str, file: str | None, number: int) -> Line:
    return Line(text, [(file, number, c) for c in range(1, len(text) + 2)])


class _State:
    def __init__(self, result: Result):
        self.result = result
        self.macros: dict[str, _Macro] = {}
        self.constants: dict[str, float] = {}

    # ---------------------------------------------------------------- expansion
    def expand(self, line: Line, hide: frozenset[str] = frozenset(), depth: int = 0) -> Line:
        """``line`` with its (non-constant) macros substituted."""
        if depth > _EXPANSION_DEPTH:
            raise self.result.error("macro expansion nested too deeply (a macro that "
                                    "expands to itself?)", line.at(1))  # fmt: skip
        text = line.text
        pieces: list[Line] = []
        pos = 0
        i = 0
        while i < len(text):
            m = _TOKEN.match(text, i)
            tok = m.group()
            macro = self.macros.get(tok) if _IDENT.match(tok) else None
            if macro is None or tok in hide:
                i = m.end()
                continue
            start, end = i, m.end()
            args: list[Line] | None = None
            if macro.params is not None:
                j = end
                while j < len(text) and text[j] in " \t":
                    j += 1
                if j >= len(text) or text[j] != "(":
                    i = end  # a function-like macro's name without '(' is not a call
                    continue
                args, end = self._arguments(line, j, tok)
                if len(args) != len(macro.params) and not (
                    macro.params == () and len(args) == 1 and not args[0].text.strip()
                ):
                    raise self.result.error(
                        f"macro {tok} takes {len(macro.params)} argument(s), got {len(args)}",
                        line.at(start + 1))  # fmt: skip
            where = line.origin[start]
            body = self._substitute(macro, args, hide, depth)
            made = Line(body, [where] * (len(body) + 1))
            pieces.append(line.slice(pos, start))
            pieces.append(self.expand(made, hide | {tok}, depth + 1))
            pos = i = end
        if not pieces:
            return line
        pieces.append(line.slice(pos))
        out = pieces[0]
        for p in pieces[1:]:
            out = out + p
        return out

    def _arguments(self, line: Line, at: int, name: str) -> tuple[list[Line], int]:
        text, depth, start, args = line.text, 0, at + 1, []
        for k in range(at, len(text)):
            ch = text[k]
            if ch == "(":
                depth += 1
            elif ch == ")":
                depth -= 1
                if depth == 0:
                    args.append(line.slice(start, k))
                    return args, k + 1
            elif ch == "," and depth == 1:
                args.append(line.slice(start, k))
                start = k + 1
        raise self.result.error(f"unterminated arguments of macro {name}; expected ')'",
                                line.at(at + 1))  # fmt: skip

    def _substitute(self, macro: _Macro, args, hide, depth) -> str:
        if macro.params is None:
            return macro.body
        values = {p: self.expand(a, hide, depth + 1).text.strip()
                  for p, a in zip(macro.params, args or [], strict=False)}  # fmt: skip
        return "".join(values.get(t, t) for t in _TOKEN.findall(macro.body))

    # ---------------------------------------------------------------- expressions
    def evaluate(self, text: str) -> float | None:
        """The value of a constant expression over the constants, or None."""
        from ..expr import evaluate_constant
        from .lsysvis import parse_expr

        try:
            v = float(evaluate_constant(parse_expr(text.replace("^", "**")), self.constants))
        except (SylvaError, ArithmeticError, ValueError, TypeError):
            return None
        return v if math.isfinite(v) else None

    def condition(self, line: Line, rest: int, what: str) -> bool:
        rest += len(line.text[rest:]) - len(line.text[rest:].lstrip())
        text = _DEFINED.sub(lambda m: "1" if (m.group(1) or m.group(2)) in self.macros
                            or (m.group(1) or m.group(2)) in self.constants else "0",
                            line.text[rest:])  # fmt: skip
        text = self.expand(Line(text, [line.at(rest + 1)] * (len(text) + 1))).text
        names = {t for t in _TOKEN.findall(text) if _IDENT.match(t)} - set(self.constants)
        for n in names:  # C: a name that is not a macro is 0
            text = re.sub(rf"\b{n}\b(?!\s*\()", "0", text)
        if not text.strip():
            raise self.result.error(f"#{what} needs a constant expression", line.at(rest + 1))
        v = self.evaluate(text)
        if v is None:
            raise self.result.error(f"#{what} {text.strip()!r}: expected a constant expression",
                                    line.at(rest + 1))  # fmt: skip
        return v != 0.0


def preprocess(text: str, filename: str | None = None) -> Result:
    """Run the preprocessor over ``text`` (from ``filename``); see the module notes.

    Raises
    ------
    LSystemSyntaxError
        For a bad or unsupported directive, a missing include file, an unterminated ``#if``,
        naming the file, line and column.
    """
    result = Result([])
    state = _State(result)
    _file(state, text, filename, 0, None)
    return result


def _file(state: _State, text: str, filename: str | None, depth: int, at: Origin | None) -> None:
    result = state.result
    raw = text.removeprefix("\ufeff").split("\n")
    for n, s in enumerate(raw, start=1):
        result.sources[(filename, n)] = s.rstrip("\r")
    lines = strip_comments(text.removeprefix("\ufeff")).split("\n")
    stack: list[list] = []  # [active, taken, else seen, origin] per open #if
    k = 0
    while k < len(lines):
        number = k + 1
        line = _line(lines[k].rstrip("\r"), filename, number)
        k += 1
        m = None if _MODULE_HASH.match(line.text) else _DIRECTIVE.match(line.text)
        active = all(s[0] for s in stack)
        if m is None:
            result.lines.append(state.expand(line) if active else _line("", filename, number))
            continue
        result.lines.append(_line("", filename, number))
        while line.text.rstrip().endswith("\\") and k < len(lines):  # a directive continued
            cut = len(line.text.rstrip()) - 1
            if line.text[:cut].endswith("\\"):  # vlab's files write '\\' for one '\'
                cut -= 1
            line = line.slice(0, cut) + _line(lines[k].rstrip("\r"), filename, k + 1)
            k += 1
            result.lines.append(_line("", filename, k))
        name = m.group(1) or ""
        rest = m.start(2)
        hash_at = line.text.index("#") + 1
        if name in ("ifdef", "ifndef"):
            word = line.text[rest:].strip()
            if not _IDENT.match(word):
                raise result.error(f"#{name} needs a macro name", line.at(rest + 1))
            known = word in state.macros or word in state.constants
            stack.append([known == (name == "ifdef"), False, False, line.at(hash_at)])
            stack[-1][1] = stack[-1][0]
        elif name == "if":
            parent = active
            v = state.condition(line, rest, name) if parent else False
            stack.append([v, v, False, line.at(hash_at)])
        elif name in ("elif", "else", "endif"):
            if not stack:
                raise result.error(f"#{name} without #if", line.at(hash_at))
            top = stack[-1]
            if name == "endif":
                stack.pop()
            elif top[2]:
                raise result.error(f"#{name} after #else", line.at(hash_at))
            elif name == "else":
                top[0], top[2] = not top[1], True
            else:
                parent = all(s[0] for s in stack[:-1])
                v = not top[1] and parent and state.condition(line, rest, name)
                top[0] = v
                top[1] = top[1] or v
        elif not active:
            continue
        elif name == "define":
            _define(state, line, rest)
        elif name == "undef":
            word = line.text[rest:].strip()
            state.macros.pop(word, None)
            state.constants.pop(word, None)
        elif name == "include":
            _include(state, line, rest, filename, depth)
        else:
            shown = f"#{name}" if name else "#"
            raise result.error(f"{shown} is not supported; expected #define, #include, "
                               "#ifdef, #ifndef, #if, #elif, #else, #endif or #undef",
                               line.at(hash_at))  # fmt: skip
    if stack:
        raise result.error("#if without #endif", stack[-1][3])


def _define(state: _State, line: Line, rest: int) -> None:
    text = line.text
    m = re.compile(r"\s*([A-Za-z_]\w*)").match(text, rest)
    if m is None:
        raise state.result.error("#define needs a macro name", line.at(rest + 1))
    name = m.group(1)
    params = None
    at = m.end()
    if at < len(text) and text[at] == "(":
        close = text.find(")", at)
        if close < 0:
            raise state.result.error(f"#define {name}(: expected ')'", line.at(at + 1))
        params = tuple(p.strip() for p in text[at + 1 : close].split(",") if p.strip())
        bad = [p for p in params if not _IDENT.match(p)]
        if bad:
            raise state.result.error(f"#define {name}: bad parameter {bad[0]!r}; expected names",
                                     line.at(at + 2))  # fmt: skip
        at = close + 1
    while at < len(text) and text[at] in " \t":
        at += 1
    body = line.slice(at, len(text.rstrip()))
    if name in state.macros or name in state.constants:
        old = state.macros.get(name)
        same = old is not None and old.params == params and old.body == body.text
        if not same and not (
            name in state.constants
            and params is None
            and state.evaluate(state.expand(body).text) == state.constants[name]
        ):
            raise state.result.error(
                f"#define {name} again with another value; expected #undef {name} first "
                "(a name is one constant for the whole L-system)",
                line.at(m.start(1) + 1),
            )
        return
    if params is None and body.text.strip():
        expanded = state.expand(body)
        v = state.evaluate(expanded.text)
        if v is not None:
            state.constants[name] = v
            state.result.constants.append((name, expanded))
            state.result.values[name] = v
            state.result.lines[-1] = Line(expanded.text, expanded.origin, define=name)
            return
    state.macros[name] = _Macro(name, params, body.text)


def _include(state: _State, line: Line, rest: int, filename: str | None, depth: int) -> None:
    text = state.expand(line.slice(rest)).text.strip()
    m = re.fullmatch(r'"([^"]+)"|<([^>]+)>', text)
    if m is None:
        raise state.result.error(f'#include {text}: expected "file" or <file>', line.at(rest + 1))
    name = m.group(1) or m.group(2)
    where = line.at(line.text.index(name, rest) + 1)
    if depth >= INCLUDE_DEPTH:
        raise state.result.error(f"#include {name}: nested deeper than {INCLUDE_DEPTH} files "
                                 "(does a file include itself?)", where)  # fmt: skip
    folder = Path(filename).parent if filename else Path(".")
    path = folder / name
    try:
        data = path.read_bytes()
    except OSError as e:
        raise state.result.error(
            f"#include {name}: cannot read {str(path)!r} "
            f"({e.strerror or e}); expected a file beside "
            f"{filename or 'the current folder'}",
            where,
        ) from None
    try:
        included = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        included = data.decode("latin-1")
    _file(state, included, str(path), depth + 1, where)
