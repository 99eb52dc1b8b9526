"""The 3D turtle: interpret a derived word into segments, leaves, polygons and blocks.

One interpreter (a numba loop over the word's arrays) serves every dialect; a dialect is a
command table (:mod:`sylva.turtle.tables`).  :func:`interpret` returns a
:class:`~sylva.geometry.records.Geometry`; :func:`sylva.geometry.build.build_mesh` turns it
into triangles and :func:`sylva.geometry.exchange.write` into files.

Examples
--------
>>> from sylva.lsystem.lstring import ModuleString
>>> word = ModuleString.from_text("F[+F][-F]F")
>>> g = interpret(word, dialect="abop", rot=25.7)
>>> g.n_segments, g.bounds()[1, 1].round(6)
(4, np.float64(2.0))
"""

from ..geometry.records import Geometry
from .engine import generate, hash01, hash1d
from .interpreter import DIALECTS, Trace, TurtleSettingsError, interpret, trace
from .tables import DEFAULTS, TABLES

__all__ = [
    "DEFAULTS",
    "DIALECTS",
    "TABLES",
    "Geometry",
    "Trace",
    "TurtleSettingsError",
    "generate",
    "hash01",
    "hash1d",
    "interpret",
    "trace",
]
