"""Step counts checked before a derivation starts: a documented maximum and the module limit.

:func:`check_steps` refuses more than :data:`~sylva.lsystem.ast.MAX_STEPS` steps, and more
steps than a word can take before it passes the module limit, which :func:`growth_floor`
proves from a lower bound of the word's length after each step.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import StepsError
from .ast import MAX_STEPS, Program

if TYPE_CHECKING:
    from .engine import _RuleSet

__all__ = ["check_steps", "growth_floor"]

#: The module limit of a derivation unless one is given (``--limit`` on the command line).
DEFAULT_MODULE_LIMIT = 50_000_000


_FLOOR_ITERATIONS = 64


def growth_floor(rs: _RuleSet, counts: np.ndarray, steps: int, limit: int) -> int | None:
    """The first step ``k <= steps`` by which *every* derivation has more than ``limit``
    modules, or ``None`` when none is known.

    ``L_k(s)``, the fewest modules a single ``s`` can become in ``k`` steps, follows
    ``L_{k+1}(s) = min over the outcomes o of s of sum(L_k(t) for t in o)``, where the
    outcomes are the successors of ``s``'s rules, and ``s`` itself when no rule need apply
    (conditions, contexts, weights that are not positive constants).  Parameters do not
    change how many modules a successor has, so the bound holds for every class of system
    but ABOP's cut ``%``, which removes modules (then ``None``).  After
    ``_FLOOR_ITERATIONS`` steps the bound goes on linearly: ``f(x) = L``'s map is monotone
    and superadditive, so when the last increment ``D`` has ``f(D) >= D`` every later step
    adds at least ``D``.
    """
    rs.grow()
    size = counts.shape[0]
    cut = rs.alphabet.get("%")
    if cut >= 0 and (cut < size and counts[cut] or any((cr.succ_ids == cut).any()
                                                       for cr in rs.rules)):
        return None
    if not rs.rules or steps <= 0:
        return None
    pred = np.array([cr.pred for cr in rs.rules], np.int64)
    flat = np.concatenate([cr.succ_ids for cr in rs.rules]).astype(np.int64)
    ends = np.cumsum([len(cr.succ_ids) for cr in rs.rules])
    starts = ends - np.array([len(cr.succ_ids) for cr in rs.rules])
    copy = np.ones(size, np.bool_)
    for cr in rs.rules:
        if (cr.cond is None and not cr.rule.has_context and cr.weight_const is not None
                and cr.weight_const > 0 and not rs.exact):
            # a rule always applies: the module never stays (with cpfg's exact parameter
            # counts, a module of its letter but another count stays)
            copy[cr.pred] = False
    cap = 2.0**52 / max(len(flat), 1)  # sums stay exact integers below 2**53
    w = counts.astype(np.float64)

    def f(x: np.ndarray) -> np.ndarray:
        cs = np.concatenate(([0.0], np.cumsum(x[flat])))
        out = np.full(size, np.inf)
        np.minimum.at(out, pred, cs[ends] - cs[starts])
        return np.where(copy, np.minimum(out, x), out)

    low = np.ones(size)
    k_max = min(steps, _FLOOR_ITERATIONS)
    prev = low
    for k in range(1, k_max + 1):
        prev, low = low, f(low)
        total = float(w @ low)
        if total > limit:
            return k
        if np.array_equal(low, prev):
            return None  # a fixed point: the bound grows no more
        if low.max() > cap:
            return None
    if steps <= k_max:
        return None
    d = low - prev
    per_step = float(w @ d)
    if per_step <= 0 or (f(d) < d).any():
        return None
    k = k_max + int((limit - total) // per_step) + 1  # first step with total > limit
    return k if k <= steps else None


def check_steps(
    program: Program,
    steps: int | None = None,
    *,
    limit: int = DEFAULT_MODULE_LIMIT,
    option: str | None = None,
) -> int:
    """The number of steps to derive, checked before any is derived.

    Parameters
    ----------
    program : Program
    steps : int, optional
        The steps asked for; ``None`` takes the program's own count (and errors name the
        place in the file where it was written, :attr:`Program.steps_at`).
    limit : int
        The module limit of the derivation.
    option : str, optional
        Where ``steps`` came from, named in errors (such as ``"-n"`` on the command line).

    Returns
    -------
    int
        ``steps``, or the program's count.

    Raises
    ------
    StepsError
        When the count is above :data:`MAX_STEPS`, or when every derivation of ``program``
        passes ``limit`` modules within that many steps (see :func:`growth_floor`).
    """
    from_file = steps is None and program.steps is not None
    if steps is not None and int(steps) < 0:
        where = f"{option} {int(steps)}" if option else f"{int(steps)} steps"
        raise StepsError(f"{where}: expected 0 or more derivation steps")
    from .engine import _compiled, _steps

    n = _steps(program, steps)
    at = program.steps_at if from_file else None
    if option is not None and not from_file:
        what = f"{option} {n:,}"
    elif from_file:
        what = f"{n:,} steps" if at is None else f"steps = {n:,}"
    else:
        what = f"{n:,} steps"

    def error(message: str, fits: int | None) -> StepsError:
        if at is None:
            return StepsError(f"{what}: {message}", fits=fits)
        return StepsError(f"{what}: {message}", fits=fits, filename=at.filename, line=at.line,
                          column=at.column, source_line=_source_line(at))  # fmt: skip

    if n > MAX_STEPS:
        big = f"{n:,}" if n < 10**12 else f"{float(n):.3g}"
        raise error(f"{big} steps asked for; expected at most {MAX_STEPS:,} derivation steps "
                    "(sylva.lsystem.MAX_STEPS)", None)  # fmt: skip
    comp = _compiled(program)
    counts = np.bincount(comp.axiom.ids, minlength=len(comp.alphabet))
    k = growth_floor(comp.productions, counts, n, int(limit))
    if k is not None:
        raise error(
            f"every word of this L-system has more than {int(limit):,} modules (the module "
            f"limit) by step {k:,}, so at most {k - 1:,} steps can be derived; derive fewer "
            "steps or raise the limit (--limit on the command line)",
            k - 1,
        )
    return n


def _source_line(at) -> str | None:
    """The text of the line ``at`` points to, read again from its file (best effort)."""
    if not at.filename:
        return None
    try:
        with open(at.filename, encoding="utf-8", errors="replace") as f:
            for i, line in enumerate(f, 1):
                if i == at.line:
                    return line
    except OSError:
        return None
    return None
