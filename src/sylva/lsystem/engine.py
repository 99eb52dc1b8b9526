"""Derivation: rewriting every module of a word in parallel, for every class of L-system.

One engine serves every dialect.  A step rewrites *all instances of a symbol at once*:

1. the positions of each symbol that has rules are found;
2. for each priority tier (conditional > context > context-free, seed 001 §2.4) every
   rule of the tier is tested on all still-undecided instances together — contexts by a
   compiled matcher, parameter counts by array comparisons, conditions as masks computed
   by the compiled expression;
3. among the applicable rules of the first tier that has any, one rule per instance is
   drawn by weight with a single vectorised draw;
4. the successors are assembled by a compiled kernel and their parameters evaluated per
   rule for all its instances at once.

Context-free systems without parameters take a faster road: one compiled pass over a
table of successors.  Both roads draw their random numbers from a counter-based hash of
``(seed, step, position)``, so they produce the same word, and the same seed gives the same
word on every machine, whatever the order of evaluation.

Examples
--------
>>> from sylva.lsystem.ast import Module, Pattern, Program, Rule
>>> algae = Program(axiom=(Module("a"),),
...                 rules=(Rule(Pattern("a"), (Module("a"), Module("b"))),
...                        Rule(Pattern("b"), (Module("a"),))))
>>> [str(w) for w in iterate(algae, 4)]
['a', 'ab', 'aba', 'abaab', 'abaababa']
"""

from __future__ import annotations

import contextlib
import copy
import os
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from .._jit import road
from ..errors import GrowthLimitError, LSystemSemanticError, StepsError
from . import _arity, _walk
from . import _sublsystems as _sub
from . import environment as _open
from ._cut import _apply_cut, _cut_keep
from ._lineage import axiom_keys, child_index, decomposed_keys, lineage_keys
from ._memory import _check_limit, block_step_bytes, fast_step_bytes, general_step_bytes
from ._steps import _FLOOR_ITERATIONS, DEFAULT_MODULE_LIMIT, check_steps
from .ast import MAX_STEPS, Program, Rule
from .environment import Query, apply_query, has_queries, missing_query
from .expr import compile_expr, truth
from .lstring import CLOSE, ID_DTYPE, OPEN, SMALL_WORD, Alphabet, ModuleString
from .matching import ignored_table, pattern_match

_kernels = road("sylva.lsystem._kernels", size=SMALL_WORD)  # one road, lstring's

__all__ = [
    "DEFAULT_MODULE_LIMIT",
    "MAX_STEPS",
    "Derivation",
    "check_steps",
    "derive",
    "iterate",
]

_MASK = (1 << 64) - 1


def _splitmix(z: int) -> int:
    z = (z + 0x9E3779B97F4A7C15) & _MASK
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & _MASK
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & _MASK
    return z ^ (z >> 31)


def step_key(seed: int, step: int, render: bool = False) -> np.uint64:
    """The 64-bit key of the random numbers of one step (a hash of seed and step)."""
    return np.uint64(_splitmix((seed & _MASK) ^ _splitmix(step * 2 + (1 if render else 0))))


# ----------------------------------------------------------------------------- compiled rules
@dataclass
class _CRule:
    index: int
    rule: Rule
    pred: int
    pred_arity: int
    left: np.ndarray
    left_arity: np.ndarray
    right: np.ndarray
    right_arity: np.ndarray
    right_match: np.ndarray
    bindings: list[tuple[str, str, int, int]]  # name, where, pattern index, parameter
    cond: Callable | None
    weight: Callable
    weight_const: float | None
    succ_ids: np.ndarray
    succ_nparams: np.ndarray
    args: list[Callable]
    walk_right: bool = False  # cpfg's literal walk (:mod:`._walk`), not the tree pattern

    @property
    def needs_env(self) -> bool:
        return bool(self.bindings)


class _RuleSet:
    """The rules of one kind (productions or render rules) compiled for an alphabet."""

    def __init__(self, rules: Sequence[Rule], alphabet: Alphabet, constants, *,
                 cpfg: bool = False, ring: bool = False, live: frozenset = frozenset(),
                 live_get: Callable | None = None, first: bool = False,
                 exact: bool = False) -> None:  # fmt: skip
        self.alphabet, self.exact = alphabet, exact  # exact: cpfg's parameter counts, _arity
        self.ring, self.skip = ring, (alphabet.id("=") if cpfg else -1)  # cpfg's ring and =
        # globals blocks assign, read per application (live_get()): module by module
        self.live = tuple(sorted(live)) if any(r.block is not None for r in rules) else ()
        self.live_get = live_get
        self.rules: list[_CRule] = [
            self._compile(i, r, alphabet, constants, self.skip, self.live)
            for i, r in enumerate(rules)
        ]
        # cpfg without seed: the first applicable production in file order, no tiers nor draw
        self.first = first and len({cr.pred for cr in self.rules}) < len(self.rules)
        by: dict[int, list[list[_CRule]]] = {}
        for cr in self.rules:
            by.setdefault(cr.pred, [[], [], []])[0 if self.first else cr.rule.tier].append(cr)
        self.by_symbol = by
        # flattened successor tables for the assembly kernel
        lens = [len(cr.succ_ids) for cr in self.rules]
        self.rule_len = np.array(lens, np.int64)
        self.rule_ids_start = np.zeros(len(lens), np.int64)
        if lens:
            self.rule_ids_start[1:] = np.cumsum(lens)[:-1]
        self.rule_ids = (
            np.concatenate([cr.succ_ids for cr in self.rules]).astype(ID_DTYPE)
            if self.rules
            else np.zeros(0, ID_DTYPE)
        )
        self.rule_nparams = (
            np.concatenate([cr.succ_nparams for cr in self.rules]).astype(np.int64)
            if self.rules
            else np.zeros(0, np.int64)
        )
        self.rule_nvals = np.array([int(cr.succ_nparams.sum()) for cr in self.rules], np.int64)
        self._build_fast_table()
        self._build_context_table()
        self.fast, self.ctx_fast = self.fast and not self.first, self.ctx_fast and not self.first

    @staticmethod
    def _compile(index: int, rule: Rule, alphabet: Alphabet, constants, skip: int = -1,
                 live: tuple = ()) -> _CRule:  # fmt: skip
        pred = rule.predecessor
        if pred.symbol in ("[", "]"):
            raise _rule_error(rule, f"a bracket {pred.symbol!r} cannot be rewritten")
        for p in rule.left:
            if p.symbol in ("[", "]"):
                raise _rule_error(rule, "a left context cannot contain brackets")
        bindings: list[tuple[str, str, int, int]] = []
        for j, p in enumerate(rule.left):
            bindings += [(name, "left", j, k) for k, name in enumerate(p.params)]
        bindings += [(name, "pred", 0, k) for k, name in enumerate(pred.params)]
        for j, p in enumerate(rule.right):
            bindings += [(name, "right", j, k) for k, name in enumerate(p.params)]
        names = tuple(dict.fromkeys([b[0] for b in bindings] + list(live)))
        block = rule.block  # cpfg's statement blocks: what they assign is bound too
        if block is not None:
            names = tuple(dict.fromkeys(names + block.outputs))
        right_ids = np.array([alphabet.id(p.symbol) for p in rule.right], ID_DTYPE)
        walk = _walk.needs_walk(right_ids, skip)

        def comp(e):
            try:
                return compile_expr(e, bound=names, constants=constants)
            except LSystemSemanticError as exc:
                if exc.line is None and rule.span is not None:
                    raise _rule_error(rule, exc.message) from None
                raise

        cond = comp(rule.condition) if rule.condition is not None else None
        if block is not None:  # the blocks run around the condition, over its arrays
            cond = block.wrap(cond, constants)
        weight = comp(rule.weight)
        wc = getattr(weight, "constant", None)
        if wc is not None and not np.isfinite(wc):
            raise _rule_error(rule, f"the weight is {wc}; expected a finite number")
        args: list[Callable] = []
        for m in rule.successor:
            args += [comp(a) for a in m.args]
        return _CRule(
            index=index,
            rule=rule,
            pred=alphabet.id(pred.symbol),
            pred_arity=len(pred.params),
            left=np.array([alphabet.id(p.symbol) for p in rule.left], ID_DTYPE),
            left_arity=np.array([len(p.params) for p in rule.left], np.int64),
            right=right_ids,
            right_match=pattern_match(right_ids) if not walk else np.zeros(0, np.int64),
            right_arity=np.array([len(p.params) for p in rule.right], np.int64),
            bindings=bindings,
            cond=cond,
            weight=weight,
            weight_const=wc,
            succ_ids=np.array([alphabet.id(m.symbol) for m in rule.successor], ID_DTYPE),
            succ_nparams=np.array([len(m.args) for m in rule.successor], np.int64),
            args=args,
            walk_right=walk,
        )

    def _build_context_table(self) -> None:
        """Flat tables for the compiled road of parameter-free systems with contexts."""
        self.ctx_fast = not self.fast and not self.ring and all(
            not cr.walk_right
            and cr.cond is None
            and cr.pred_arity == 0
            and not cr.left_arity.any()
            and not cr.right_arity.any()
            and cr.weight_const is not None
            and not cr.succ_nparams.any()
            for cr in self.rules
        )
        if not self.ctx_fast:
            return
        order = sorted(
            (cr for cr in self.rules if cr.weight_const > 0),
            key=lambda cr: (int(cr.pred), cr.rule.tier, cr.index),
        )
        size = len(self.alphabet)
        self.c_sym_start = np.zeros(size, np.int64)
        self.c_sym_count = np.zeros(size, np.int64)
        for q, cr in enumerate(order):
            if self.c_sym_count[cr.pred] == 0:
                self.c_sym_start[cr.pred] = q
            self.c_sym_count[cr.pred] += 1
        pats: list[int] = []
        lstart, llen, rstart, rlen = [], [], [], []
        for cr in order:
            lstart.append(len(pats))
            llen.append(len(cr.left))
            pats += cr.left.tolist()
            rstart.append(len(pats))
            rlen.append(len(cr.right))
            pats += cr.right.tolist()
        self.c_tier = np.array([cr.rule.tier for cr in order], np.int64)
        self.c_weight = np.array([cr.weight_const for cr in order], np.float64)
        self.c_lstart = np.array(lstart, np.int64)
        self.c_llen = np.array(llen, np.int64)
        self.c_rstart = np.array(rstart, np.int64)
        self.c_rlen = np.array(rlen, np.int64)
        self.c_pats = np.array(pats, ID_DTYPE)
        self.c_len = np.array([len(cr.succ_ids) for cr in order], np.int64)
        self.c_ids_start = self.rule_ids_start[[cr.index for cr in order]] if order else (
            np.zeros(0, np.int64)
        )

    def _build_fast_table(self) -> None:
        """A successor table when every rule is context-free, unconditional, parameter-free."""
        self.fast = all(
            cr.cond is None
            and not cr.rule.has_context
            and cr.pred_arity == 0
            and cr.weight_const is not None
            and not cr.succ_nparams.any()
            for cr in self.rules
        )
        if not self.fast:
            return
        size = len(self.alphabet)
        self.nalt = np.zeros(size, np.int64)
        self.alt_start = np.zeros(size, np.int64)
        order: list[_CRule] = []
        cum: list[float] = []
        for sym, tiers in sorted(self.by_symbol.items()):
            alts = [cr for cr in tiers[2] if cr.weight_const > 0]
            self.alt_start[sym] = len(order)
            self.nalt[sym] = len(alts)
            total = 0.0
            for cr in alts:
                total += cr.weight_const
                cum.append(total)
                order.append(cr)
            if not alts and tiers[2]:
                # every rule has weight 0: the identity applies
                self.nalt[sym] = 0
        self.alt_rule = np.array([cr.index for cr in order], np.int64)
        self.cum_w = np.array(cum, np.float64)
        self.alt_succ_start = self.rule_ids_start[self.alt_rule] if order else np.zeros(0, np.int64)
        self.alt_succ_len = self.rule_len[self.alt_rule] if order else np.zeros(0, np.int64)
        self.max_len = int(self.alt_succ_len.max()) if order else 1

    def grow(self) -> None:
        """Re-size per-symbol tables after the alphabet grew (ids are append-only)."""
        size = len(self.alphabet)
        if self.fast and self.nalt.shape[0] < size:
            extra = size - self.nalt.shape[0]
            self.nalt = np.concatenate([self.nalt, np.zeros(extra, np.int64)])
            self.alt_start = np.concatenate([self.alt_start, np.zeros(extra, np.int64)])
        if self.ctx_fast and self.c_sym_count.shape[0] < size:
            extra = size - self.c_sym_count.shape[0]
            self.c_sym_count = np.concatenate([self.c_sym_count, np.zeros(extra, np.int64)])
            self.c_sym_start = np.concatenate([self.c_sym_start, np.zeros(extra, np.int64)])


def _rule_error(rule: Rule, message: str) -> LSystemSemanticError:
    span = rule.span
    if span is None:
        return LSystemSemanticError(message)
    source = None
    if span.filename and os.path.isfile(span.filename):
        try:
            with open(span.filename, encoding="utf-8", errors="replace") as f:
                lines = f.read().splitlines()
            source = lines[span.line - 1] if 0 < span.line <= len(lines) else None
        except OSError:
            source = None
    return LSystemSemanticError(
        message, filename=span.filename, line=span.line, column=span.column, source_line=source
    )


# ----------------------------------------------------------------------------- the step
class _Compiled:
    """A program compiled once: alphabet, axiom word, rule sets, ignore table."""

    def __init__(self, program: Program) -> None:
        self.program = program
        alphabet = Alphabet()
        constants = dict(program.constants)
        # axiom (parameters are expressions over the constants)
        index: dict[str, int] = {}
        for m in program.axiom:
            if m.symbol not in index:
                index[m.symbol] = alphabet.id(m.symbol)
        ids = [index[m.symbol] for m in program.axiom]
        counts = [len(m.args) for m in program.axiom]
        values: list[float] = []
        for m in program.axiom:
            for a in m.args:
                values.append(float(compile_expr(a, constants=constants)({}, 1)[0]))
        self.dtype = np.float32 if program.dialect == "cpfg" else np.float64  # cpfg's C floats
        if values:
            offsets = np.zeros(len(ids) + 1, np.int64)
            np.cumsum(counts, out=offsets[1:])
            self.axiom = ModuleString(alphabet, np.array(ids, ID_DTYPE), offsets,
                                      np.array(values, self.dtype).astype(np.float64))
        else:
            self.axiom = ModuleString(alphabet, np.array(ids, ID_DTYPE))
        self.axiom.check_brackets(program.filename)
        self.alphabet = alphabet
        self._constants = constants
        self._groups: dict[int, _RuleSet] = {}
        stm = program.statements
        self._kind = {"cpfg": program.dialect == "cpfg", "ring": bool(program.ring),
                      "first": bool(program.settings.get("first_match")),
                      "exact": bool(program.settings.get("exact_arity")),
                      "live": frozenset(getattr(stm, "written", ()) or ()),
                      "live_get": getattr(stm, "live_values", None)}  # fmt: skip
        self.productions = self.group_rules(0)
        self.sublsystems = any(r.lsystem for r in program.rules)  # cpfg's ?(n) … $, all phases
        self.render = _RuleSet(program.render_rules, alphabet, constants, **self._kind)
        self.decomposition = _RuleSet(program.decompositions, alphabet, constants, **self._kind)
        self.interpretation = _RuleSet(program.interpretations, alphabet, constants,
                                       **self._kind)  # fmt: skip
        self.group_fn = None
        if program.group is not None:
            try:
                self.group_fn = compile_expr(program.group, bound=("step",), constants=constants)
            except LSystemSemanticError as exc:
                raise LSystemSemanticError(
                    f"the group expression: {exc.message}", filename=program.filename
                ) from None
        ign = [alphabet.id(s) for s in program.ignore]
        cons = None
        if program.consider is not None:
            cons = [alphabet.id(s) for s in program.consider]
        self._ign = ign
        self._cons = cons
        self.ignored = ignored_table(len(alphabet), ign, cons)
        self.sub_ctx = _sub.ContextTables.of(program, alphabet)  # their own ignore: tables

    def group_rules(self, group: int) -> _RuleSet:
        """The productions of ``group`` and of group 0 (those outside any group)."""
        rs = self._groups.get(group)
        if rs is None:
            prods = self.program.productions
            mine = [i for i, r in enumerate(prods) if r.group in (0, group)]
            rs = _RuleSet([prods[i] for i in mine], self.alphabet, self._constants,
                          **self._kind)  # fmt: skip
            rs.origin = np.array(mine, np.int64)  # index in program.productions
            self._groups[group] = rs
        return rs

    def rules_for(self, step: int) -> _RuleSet:
        """The productions of step ``step`` (0 for the first): the group ``Program.group``
        chooses, with group 0."""
        if self.group_fn is None:
            return self.productions
        v = float(np.asarray(self.group_fn({"step": np.array([float(step)])}, 1)).ravel()[0])
        if not (np.isfinite(v) and v == int(v)):
            raise LSystemSemanticError(
                f"step {step + 1}: the group expression gave {v:g}; expected a whole number "
                "(the group of productions to use)",
                filename=self.program.filename,
            )
        return self.group_rules(int(v))

    def ignored_for(self, word: ModuleString) -> np.ndarray:
        if self.ignored.shape[0] < len(word.alphabet):
            self.ignored = ignored_table(len(word.alphabet), self._ign, self._cons)
        return self.ignored


def _with_constants(comp: _Compiled, constants: Mapping[str, float]) -> _Compiled:
    """``comp`` with its rules compiled again over other values of the globals (the same
    alphabet, so the word needs no re-coding)."""
    new = copy.copy(comp)
    new._constants = {**comp._constants, **constants}
    new._groups = {}
    new.productions = new.group_rules(0)
    program = comp.program
    new.decomposition = _RuleSet(program.decompositions, comp.alphabet, new._constants,
                                 **comp._kind)  # fmt: skip
    new.render = _RuleSet(program.render_rules, comp.alphabet, new._constants, **comp._kind)
    new.interpretation = _RuleSet(program.interpretations, comp.alphabet, new._constants,
                                  **comp._kind)  # fmt: skip
    return new


def _compiled(program: Program) -> _Compiled:
    """The compiled form of ``program``, made once and kept on the (frozen) program."""
    comp = program.__dict__.get("_sylva_compiled")
    if comp is None:
        comp = _Compiled(program)
        object.__setattr__(program, "_sylva_compiled", comp)
    return comp


def _step_fast(word: ModuleString, rs: _RuleSet, key: np.uint64, limit: int, step: int):
    rs.grow()
    n = len(word)
    if n * rs.max_len > limit:
        total = _kernels.count_table(
            word.ids, key, True, rs.nalt, rs.alt_start, rs.cum_w, rs.alt_succ_len
        )
        _check_limit(int(total), fast_step_bytes(n, int(total)), limit, word, step)
    elif n * rs.max_len > 10_000_000:  # memory only, for the longest outcome
        _check_limit(0, fast_step_bytes(n, n * rs.max_len), limit, word, step)
    ids = _kernels.rewrite_table(
        word.ids,
        key,
        True,
        rs.nalt,
        rs.alt_start,
        rs.cum_w,
        rs.alt_succ_start,
        rs.alt_succ_len,
        rs.rule_ids,
    )
    return ModuleString(word.alphabet, ids)


def _expand_d0l(
    word: ModuleString, rs: _RuleSet, steps: int, limit: int, step0: int = 0
) -> ModuleString:
    """``steps`` deterministic context-free steps at once, by expansion of whole blocks.

    The word after ``k`` steps of a symbol is the concatenation of the ``k - 1``-step words
    of its successor's symbols (seed 000's recursive generator, memoised per symbol and
    level), so the final word is assembled from a few large block copies instead of symbol
    by symbol.  Lengths are computed exactly first, so the limit is checked before any
    memory is used.
    """
    rs.grow()
    succ = {
        int(s): rs.rule_ids[rs.alt_succ_start[rs.alt_start[s]] :][
            : rs.alt_succ_len[rs.alt_start[s]]
        ]
        for s in np.flatnonzero(rs.nalt)
    }
    present = np.flatnonzero(np.bincount(word.ids, minlength=len(word.alphabet)))
    # symbols reachable from the word
    reach = set(int(s) for s in present)
    todo = list(reach)
    while todo:
        s = todo.pop()
        for t in succ.get(s, ()):
            t = int(t)
            if t not in reach:
                reach.add(t)
                todo.append(t)
    counts = np.bincount(word.ids, minlength=len(word.alphabet))
    length = {s: 1 for s in reach}
    before = len(word)
    for k in range(steps):
        new_len = {
            s: (sum(length[int(t)] for t in succ[s]) if s in succ else 1) for s in reach
        }
        total = sum(int(counts[s]) * new_len[s] for s in reach)
        if total > limit or total > 2_000_000:
            try:
                need = block_step_bytes(total, sum(new_len.values()), sum(length.values()))
                _check_limit(total, need, limit, word, step0 + k)
            except GrowthLimitError as exc:
                exc.step = k  # steps that still fit
                exc.args = (str(exc).replace(f"from {len(word):,}", f"from {before:,}"),)
                raise
        before = total
        length = new_len
    single = {s: np.array([s], ID_DTYPE) for s in reach}
    empty = np.zeros(0, ID_DTYPE)

    def grow(s: int, exp: dict[int, np.ndarray]) -> np.ndarray:
        if s not in succ:
            return single[s]
        parts = [exp[int(t)] for t in succ[s]]
        return np.concatenate(parts) if parts else empty

    exp = dict(single)
    for _ in range(steps):
        exp = {s: grow(s, exp) for s in reach}
    ids = word.ids.tolist()
    if len(ids) == 1:
        out = exp[ids[0]].copy()
    else:
        out = np.concatenate([exp[s] for s in ids])
    return ModuleString(word.alphabet, out)


def _env(word: ModuleString, cr: _CRule, cand, lpos, rpos, sel, rs=None) -> dict:
    env: dict[str, np.ndarray] = {}
    if rs is not None and rs.live:  # the globals blocks assign, as they are now
        now = rs.live_get()
        env.update({k: np.full(sel.size, float(now.get(k, 0.0))) for k in rs.live})
    off = word.offsets
    vals = word.values
    for name, where, j, k in cr.bindings:
        if where == "pred":
            p = cand[sel]
        elif where == "left":
            p = lpos[sel, j]
        else:
            p = rpos[sel, j]
        env[name] = vals[off[p] + k]
    return env


def _step_general(
    word: ModuleString,
    rs: _RuleSet,
    comp: _Compiled,
    key: np.uint64,
    limit: int,
    step: int,
    choices: list | None = None,
    keys: np.ndarray | None = None,
    scope: np.ndarray | None = None,
) -> ModuleString:
    """The general road; when ``choices`` is a list, the rule chosen per module is appended.

    ``keys`` (``uint64[n]``, lineage keys) replace the positions in the random draws;
    ``scope`` (``int64[n]``) is each module's sub-L-system, which a rule's must match."""
    n = len(word)
    ids = word.ids
    made = (word._match is None, word._offsets is None)  # what matching will make, and keep
    choice = np.full(n, -1, np.int64)
    if choices is not None:
        choices.append(choice)
    pending: list[tuple[_CRule, np.ndarray, dict[str, np.ndarray]]] = []
    ignored = comp.ignored_for(word) if any(cr.rule.has_context for cr in rs.rules) else None
    nparams = word.nparams if word.has_params else None
    order = ([(s, np.array([p])) for p, s in enumerate(ids.tolist()) if s in rs.by_symbol]
             if rs.live else ((s, np.flatnonzero(ids == s)) for s in rs.by_symbol))  # fmt: skip
    for sym, undecided in order:
        tiers = rs.by_symbol[sym]
        if undecided.size == 0:
            continue
        for tier in tiers:
            if not tier or undecided.size == 0:
                continue
            k = undecided.size
            weights = np.zeros((k, len(tier)), np.float64) if len(tier) > 1 else None
            staged = []
            for r, cr in enumerate(tier):
                ok = _arity.pred_ok(nparams, undecided, cr.pred_arity, rs.exact)
                if scope is not None:
                    ok &= scope[undecided] == cr.rule.lsystem
                ign = ignored if comp.sub_ctx is None else comp.sub_ctx.get(word, cr, ignored)
                lpos, rpos = _walk.contexts(word, cr, undecided, ign, ok, _kernels,
                                            rs.ring, rs.skip, rs.exact)  # fmt: skip
                sel = np.flatnonzero(ok)
                if sel.size == 0:
                    continue
                env = (_env(word, cr, undecided, lpos, rpos, sel, rs)
                       if cr.needs_env or rs.live else {})  # fmt: skip
                if cr.cond is not None:
                    c = truth(cr.cond(env, sel.size))
                    if not c.all():
                        sel = sel[c]
                        env = {name: v[c] for name, v in env.items()}
                    if sel.size == 0:
                        continue
                w = (
                    np.full(sel.size, cr.weight_const)
                    if cr.weight_const is not None
                    else cr.weight(env, sel.size)
                )
                if not np.isfinite(w).all():
                    raise _rule_error(cr.rule, f"step {step + 1}: the weight is "
                                      f"{w[~np.isfinite(w)][0]}; expected a finite number")
                positive = w > 0  # a weight <= 0: the rule does not apply there
                if not positive.all():
                    sel = sel[positive]
                    w = w[positive]
                    env = {name: v[positive] for name, v in env.items()}
                if weights is not None:
                    weights[sel, r] = w
                staged.append((r, cr, sel, env))
            if not staged:
                continue
            if len(staged) == 1:
                # one applicable rule in this tier: no draw
                r, cr, sel, env = staged[0]
                pos = undecided[sel]
                choice[pos] = cr.index
                if cr.args:
                    pending.append((cr, pos, env))
                if sel.size == k:
                    undecided = undecided[:0]
                else:
                    rest = np.ones(k, np.bool_)
                    rest[sel] = False
                    undecided = undecided[rest]
                continue
            applicable = (weights > 0).any(axis=1)
            rows = np.flatnonzero(applicable)
            cum = np.cumsum(weights[rows], axis=1)
            at = undecided[rows] if keys is None else keys[undecided[rows]]
            u = _kernels.uniform(key, at) * cum[:, -1]
            pick = np.minimum((cum <= u[:, None]).sum(axis=1), len(tier) - 1)
            if rs.first:
                pick = np.argmax(weights[rows] > 0, axis=1)
            chosen_r = np.full(k, -1, np.int64)
            chosen_r[rows] = pick
            for r, cr, sel, env in staged:
                mine = chosen_r[sel] == r
                if not mine.any():
                    continue
                pos = undecided[sel[mine]]
                choice[pos] = cr.index
                if cr.args:
                    env2 = {name: v[mine] for name, v in env.items()} if env else env
                    pending.append((cr, pos, env2))
            undecided = undecided[~applicable]
    # sizes and the growth limit
    chosen = choice >= 0
    if chosen.any():
        n_out = int(n - np.count_nonzero(chosen) + rs.rule_len[choice[chosen]].sum())
        n_vals = int(word.values.shape[0] + rs.rule_nvals[choice[chosen]].sum())
    else:
        n_out, n_vals = n, int(word.values.shape[0])
    if n_out > 1_000_000 or n_out > limit:
        counts = np.bincount(ids, minlength=len(word.alphabet))
        need = general_step_bytes(word, rs, counts, n_out, n_vals, made=made)
        _check_limit(n_out, need, limit, word, step)
    if not word.has_params and not pending and not rs.rule_nvals.any():
        new_ids = _kernels.assemble_ids(ids, choice, rs.rule_len, rs.rule_ids_start, rs.rule_ids)
        return ModuleString(word.alphabet, new_ids)
    new_ids, new_off, new_vals, _, val_start = _kernels.assemble(
        ids,
        word.offsets,
        word.values,
        choice,
        rs.rule_len,
        rs.rule_nvals,
        rs.rule_ids_start,
        rs.rule_ids,
        rs.rule_nparams,
    )
    for cr, pos, env in pending:
        base = val_start[pos]
        m = pos.size
        for q, f in enumerate(cr.args):
            v = f(env, m)
            if not np.isfinite(v).all():
                bad = v[~np.isfinite(v)][0]
                raise _rule_error(
                    cr.rule,
                    f"step {step + 1}: this rule computed a non-finite parameter ({bad}); "
                    "expected finite numbers: check divisions and powers",
                )
            new_vals[base + q] = v
    if not new_vals.size:
        return ModuleString(word.alphabet, new_ids)
    new_vals = new_vals.astype(comp.dtype, copy=False).astype(np.float64, copy=False)
    return ModuleString(word.alphabet, new_ids, new_off, new_vals)


def _step_context(word, rs, comp, key, limit, step) -> ModuleString:
    rs.grow()
    n = len(word)
    if n * max(1, int(rs.c_len.max(initial=1))) > min(limit, 2_000_000):
        # an exact count needs the choices: take the general road, which checks first
        return _step_general(word, rs, comp, key, limit, step)
    ids = _kernels.rewrite_context(
        word.ids, word.match, comp.ignored_for(word), key, rs.c_sym_start, rs.c_sym_count,
        rs.c_tier, rs.c_weight, rs.c_lstart, rs.c_llen, rs.c_rstart, rs.c_rlen, rs.c_pats,
        rs.c_len, rs.c_ids_start, rs.rule_ids,
    )
    return ModuleString(word.alphabet, ids)


def _step(word, rs, comp, key, limit, step, scope=None):
    if not rs.rules:
        return word
    if scope is not None:
        out = _step_general(word, rs, comp, key, limit, step, scope=scope)
    elif rs.fast and not word.has_params:
        out = _step_fast(word, rs, key, limit, step)
    elif rs.ctx_fast and not word.has_params:
        out = _step_context(word, rs, comp, key, limit, step)
    else:
        out = _step_general(word, rs, comp, key, limit, step)
    cut = out.alphabet.get("%")
    if cut >= 0:
        out = _apply_cut(out, cut)
    return out


# ----------------------------------------------------------------------------- public API
def _resolve_seed(seed: int | None, program: Program) -> int:
    if seed is None:
        seed = program.seed
    if seed is None:
        seed = int(np.random.SeedSequence().entropy) & _MASK
    return int(seed) & _MASK


def _pass_key(seed: int, step: int, phase: str, depth: int) -> np.uint64:
    """The key of one decomposition or interpretation pass (apart from every step's)."""
    base = int(step_key(seed, step, phase == "interpretation"))
    return np.uint64(_splitmix(base ^ _splitmix(0x5EED0000 + 2 * depth + 1)))


def _passes(word, rs, comp, seed, step, depth, phase, limit, track=False):
    """``rs`` applied again and again until no rule applies, at most ``depth`` times.

    Returns the word and, when ``track``, the index of the module each new module came
    from (``int64[n]``; ``None`` otherwise).  A rule that still applies after ``depth``
    passes raises :class:`~sylva.errors.LSystemSemanticError` naming the module, the step
    and the rule.
    """
    src = np.arange(len(word), dtype=np.int64) if track else None
    if not rs.rules:
        return word, src
    for d in range(depth + 1):
        rs.grow()
        got: list[np.ndarray] = []
        new = _step_general(word, rs, comp, _pass_key(seed, step, phase, d), limit, step, got,
                            scope=_sub.scope_if(word, comp.sublsystems))  # fmt: skip
        choice = got[0]
        applied = np.flatnonzero(choice >= 0)
        if applied.size == 0:
            return word, src
        if d == depth:
            k = int(applied[0])
            name = word.alphabet.names[int(word.ids[k])]
            where = f"after step {step}" if step else "of the axiom"
            raise _rule_error(
                rs.rules[int(choice[k])].rule,
                f"the {phase} {where} goes deeper than its maximum depth {depth}: module {k} "
                f"({name!r}) is still rewritten; expected rules that end within the depth "
                f"(or a larger 'maximum depth')",
            )
        if track:
            src = np.repeat(src, np.where(choice < 0, 1, rs.rule_len[np.maximum(choice, 0)]))
        keep = _cut_keep(new)
        if keep is not None:
            new = _apply_cut(new, -1, keep)
            if track:
                src = src[keep]
        word = new
    return word, src  # pragma: no cover - the loop returns or raises


def _traced_step(word, rs, comp, key, limit, step, keys=None, scope=None):
    """A general-road step that also says where every new module came from.

    Returns the new word, the index of the old module each new module replaced
    (``int64[n_new]``) and the rule that made it (``int64[n_new]``, -1 for a copy); with
    lineage ``keys`` (``uint64[n]``) the draws use them, and the new modules' keys come
    fourth (a copy keeps its key).
    """
    if not rs.rules:
        idx = np.arange(len(word), dtype=np.int64)
        return word, idx, np.full(len(word), -1, np.int64), keys
    rs.grow()
    got: list[np.ndarray] = []
    new = _step_general(word, rs, comp, key, limit, step, choices=got, keys=keys, scope=scope)
    choice = got[0]
    lens = np.where(choice < 0, 1, rs.rule_len[np.maximum(choice, 0)])
    src = np.repeat(np.arange(len(word), dtype=np.int64), lens)
    rule = choice[src]
    new_keys = None
    if keys is not None:
        new_keys = np.where(rule >= 0, lineage_keys(keys[src], child_index(src)), keys[src])
    keep = _cut_keep(new)
    if keep is not None:
        new = _apply_cut(new, -1, keep)
        src, rule = src[keep], rule[keep]
        if new_keys is not None:
            new_keys = new_keys[keep]
    return new, src, rule, new_keys


class Derivation:
    """A derivation in progress: the current word, its step number, stepping and render words.

    Parameters
    ----------
    program : Program
    seed : int, optional
        The seed of the random choices; defaults to the program's ``seed`` or, when it has
        none, a fresh one (kept in :attr:`seed` so the run can be repeated).
    limit : int
        The module limit; a step that would pass it raises
        :class:`~sylva.errors.GrowthLimitError` and keeps the current word.
    trace : bool
        Remember, for every module, the rule and the step that made it (:meth:`origin`),
        for debuggers such as the studio.  Tracing takes the general road.
    lineage : bool
        Key the random choices by ancestry instead of position: every module carries a key,
        a hash of its parent's key and its index in the parent's successor (the axiom's
        modules: of the seed and their index), and a stochastic rule is drawn from the key
        and the step.  Editing the rules of one branch then leaves every other branch as it
        was.  The same seed gives the same word on every machine; takes the general road.
    query : callable, optional
        ``query(word, index) -> float64[m, 3]``: the new values of the word's query modules
        (``?P ?H ?U ?L``, at positions ``index``), called on the axiom and after every step
        (see :mod:`sylva.lsystem.environment`).  A program with query modules needs one:
        :func:`sylva.derive` and :func:`sylva.grow` pass the turtle's.
    environment, locate : callable, optional
        An open L-system's environment, ``environment(communication) -> float64[m, k]``,
        sets the ``?E`` modules' parameters on the axiom and after every step (after the
        queries); ``locate(word, index)`` gives it the turtle's state there
        (:mod:`sylva.lsystem.environment`; :func:`sylva.grow` passes the program's).

    Attributes
    ----------
    on_rewrite : callable or None
        A debugger's hook (the studio's breakpoints and profile): with ``trace=True``,
        ``on_rewrite(step, src, rule)`` is called after each step with, per module of the
        new word, the index of the old module it replaced and the production that made it
        (-1: copied).  ``None`` (the default) costs nothing; the other roads never call it.

    Examples
    --------
    >>> from sylva.lsystem.ast import Module, Pattern, Program, Rule
    >>> p = Program(axiom=(Module("a"),), rules=(Rule(Pattern("a"), (Module("b"),)),
    ...                                        Rule(Pattern("b"), (Module("a"), Module("a")))))
    >>> d = Derivation(p)
    >>> str(d.advance(4)), d.step
    ('aaaa', 4)
    >>> str(d.back()), d.step
    ('bb', 3)
    """

    def __init__(
        self,
        program: Program,
        *,
        seed: int | None = None,
        limit: int = DEFAULT_MODULE_LIMIT,
        trace: bool = False,
        lineage: bool = False,
        query: Query | None = None,
        environment: _open.Environment | None = None,
        locate: _open.Locate | None = None,
    ) -> None:
        if query is None and has_queries(program):
            raise missing_query(program)
        if environment is None and _open.has_communication(program):
            raise _open.missing_environment(program)
        self.query = query
        self.environment = environment
        self.locate = locate
        self.program = program
        self.seed = _resolve_seed(seed, program)
        self.limit = int(limit)
        self.trace = bool(trace)
        self.lineage = bool(lineage)
        self._compiled = _compiled(program)
        self._history: list = []
        self._globals = None  # of program.statements, between steps
        # a debugger's hook (the studio's breakpoints and profile), on the traced road only:
        # on_rewrite(step, src, rule) after each step, with per new module the index of the
        # old module it replaced and the production that made it (-1: copied)
        self.on_rewrite: Callable[[int, np.ndarray, np.ndarray], None] | None = None
        self.reset()

    def _axiom(self) -> ModuleString:
        """The axiom, decomposed (cpfg's as written, control.c), and its lineage keys."""
        comp = self._compiled
        depth = self.program.decomposition_depth
        word, src = comp.axiom, None
        if self.program.dialect != "cpfg":
            word, src = _passes(comp.axiom, comp.decomposition, comp, self.seed, 0, depth,
                                "decomposition", self.limit, track=self.lineage)  # fmt: skip
        if self.lineage:
            keys = axiom_keys(self.seed, len(comp.axiom))
            self._keys = keys if word is comp.axiom else decomposed_keys(keys, src)
        return word

    @property
    def keys(self) -> np.ndarray:
        """``uint64[n]``: the lineage key of every module (needs ``lineage=True``)."""
        if not self.lineage:
            raise ValueError("keys needs a Derivation made with lineage=True")
        return self._keys

    def origin(self, index: int) -> tuple[Rule | None, int]:
        """The production that made module ``index`` of the current word, and its step.

        ``(None, 0)`` for a module that has been there since the axiom.  Needs
        ``trace=True``.
        """
        if not self.trace:
            raise ValueError("origin() needs a Derivation made with trace=True")
        r = int(self._origin_rule[index])
        rule = self.program.productions[r] if r >= 0 else None
        return rule, int(self._origin_step[index])

    @property
    def origin_rules(self) -> np.ndarray:
        """``int64[n]``: per module, the index in ``program.productions`` of the rule that
        made it (-1 for the axiom's modules); needs ``trace=True``."""
        if not self.trace:
            raise ValueError("origin_rules needs a Derivation made with trace=True")
        return self._origin_rule

    @property
    def origin_steps(self) -> np.ndarray:
        """``int64[n]``: per module, the step in which it was made; needs ``trace=True``."""
        if not self.trace:
            raise ValueError("origin_steps needs a Derivation made with trace=True")
        return self._origin_step

    @property
    def alphabet(self) -> Alphabet:
        return self._compiled.alphabet

    def reset(self) -> ModuleString:
        """Back to the axiom."""
        self._keys = None
        if self.program.statements is not None:
            self._globals = self.program.statements.fresh()
        self.word = self._axiom()
        if self.query is not None:
            self.word = apply_query(self.word, self.query, 0)
        if self.environment is not None:
            self.word = _open.apply_environment(self.word, self.environment, 0, self.locate)
        self.step = 0
        self._history.clear()
        self._origin_rule = self._origin_step = None
        if self.trace:
            self._origin_rule = np.full(len(self.word), -1, np.int64)
            self._origin_step = np.zeros(len(self.word), np.int64)
        return self.word

    @property
    def is_d0l(self) -> bool:
        """True when the remaining steps are deterministic, context-free and parameter-free,
        so that :meth:`advance` jumps several steps at once by block expansion."""
        comp = self._compiled
        rs = comp.productions
        rs.grow()
        return bool(
            not self.trace
            and not self.lineage
            and self.query is None
            and self.environment is None
            and self.program.statements is None
            and comp.group_fn is None
            and not comp.sublsystems
            and not comp.decomposition.rules
            and rs.rules
            and rs.fast
            and not self.word.has_params
            and len(self.word) < 100_000
            and (rs.nalt <= 1).all()
            and "%" not in self.alphabet
        )

    def advance(self, n: int = 1) -> ModuleString:
        """Derive ``n`` more steps (at most :data:`MAX_STEPS`) and return the new word."""
        n = int(n)
        if n > MAX_STEPS:
            raise StepsError(f"{n:.3g} steps: expected at most {MAX_STEPS:,} derivation steps")
        rs = self._compiled.productions
        if n > 1 and self.is_d0l:
            # deterministic, context-free, parameter-free: expand whole blocks at once
            self._history.clear()
            try:
                self.word = _expand_d0l(self.word, rs, n, self.limit, self.step)
                self.step += n
            except GrowthLimitError as exc:
                # keep what fits: the word of the last step under the limit
                fit = int(exc.step or 0)
                if fit:
                    self.word = _expand_d0l(self.word, rs, fit, self.limit, self.step)
                    self.step += fit
                exc.word, exc.step = self.word, self.step
                raise
            return self.word
        for _ in range(n):
            self._advance_one()
        return self.word

    def _advance_one(self) -> None:
        comp = self._compiled
        stm = self.program.statements
        if stm is not None:  # statements between steps change the globals: recompile
            before = copy.deepcopy(self._globals)
            stm.before(self._globals, self.step)
            comp = _with_constants(comp, self._globals.numbers())
        key = step_key(self.seed, self.step)
        rs = comp.rules_for(self.step)
        decompose = comp.decomposition.rules
        scope = _sub.scope(self.word) if comp.sublsystems else None
        saved = (self.word, self._origin_rule, self._origin_step, self._keys,
                 before if stm is not None else None)  # fmt: skip
        if self.trace or self.lineage:
            new, src, rule, keys = _traced_step(self.word, rs, comp, key, self.limit,
                                                self.step, self._keys, scope)  # fmt: skip
            if self.trace:
                made = rule >= 0
                if made.any():  # the group's rule index in program.productions
                    rule = np.where(made, rs.origin[np.maximum(rule, 0)], -1)
                self._origin_rule = np.where(made, rule, self._origin_rule[src])
                self._origin_step = np.where(made, self.step + 1, self._origin_step[src])
                if self.on_rewrite is not None:
                    self.on_rewrite(self.step + 1, src, np.where(made, rule, -1))
            if decompose:  # decomposed modules keep the origin of the module they replace
                new, src = _passes(new, comp.decomposition, comp, self.seed, self.step + 1,
                                   self.program.decomposition_depth, "decomposition",
                                   self.limit, track=True)  # fmt: skip
                if self.trace:
                    self._origin_rule = self._origin_rule[src]
                    self._origin_step = self._origin_step[src]
                if keys is not None:
                    keys = decomposed_keys(keys, src)
            self._keys = keys
        else:
            new = _step(self.word, rs, comp, key, self.limit, self.step, scope)
            if decompose:
                new, _ = _passes(new, comp.decomposition, comp, self.seed, self.step + 1,
                                 self.program.decomposition_depth, "decomposition",
                                 self.limit)  # fmt: skip
        if self.query is not None:  # the turtle's state into the query modules
            new = apply_query(new, self.query, self.step + 1)
        if self.environment is not None:  # the environment answers the ?E modules
            new = _open.apply_environment(new, self.environment, self.step + 1, self.locate)
        if stm is not None:
            stm.after(self._globals, self.step)
        self._history.append(saved)
        if len(self._history) > 8:
            self._history.pop(0)
        self.word = new
        self.step += 1

    def back(self) -> ModuleString:
        """One step back (re-derived from the axiom when it is no longer cached)."""
        if self.step == 0:
            return self.word
        if self._history:
            self.word, self._origin_rule, self._origin_step, self._keys, g = self._history.pop()
            if g is not None:
                self._globals = g
            self.step -= 1
            return self.word
        target = self.step - 1
        self.reset()
        return self.advance(target)

    def render_word(self) -> ModuleString:
        """The word the turtle draws: render rules applied once to the current word."""
        comp = self._compiled
        if self.program.statements is not None and self._globals is not None:
            comp = _with_constants(comp, self._globals.numbers())  # the globals now
        word, _ = _passes(self.word, comp.interpretation, comp, self.seed, self.step,
                          self.program.interpretation_depth, "interpretation",
                          self.limit)  # fmt: skip
        if comp.render.rules:
            key = step_key(self.seed, self.step, render=True)
            word = _step(word, comp.render, comp, key, self.limit, self.step,
                         _sub.scope_if(word, comp.sublsystems))  # fmt: skip
        return _sub.silence(word) if comp.sublsystems else word

    def render_word_sources(self) -> tuple[ModuleString, np.ndarray]:
        """The render word and, per render-word module, the index of the word module it
        came from (``int64[n]``), so a drawn module can be traced back to the word."""
        comp = self._compiled
        word, first = _passes(self.word, comp.interpretation, comp, self.seed, self.step,
                              self.program.interpretation_depth, "interpretation",
                              self.limit, track=True)  # fmt: skip
        key = step_key(self.seed, self.step, render=True)
        word, src, _, _ = _traced_step(word, comp.render, comp, key, self.limit, self.step,
                                       scope=_sub.scope_if(word, comp.sublsystems))  # fmt: skip
        return (_sub.silence(word) if comp.sublsystems else word), first[src]

    def __iter__(self) -> Iterator[ModuleString]:
        """Yield the current word, then each following word, without end."""
        yield self.word
        while True:
            self._advance_one()
            yield self.word


def _steps(program: Program, steps: int | None) -> int:
    if steps is None:
        steps = program.steps if program.steps is not None else 0
    steps = int(steps)
    if steps < 0:
        raise ValueError("the number of steps cannot be negative")
    return steps


def derive(
    program: Program,
    steps: int | None = None,
    *,
    seed: int | None = None,
    limit: int = DEFAULT_MODULE_LIMIT,
    lineage: bool = False,
    query: Query | None = None,
    environment: _open.Environment | None = None,
    locate: _open.Locate | None = None,
) -> ModuleString:
    """The word after ``steps`` derivation steps (default: the program's own count, else 0).

    ``lineage=True`` keys the random choices by ancestry, ``query`` fills the query
    modules and ``environment`` the communication modules between steps (see
    :class:`Derivation`; :func:`sylva.derive` passes the turtle's and the program's).

    >>> from sylva.lsystem.ast import Module, Pattern, Program, Rule
    >>> koch = Program(axiom=(Module("F"),), rules=(Rule(Pattern("F"),
    ...     tuple(Module(c) for c in "F+F--F+F")),))
    >>> len(derive(koch, 3))
    148
    """
    try:
        n = check_steps(program, steps, limit=limit)
    except StepsError as exc:
        if exc.fits is None or exc.fits > _FLOOR_ITERATIONS:
            raise
        # fast growth: the steps that fit are few, so keep their word as a step-by-step
        # derivation that met the limit would
        d = Derivation(program, seed=seed, limit=limit, lineage=lineage, query=query,
                       environment=environment, locate=locate)  # fmt: skip
        with contextlib.suppress(GrowthLimitError):
            d.advance(exc.fits)
        exc.word, exc.step = d.word, d.step
        raise
    d = Derivation(program, seed=seed, limit=limit, lineage=lineage, query=query,
                   environment=environment, locate=locate)  # fmt: skip
    return d.advance(n)


def iterate(
    program: Program,
    steps: int | None = None,
    *,
    seed: int | None = None,
    limit: int = DEFAULT_MODULE_LIMIT,
    query: Query | None = None,
    environment: _open.Environment | None = None,
    locate: _open.Locate | None = None,
) -> Iterator[ModuleString]:
    """Yield the words of steps ``0 … steps`` (step 0 is the axiom)."""
    n = check_steps(program, steps, limit=limit)
    d = Derivation(program, seed=seed, limit=limit, query=query, environment=environment,
                   locate=locate)  # fmt: skip
    yield d.word
    for _ in range(n):
        yield d.advance()


_ = (OPEN, CLOSE)
