"""The Studio's debugger: breakpoints that stop a derivation, and a per-rule profile.

A breakpoint is checked after every step of a run (:func:`debugging`):

* ``{"kind": "rule", "rule": i}`` — production ``i`` (its index in the program's
  productions, as :func:`rules` lists them) rewrote at least one module in the step;
* ``{"kind": "module", "symbol": "X"}`` — a module ``X`` was made in the step;
* ``{"kind": "condition", "text": "A(x) : x > 3"}`` — a module of the word matches the
  pattern and its condition holds (the pattern and condition are parsed by the ``.lsys``
  parser, :func:`sylva.lsystem.parse_rule`, and evaluated by the compiled expressions of
  :mod:`sylva.lsystem.expr`: user text is never evaluated as Python).

The hit says which modules matched (their indices in the word, the first
:data:`MAX_MATCHED`), and the derivation stays at that step, so that the next run steps on
from there.  The rule and module breakpoints and the profile read the rule trace
(:attr:`sylva.lsystem.Derivation.on_rewrite`, called on the traced road only): the fast
roads of a derivation without them are untouched.

The profile counts, per step and per rule, the instances rewritten (modules of the old word
the rule replaced) and the modules written; the step's time is measured, and split between
its rules by the modules each wrote (the rewriting is one vectorised pass over all rules, so
a rule's own time is not measured apart).
"""

from __future__ import annotations

import time

import numpy as np

from ..errors import GrowthLimitError, SylvaError
from ..lsystem import parse_rule
from ..lsystem.dialects import format_rule
from ..lsystem.expr import compile_expr, truth
from ._limits import Limits
from ._sessions import Session

__all__ = ["MAX_BREAKPOINTS", "MAX_MATCHED", "check_breakpoints", "debugging", "rules"]

MAX_BREAKPOINTS = 16
MAX_MATCHED = 200
MAX_PROFILE = 500  # steps kept in a session's profile


def rules(program) -> list[dict]:
    """The program's productions as the rule picker lists them."""
    out = []
    for i, r in enumerate(program.productions):
        span = r.span
        out.append({"index": i, "text": format_rule(r),
                    "line": span.line if span is not None else None})
    return out


class _Condition:
    """``A(x, y) : condition`` as a test of the modules of a word."""

    def __init__(self, text: str, constants) -> None:
        src = text.strip()
        if ":" not in src:
            src += " : 1"
        # the successor is never used: a rule's text is parsed for its pattern and condition
        rule = parse_rule(src + " -> F", constants=dict(constants), filename="<breakpoint>")
        if rule.left or rule.right:
            raise SylvaError("a condition breakpoint is one module and a condition, such "
                             "as A(x) : x > 3 (no context)")
        self.symbol = rule.predecessor.symbol
        self.names = rule.predecessor.params
        self.test = compile_expr(rule.condition, bound=self.names, constants=dict(constants)) \
            if rule.condition is not None else None

    def matches(self, word) -> np.ndarray:
        sid = word.alphabet.get(self.symbol)
        if sid < 0:
            return np.empty(0, np.int64)
        idx = np.flatnonzero(word.ids == sid)
        if len(self.names):
            idx = idx[word.nparams[idx] == len(self.names)]
        if not len(idx) or self.test is None:
            return idx
        off = word.offsets
        env = {n: word.values[off[idx] + k] for k, n in enumerate(self.names)}
        ok = truth(np.broadcast_to(self.test(env, len(idx)), (len(idx),)))
        return idx[ok]


def check_breakpoints(raw, program) -> list[dict]:
    """The breakpoints of a request, checked: a :class:`SylvaError` names the bad one."""
    if raw is None:
        return []
    if not isinstance(raw, list) or len(raw) > MAX_BREAKPOINTS:
        raise SylvaError(f"breakpoints must be a list of at most {MAX_BREAKPOINTS}")
    n_rules = len(program.productions)
    out = []
    for k, b in enumerate(raw):
        if not isinstance(b, dict):
            raise SylvaError(f"breakpoint {k + 1} must be an object with a kind")
        kind = b.get("kind")
        if kind == "rule":
            i = b.get("rule")
            if isinstance(i, bool) or not isinstance(i, int) or not 0 <= i < n_rules:
                raise SylvaError(f"breakpoint {k + 1}: rule must be a rule number in "
                                 f"[0, {n_rules - 1}]" if n_rules else
                                 f"breakpoint {k + 1}: the program has no rules")
            out.append({"kind": "rule", "rule": i})
        elif kind == "module":
            s = b.get("symbol")
            if not isinstance(s, str) or not s.strip() or len(s) > 64:
                raise SylvaError(f"breakpoint {k + 1}: symbol must be a module name")
            out.append({"kind": "module", "symbol": s.strip()})
        elif kind == "condition":
            t = b.get("text")
            if not isinstance(t, str) or not t.strip() or len(t) > 500 or "\n" in t:
                raise SylvaError(f"breakpoint {k + 1}: text must be one line such as "
                                 "A(x) : x > 3")
            try:
                cond = _Condition(t, program.constants)
            except SylvaError as exc:
                raise SylvaError(f"breakpoint {k + 1} ({t.strip()}): {exc}") from None
            out.append({"kind": "condition", "text": t.strip(), "test": cond})
        else:
            raise SylvaError(f"breakpoint {k + 1}: kind must be rule, module or condition")
    return out


def _public(b: dict) -> dict:
    return {k: v for k, v in b.items() if k != "test"}


def debugging(session: Session, n: int, breakpoints: list[dict], profile: bool,
              limits: Limits, clock=None):
    """Derive up to ``n`` steps, stopping after the first step where a breakpoint holds; a
    generator (the scheduler's turns) that returns ``{done, hit}``.

    With ``profile`` (or a rule or module breakpoint) the session's derivation must trace
    rules.  The profile of each step is appended to ``session.profile``.
    """
    from . import _work  # the cap checks and the module cap's message

    d = session.derivation
    needs_trace = profile or any(b["kind"] in ("rule", "module") for b in breakpoints)
    if needs_trace and not d.trace:
        raise SylvaError("rule and module breakpoints and the profile need rule tracing: "
                         "turn on Rule tracing and reset")
    n_rules = len(session.program.productions)
    seen: dict = {}

    def hook(step, src, rule):
        made = rule >= 0
        first = np.ones(len(src), bool)
        first[1:] = src[1:] != src[:-1]
        seen["instances"] = np.bincount(rule[made & first], minlength=n_rules)
        seen["written"] = np.bincount(rule[made], minlength=n_rules)
        seen["new"] = made

    clock = clock or _work._clock()
    done = 0
    hit = None
    start = time.perf_counter()
    session.progress = {"steps": 0, "of": n, "modules": len(d.word), "interpreted": 0}
    if needs_trace:
        d.on_rewrite = hook
    try:
        for _ in range(n):
            _work.check_turn(session, limits, clock, done, n)
            seen.clear()
            t0 = time.perf_counter()
            try:
                d.advance(1)
            except GrowthLimitError as exc:
                raise _work.CapError("modules", _work.refused(d, exc, limits, done, n)) \
                    from None
            dt = time.perf_counter() - t0
            done += 1
            session.progress.update(steps=done, modules=len(d.word))
            session.timings["derive_ms"] = (time.perf_counter() - start) * 1e3
            if profile and "written" in seen:
                written = seen["written"]
                total = max(int(written.sum()), 1)
                session.profile.append({
                    "step": d.step,
                    "ms": dt * 1e3,
                    "modules": len(d.word),
                    "rules": [{"rule": i, "instances": int(seen["instances"][i]),
                               "written": int(written[i]),
                               "ms": dt * 1e3 * int(written[i]) / total}
                              for i in range(n_rules) if seen["instances"][i]],
                })
                del session.profile[:-MAX_PROFILE]
            hit = _first_hit(d, breakpoints, seen)
            if hit is not None:
                break
            yield
    finally:
        d.on_rewrite = None
    return {"done": done, "hit": hit}


def _first_hit(d, breakpoints, seen) -> dict | None:
    word = d.word
    for b in breakpoints:
        if b["kind"] == "rule":
            if "instances" in seen and seen["instances"][b["rule"]]:
                idx = np.flatnonzero((d.origin_rules == b["rule"])
                                     & (d.origin_steps == d.step))
            else:
                continue
        elif b["kind"] == "module":
            sid = word.alphabet.get(b["symbol"])
            if sid < 0 or "new" not in seen:
                continue
            idx = np.flatnonzero((word.ids == sid) & (d.origin_steps == d.step))
        else:
            idx = b["test"].matches(word)
        if len(idx):
            return {**_public(b), "step": d.step, "count": int(len(idx)),
                    "matched": idx[:MAX_MATCHED].tolist()}
    return None
