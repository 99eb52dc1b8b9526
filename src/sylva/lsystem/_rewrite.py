"""One-off rewriting with a program's rules: its render rules on a word, or one step.

Both take any word (one read from text is re-coded to the program's alphabet first); the
compiled rules and the step road are :mod:`sylva.lsystem.engine`'s.
"""

from __future__ import annotations

from ._steps import DEFAULT_MODULE_LIMIT
from ._sublsystems import scope, silence
from .ast import Program
from .engine import _compiled, _passes, _resolve_seed, _step, step_key
from .lstring import ModuleString

__all__ = ["render_word", "rewrite"]


def render_word(
    program: Program,
    word: ModuleString,
    *,
    seed: int | None = None,
    step: int = 0,
) -> ModuleString:
    """Apply the render rules (``->>``) of ``program`` once to ``word``.

    ``word`` should come from a derivation of the same program (it shares its alphabet);
    a word read from text is re-coded first.
    """
    comp = _compiled(program)
    if not comp.render.rules and not comp.interpretation.rules:
        return silence(word) if comp.sublsystems else word
    if word.alphabet is not comp.alphabet:
        word = ModuleString.from_modules(iter(word), comp.alphabet)
        comp.render.grow()
    seed = _resolve_seed(seed, program)
    word, _ = _passes(word, comp.interpretation, comp, seed, step,
                      program.interpretation_depth, "interpretation",
                      DEFAULT_MODULE_LIMIT)  # fmt: skip
    if comp.render.rules:
        key = step_key(seed, step, render=True)
        word = _step(word, comp.render, comp, key, DEFAULT_MODULE_LIMIT, step,
                     scope(word) if comp.sublsystems else None)  # fmt: skip
    return silence(word) if comp.sublsystems else word


def rewrite(
    program: Program, word: ModuleString, *, seed: int | None = None, step: int = 0
) -> ModuleString:
    """One derivation step of ``program`` applied to an arbitrary ``word``."""
    comp = _compiled(program)
    rs = comp.rules_for(step)
    if word.alphabet is not comp.alphabet:
        word = ModuleString.from_modules(iter(word), comp.alphabet)
        rs.grow()
    key = step_key(_resolve_seed(seed, program), step)
    where = scope(word) if comp.sublsystems else None
    return _step(word, rs, comp, key, DEFAULT_MODULE_LIMIT, step, where)
