"""L-systems: the common program, its four languages, the compact word and the engine.

>>> from sylva.lsystem import derive, loads
>>> str(derive(loads("axiom = a\\na -> ab\\nb -> a"), 4))
'abaababa'
"""

from ._rewrite import render_word, rewrite
from .ast import Module, Pattern, Program, Rule
from .build import define
from .dialects import detect, dumps, load, load_all, loads, parse_expr, parse_rule, parse_word
from .engine import DEFAULT_MODULE_LIMIT, Derivation, derive, iterate
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
    "define",
    "derive",
    "detect",
    "dumps",
    "iterate",
    "load",
    "load_all",
    "loads",
    "parse_expr",
    "parse_rule",
    "parse_word",
    "render_word",
    "rewrite",
]
