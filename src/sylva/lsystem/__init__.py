"""L-systems: the common program, the compact word and the derivation engine."""

from .ast import Module, Pattern, Program, Rule
from .engine import DEFAULT_MODULE_LIMIT, Derivation, derive, iterate, render_word, rewrite
from .lstring import Alphabet, ModuleString

__all__ = [
    "DEFAULT_MODULE_LIMIT",
    "Alphabet",
    "Derivation",
    "Module",
    "ModuleString",
    "Pattern",
    "Program",
    "Rule",
    "derive",
    "iterate",
    "render_word",
    "rewrite",
]
