"""``sylva derive``: print the word an L-system grows."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from ..errors import GrowthLimitError, StepsError, SylvaError
from ..lsystem import DEFAULT_MODULE_LIMIT, Derivation, ModuleString, Program
from ..lsystem.engine import check_steps
from ..lsystem.environment import has_queries
from ._common import limit_type, steps_type

__all__ = ["derive_keeping", "load_program", "register"]


def load_program(source: str, dialect: str | None = None, view: str | None = None) -> Program:
    """A program from a path, or the name of a built-in example (``view``: a cpfg view file
    other than the ``.v`` beside the file)."""
    from ..lsystem import load

    p = Path(source)
    if p.exists():
        return load(p, dialect=dialect, view=view)
    from ..data import find

    try:
        ex = find(source)
    except SylvaError:
        raise SylvaError(
            f"{source}: no such file, and no built-in example of that name "
            "(`sylva examples` lists them)"
        ) from None
    return load(ex.path, dialect=dialect, view=view)


def add_common(p: argparse.ArgumentParser) -> None:
    p.add_argument("file", metavar="FILE", help="an L-system file, or a built-in example name")
    p.add_argument("-n", "--steps", type=steps_type, default=None,
                   help="derivation steps (default: the file's own count, else 0)")
    p.add_argument("-r", "--seed", type=int, default=None,
                   help="seed of the random choices (-r as in seed 000)")
    p.add_argument("--dialect", choices=["lsys", "classic", "engine", "cpfg"], default=None,
                   help="force the language of FILE (default: detected)")
    p.add_argument("--view", metavar="V", default=None,
                   help="cpfg: the view file (.v) to read (default: the one beside FILE)")
    p.add_argument("--limit", type=limit_type, default=DEFAULT_MODULE_LIMIT,
                   help=f"stop before a word passes this many modules "
                        f"(default {DEFAULT_MODULE_LIMIT:,})")
    p.add_argument("--environment", metavar="ENV", default=None,
                   help="an open L-system's environment for its ?E modules: light, "
                        "obstacle, world, with options as in the .lsys directive, e.g. "
                        "'obstacle(shape = box, sy = 2)' (default: the file's environment = …)")


def register(sub) -> None:
    p = sub.add_parser(
        "derive",
        help="derive an L-system and print the word",
        description="Derive an L-system and print the word it grows (one line), every "
        "step's word (--each, step 0 first) or statistics (--stats).",
    )
    add_common(p)
    p.add_argument("--each", action="store_true", help="print one line per step, step 0 first")
    p.add_argument("--stats", action="store_true",
                   help="print length, per-symbol counts and branch depth instead of the word")
    p.add_argument("--render", action="store_true",
                   help="print the render word (render rules applied) instead")
    p.add_argument("--keep-last", action="store_true",
                   help="when the module limit stops the derivation, print the word of the "
                        "last step that fits (and say so on stderr) instead of failing")
    p.set_defaults(func=run)


def stats_text(word: ModuleString, step: int, elapsed: float | None = None) -> str:
    counts = word.counts()
    lines = [
        f"step: {step}",
        f"modules: {len(word)}",
        f"parameters: {word.values.shape[0]}",
        f"branch depth: {word.max_depth()}",
    ]
    if elapsed is not None:
        lines.append(f"time: {elapsed:.3f} s")
    lines.append("symbols:")
    from ..lsystem.lstring import format_symbol

    for name, k in sorted(counts.items(), key=lambda kv: (-kv[1], kv[0])):
        lines.append(f"  {format_symbol(name)}\t{k}")
    return "\n".join(lines)


def derive_with_progress(d: Derivation, steps: int, each=None) -> None:
    """Advance ``d`` by ``steps``, with a progress bar on stderr once it takes a while."""
    from tqdm import tqdm

    with tqdm(total=steps, desc="deriving", unit="step", file=sys.stderr, delay=1.0,
              leave=False, disable=None if steps > 1 else True) as bar:
        for _ in range(steps):
            d.advance()
            bar.set_postfix_str(f"{len(d.word):,} modules", refresh=False)
            bar.update()
            if each is not None:
                each(d)


def stopped_note(exc: GrowthLimitError, asked: int, word: ModuleString) -> str:
    """How far a derivation the limit stopped got: steps done of those asked, modules."""
    return (f"the derivation stopped after {exc.step} of {asked} steps, with {len(word):,} "
            f"modules: {exc}")  # fmt: skip


def _environment(program: Program, seed: int | None, environment=None) -> dict:
    """The environment of the ?E modules and the turtle's locate, for a program that has
    them (the ``environment=`` and ``locate=`` of :class:`~sylva.lsystem.Derivation`)."""
    from ..lsystem.environment import has_communication

    if not has_communication(program):
        if environment is not None:  # a misspelt --environment is an error all the same
            from ..environments import resolve_environment

            resolve_environment(environment, program)
        return {}
    from ..plant import environment_for

    env, locate = environment_for(program, seed if seed is not None else program.seed,
                                  environment)  # fmt: skip
    return {"environment": env, "locate": locate}


def _query(program: Program, seed: int | None):
    """The turtle's answer to the query modules, for a program that has them."""
    if not has_queries(program):
        return None
    from ..plant import query_for  # the turtle, only when needed

    return query_for(program, seed if seed is not None else program.seed)


def derive_keeping(program: Program, steps: int | None, *, seed: int | None, limit: int,
                   keep_last: bool, environment=None) -> ModuleString:  # fmt: skip
    """The word after ``steps`` (``-n``) steps; with ``keep_last``, the word of the last step
    that fits when the module or memory limit stops the derivation (said on stderr)."""
    try:
        n = check_steps(program, steps, limit=limit, option="-n")
    except StepsError as exc:
        if not keep_last or exc.fits is None:
            raise
        print(f"sylva: note: {exc}\nsylva: note: deriving at most {exc.fits:,} steps "
              "(--keep-last)", file=sys.stderr)  # fmt: skip
        n = exc.fits
    d = Derivation(program, seed=seed, limit=limit, query=_query(program, seed),
                   **_environment(program, seed, environment))  # fmt: skip
    try:
        d.advance(n)
    except GrowthLimitError as exc:
        word = exc.word if exc.word is not None else d.word
        note = stopped_note(exc, n, word)
        if not keep_last:
            raise SylvaError(note + " (--keep-last uses the word of the last step that "
                             "fits)") from None  # fmt: skip
        print(f"sylva: note: {note}; using the word of step {exc.step} (--keep-last)",
              file=sys.stderr)  # fmt: skip
        return word
    return d.word


def run(args) -> int:
    program = load_program(args.file, args.dialect, args.view)
    try:
        steps = check_steps(program, args.steps, limit=args.limit, option="-n")
    except StepsError as exc:
        if not args.keep_last or exc.fits is None:
            raise
        print(f"sylva: note: {exc}\nsylva: note: deriving at most {exc.fits:,} steps "
              "(--keep-last)", file=sys.stderr)  # fmt: skip
        steps = exc.fits
    d = Derivation(program, seed=args.seed, limit=args.limit, query=_query(program, args.seed),
                   **_environment(program, args.seed, args.environment))  # fmt: skip
    out = sys.stdout

    def show(dd: Derivation) -> None:
        w = dd.render_word() if args.render else dd.word
        if args.stats:
            out.write(stats_text(w, dd.step) + "\n\n")
        else:
            out.write(w.to_text(float32=program.dialect == "cpfg") + "\n")

    t0 = time.perf_counter()
    try:
        if args.each:
            show(d)
            derive_with_progress(d, steps, show)
        elif steps > 1 and d.is_d0l:
            d.advance(steps)  # block expansion: all steps at once
        else:
            derive_with_progress(d, steps)
    except GrowthLimitError as exc:
        if exc.word is not None:
            d.word, d.step = exc.word, int(exc.step or 0)
        note = stopped_note(exc, steps, d.word)
        if not args.keep_last:
            raise SylvaError(note + " (--keep-last prints the word of the last step that "
                             "fits)") from None  # fmt: skip
        print(f"sylva: note: {note}; printing the word of step {d.step} (--keep-last)",
              file=sys.stderr)  # fmt: skip
        if args.each:
            return 0
    if not args.each:
        w = d.render_word() if args.render else d.word
        if args.stats:
            out.write(stats_text(w, d.step, time.perf_counter() - t0) + "\n")
        else:
            out.write(w.to_text(float32=program.dialect == "cpfg") + "\n")
    return 0
