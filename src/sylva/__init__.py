"""sylva: grow plants, their textures and the worlds they stand in.

>>> import sylva
>>> plant = sylva.loads("axiom = X\\nX -> F[+X][-X]FX\\nF -> FF")
>>> len(sylva.derive(plant, 3))
143
"""

from .errors import GrowthLimitError, LSystemSemanticError, LSystemSyntaxError, SylvaError
from .lsystem import (
    Derivation,
    ModuleString,
    Program,
    define,
    derive,
    dumps,
    iterate,
    load,
    load_all,
    loads,
    render_word,
)

__all__ = [
    "Derivation",
    "GrowthLimitError",
    "LSystemSemanticError",
    "LSystemSyntaxError",
    "ModuleString",
    "Program",
    "SylvaError",
    "define",
    "derive",
    "dumps",
    "iterate",
    "load",
    "load_all",
    "loads",
    "render_word",
]
__version__ = "0.1.0"
