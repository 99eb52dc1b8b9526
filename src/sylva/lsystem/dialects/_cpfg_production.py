"""Reading one cpfg production with statement blocks: ``pred : {pre} cond {post} --> succ``.

:func:`split_blocks` takes the blocks out of the text left of the arrow; :func:`hoist`
moves each call of a function that only cpfg has (``func``, ``ran``, ``nran`` …, see
:mod:`._cpfg_blocks`) out of a condition or successor into the production's block, as a
variable ``_hN`` the engine binds per application, and renames block variables whose names
are sylva settings (``len`` → ``_b_len``).
"""

from __future__ import annotations

import re

from ..expr import FUNCTIONS
from ._cpfg_blocks import DEGREES

__all__ = ["hoist", "split_blocks"]

_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def _match(text: str, at: int, open_: str, close: str) -> int:
    """The index of the bracket closing the one at ``at`` (or -1)."""
    depth = 0
    for k in range(at, len(text)):
        if text[k] == open_:
            depth += 1
        elif text[k] == close:
            depth -= 1
            if depth == 0:
                return k
    return -1


def split_blocks(cond: str) -> tuple[str | None, int, str, str | None, int]:
    """``{pre} condition {post}`` (each part optional) as (pre, its offset, condition,
    post, its offset); a block's text excludes its braces.  Raises ValueError(offset) for a
    brace that does not close."""
    pre = post = None
    pre_at = post_at = 0
    rest = cond
    lead = len(rest) - len(rest.lstrip())
    if rest.lstrip().startswith("{"):
        at = lead
        end = _match(rest, at, "{", "}")
        if end < 0:
            raise ValueError(at)
        pre, pre_at = rest[at + 1 : end], at + 1
        rest = " " * (end + 1) + rest[end + 1 :]
    at = rest.find("{")
    if at >= 0:
        end = _match(rest, at, "{", "}")
        if end < 0:
            raise ValueError(at)
        if rest[end + 1 :].strip():
            raise ValueError(end + 1)
        post, post_at = rest[at + 1 : end], at + 1
        rest = rest[:at]
    return pre, pre_at, rest, post, post_at


def hoist(text: str, calls: list, rename: dict, *, successor: bool) -> str:
    """``text`` with each call of a function sylva's expressions lack replaced by ``_hN``
    (appended to ``calls`` as ``(name, call text)``) and renamed variables renamed.
    In a successor only what is inside a module's parentheses is an expression."""
    if "?" in text:
        text = _hoist_ternaries(text, calls, successor)
    out, k, depth = [], 0, 0
    n = len(text)
    while k < n:
        ch = text[k]
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        m = _IDENT.match(text, k) if (ch.isalpha() or ch == "_") else None
        after_word = k > 0 and (text[k - 1].isalnum() or text[k - 1] in "_@.")
        if m is None or (successor and depth <= 0) or after_word:
            if m is not None and not (successor and depth <= 0):
                out.append(m.group())
                k = m.end()
                continue
            out.append(ch)
            k += 1
            continue
        name = m.group()
        j = m.end()
        while j < n and text[j] == " ":
            j += 1
        if j < n and text[j] == "[":  # an element of a global array
            end = _match(text, j, "[", "]")
            while 0 < end < n - 1 and text[end + 1] == "[":  # len[o][i]
                end = _match(text, end + 1, "[", "]")
            if end > 0:
                var = f"_h{len(calls) + 1}"
                calls.append((var, text[k : end + 1]))
                out.append(var)
                k = end + 1
                continue
        if j < n and text[j] == "(":
            if name not in FUNCTIONS or name in DEGREES:  # cpfg's degrees: in a block
                end = _match(text, j, "(", ")")
                if end < 0:
                    out.append(text[k:])
                    break
                var = f"_h{len(calls) + 1}"
                calls.append((var, text[k : end + 1]))
                out.append(var)
                k = end + 1
                continue
            out.append(name)
            k = m.end()
            continue
        out.append(rename.get(name, name))
        k = m.end()
    return "".join(out)


def _hoist_ternaries(text: str, calls: list, successor: bool) -> str:
    """Each argument (of a successor's module) or condition with C's ``a ? b : c`` as a
    block variable ``_hN`` (sylva's expressions have no conditional operator)."""
    if not successor:
        var = f"_h{len(calls) + 1}"
        calls.append((var, text))
        return var
    out, k, n = [], 0, len(text)
    while k < n:
        if text[k] == "(" and (k == 0 or text[k - 1] != "("):
            end = _match(text, k, "(", ")")
            if end < 0:
                break
            args, start, depth = [], k + 1, 0
            for j in range(k + 1, end):
                depth += (text[j] == "(") - (text[j] == ")")
                if text[j] == "," and depth == 0:
                    args.append(text[start:j])
                    start = j + 1
            args.append(text[start:end])
            new = []
            for a in args:
                if "?" in a:
                    var = f"_h{len(calls) + 1}"
                    calls.append((var, a))
                    new.append(var)
                else:
                    new.append(a)
            out.append("(" + ",".join(new) + ")")
            k = end + 1
            continue
        out.append(text[k])
        k += 1
    out.append(text[k:])
    return "".join(out)
