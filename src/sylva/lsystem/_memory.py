"""How many bytes a derivation step allocates, for the memory guard of the engine.

The guard refuses a step that would need more than 70 % of the memory the system has free
(``MemAvailable``), so that a raised module limit ends with a message rather than with the
out-of-memory killer.  The figures below follow the arrays each road of the engine makes
(issue 23: the former flat 20 B per module + 8 B per parameter was 2-3 times too low on the
general road); ``tests/lsystem/test_memory.py`` checks them against the peak resident memory
of a child process.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy as np

from ..errors import GrowthLimitError

if TYPE_CHECKING:
    from .engine import _RuleSet
    from .lstring import ModuleString

__all__ = ["block_step_bytes", "context_step_bytes", "fast_step_bytes", "general_step_bytes"]

#: The share of the free memory one step may take.
MEMORY_SHARE = 0.7

_ID = 2  # bytes of a symbol id (uint16)
_I64 = 8


def word_bytes(n: int, n_values: int) -> int:
    """Bytes of a word: ids, and with parameters their offsets and values."""
    if n_values:
        return n * (_ID + _I64) + _I64 + n_values * 8
    return n * _ID


def fast_step_bytes(n_in: int, n_out: int) -> int:
    """The table road: the rule picked per module (int32) and the new ids."""
    return 4 * n_in + _ID * n_out


def context_step_bytes(n_in: int, n_out: int, has_match: bool) -> int:
    """The compiled context road: the choice per module, the bracket match, the new ids."""
    return _I64 * n_in * (1 if has_match else 2) + _ID * n_out


def block_step_bytes(n_out: int, last_blocks: int, previous_blocks: int) -> int:
    """Block expansion: the blocks of the last two levels and the final word."""
    return _ID * (n_out + last_blocks + previous_blocks)


def general_step_bytes(
    word: ModuleString, rs: _RuleSet, counts: np.ndarray, n_out: int, v_out: int,
    made: tuple[bool, bool] | None = None,
) -> int:
    """The general road, from the rules and the count of each symbol in the word.

    Per module: the choice (int64), the parameter counts and bracket match when used, the
    masks and gathers of the size check; per instance of each rule's predecessor: the
    candidate indices, masks, context positions, the bound parameters, the condition and
    weight evaluated (with one temporary each), the weights table of a tier of several
    rules; then the assembly (output starts, value starts, the new word) and the
    successor's parameters evaluated one expression at a time.  ``made``: whether the
    word's bracket match and parameter offsets were still to be made when the step began
    (the guard runs after the matching, which made them; default: whether they are now).
    """
    n = len(word)
    held = n * _I64  # the choice per module, kept to the end
    if word.has_params:
        held += n * _I64  # nparams
    no_match, no_offsets = made or (word._match is None, word._offsets is None)
    if any(cr.rule.has_context for cr in rs.rules):
        if no_match:
            held += n * _I64  # the bracket match, made for context matching and kept
        if no_offsets:
            held += n * _I64  # the (zero) parameter offsets the matcher reads, kept
    pending = 0  # bound parameters kept for the successors, to the assembly
    matching = 0  # the largest transient of one symbol's rules
    biggest = 0
    for sym, tiers in rs.by_symbol.items():
        c = int(counts[sym]) if sym < counts.shape[0] else 0
        if not c:
            continue
        keep = max((_I64 * (len(cr.bindings) + 1) for t in tiers for cr in t if cr.args),
                   default=0)  # fmt: skip
        pending += c * keep
        per = 0
        for tier in tiers:
            if not tier:
                continue
            staged = sum(_I64 * (1 + len(cr.bindings)) for cr in tier)  # sel and env per rule
            if len(tier) > 1:
                staged += _I64 * len(tier)  # the weights table
                if all(cr.cond is None for cr in tier):
                    # rules that all apply are drawn from: the table's rows and their
                    # cumulative sums, draws, picks, masks (conditions mostly leave one)
                    staged += (2 * _I64 + 1) * len(tier) + 5 * _I64
            one = max(
                2 + _I64 * (len(cr.left) + len(cr.right))
                + (_I64 + 1 if cr.pred_arity else 0)
                + 2 * _I64 * len(cr.bindings)
                + (3 * _I64 + 1 if cr.cond is not None else 0)
                + (2 * _I64 + 1 if cr.weight_const is None else 0)
                for cr in tier
            )  # masks, context positions, arity, gathers of the bound parameters,
            # condition and weight with a temporary each
            per = max(per, staged + one)
        matching = max(matching, n + c * (_I64 + per))  # ids == sym, the undecided indices
        biggest = max(biggest, c)
    assembly = (
        n * (1 + 2 * _I64)  # the chosen mask, then gathers of the size check (transient)
        if not v_out and not word.has_params
        else 2 * _I64 * (n + 1) + 3 * _I64 * biggest  # starts; one parameter evaluated
    )
    return int(held + pending + max(matching, assembly) + word_bytes(n_out, v_out))


def _available_memory() -> int | None:
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def _check_limit(n_out: int, need: int, limit: int, word: ModuleString, step: int) -> None:
    """Raise :class:`GrowthLimitError` when a step makes more than ``limit`` modules, or
    needs (``need`` bytes) more than :data:`MEMORY_SHARE` of the free memory."""
    if n_out > limit:
        raise GrowthLimitError(
            f"step {step + 1} would grow the word from {len(word):,} to {n_out:,} modules, "
            f"past the limit of {limit:,}; derive fewer steps or raise the limit "
            "(--limit on the command line)",
            word=word,
            step=step,
        )
    avail = _available_memory()
    if avail is not None and need > MEMORY_SHARE * avail:
        size = f"{n_out:,} modules" if n_out else f"a word of {len(word):,} modules"
        raise GrowthLimitError(
            f"step {step + 1} would need about {need / 2**30:.2f} GiB for {size} but only "
            f"{avail / 2**30:.2f} GiB of memory is free; derive fewer steps",
            word=word,
            step=step,
        )
