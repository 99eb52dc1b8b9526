"""``sylva examples``: list the built-in examples (usable wherever a FILE is asked for)."""

from __future__ import annotations

__all__ = ["register"]


def register(sub) -> None:
    p = sub.add_parser(
        "examples",
        help="list the built-in example L-systems",
        description="List the built-in examples.  Any command that takes a FILE also takes "
        "an example's name, or a unique part of it (e.g. `sylva derive koch-snowflake`).",
    )
    p.add_argument("--path", action="store_true", help="print the path of each file")
    p.set_defaults(func=run)


def run(args) -> int:
    from ..data import examples
    from ..lsystem import load

    for ex in examples():
        dialect = load(ex.path).dialect
        where = f"  {ex.path}" if args.path else ""
        print(f"{ex.name:40s} {dialect:8s} {ex.title}{where}")
    return 0
