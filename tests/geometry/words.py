"""A tiny context-free expander for test words (independent of the derivation engine)."""

from __future__ import annotations


def expand(axiom: str, rules: dict[str, str], n: int) -> str:
    """Apply single-character context-free ``rules`` ``n`` times in parallel."""
    word = axiom
    for _ in range(n):
        word = "".join(rules.get(c, c) for c in word)
    return word
