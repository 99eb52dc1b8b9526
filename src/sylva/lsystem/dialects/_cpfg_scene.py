"""cpfg's background scene files: objects drawn around the plant (the cpfg manual §8.3).

The view file's ``background scene: file`` names a text file of OpenGL-like commands, run
through the C preprocessor first (comments, ``#define``; :mod:`._cpp`).  Each command is a
word followed by its numbers:

Primitives, in the local coordinate system of the current matrix:
    ``polygon x1 y1 z1 … xn yn zn`` (n ≥ 3, fanned from the first vertex as cpfg draws it),
    ``polygonuv x1 y1 z1 nx1 ny1 nz1 …`` (each vertex with its normal), ``rectangle a b
    [x y]`` (corner at ``(x, y, 0)``, sides ``a`` along x and ``b`` along y), ``mesh
    x1 y1 z1 … xn yn zn`` (n = 4 + 2k: vertices 2i, 2i+1, 2i+2, 2i+3 make a quad), ``box a b
    c`` or ``prism a b c`` (corner at the origin), ``cone r1 r2 h`` and ``cylinder r h``
    (along local y, from 0 to h, with caps), ``sphere r``.
``material`` with up to 17 numbers:
    ambient, diffuse, specular and emissive RGBA and the specular exponent; the primitives
    that follow take it (sylva draws the diffuse plus emissive colour, alpha the diffuse's).
Transformations (OpenGL's modelview matrix, each multiplied on the right):
    ``translate tx ty tz``, ``rotate angle vx vy vz`` (degrees), ``scale sx sy sz``,
    ``multmatrix`` (or the manual's ``mulmatrix``) and ``loadmatrix`` with 16 numbers, column
    by column, ``loadidentity``, ``pushmatrix``, ``popmatrix``.
``clear``, ``light``, ``ortho``, ``perspective``, ``lookat``, ``matrixmode``:
    the lighting and projection lines that cpfg's ``-gls`` output adds; a background does
    not need them: they are skipped with a warning.

:func:`read_scene` returns the primitives with their world matrix and material as plain
tuples (:class:`Primitive`); :mod:`sylva.geometry.scenery` makes a mesh of them, and
``sylva render`` draws it with the plant (the camera is fitted to the plant alone, as cpfg
fits its view).  A word that is no command, a command without the numbers it needs, a
``popmatrix`` without a ``pushmatrix`` are :class:`~sylva.errors.LSystemSyntaxError` naming
the file, line and column.
"""

from __future__ import annotations

import math
import re
import warnings
from pathlib import Path
from typing import NamedTuple

from ...errors import LSystemSyntaxError, SylvaError, SylvaWarning
from . import _cpp

__all__ = ["Primitive", "load_scene", "read_scene"]

#: The fewest numbers each primitive needs, and how they group (vertex size).
_PRIMITIVES = {"polygon": (9, 3), "polygonuv": (18, 6), "rectangle": (2, 1), "mesh": (12, 3),
               "box": (3, 1), "prism": (3, 1), "cone": (3, 1), "cylinder": (2, 1),
               "sphere": (1, 1)}  # fmt: skip
_MATRIX = {"translate": 3, "rotate": 4, "scale": 3, "multmatrix": 16, "mulmatrix": 16,
           "loadmatrix": 16, "loadidentity": 0, "pushmatrix": 0, "popmatrix": 0}  # fmt: skip
_SKIPPED = frozenset({"clear", "light", "ortho", "perspective", "lookat", "matrixmode",
                      "maxtrixmode"})  # fmt: skip
_WORDS = sorted({*_PRIMITIVES, *_MATRIX, "material"})
_NUM = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?\Z")
_SIGNED_NAME = re.compile(r"([-+]?)([A-Za-z_]\w*)\Z")


class Primitive(NamedTuple):
    """One object of a background scene.

    Attributes
    ----------
    kind : str
        ``polygon``, ``polygonuv``, ``rectangle``, ``mesh``, ``box``, ``cone``, ``cylinder``
        or ``sphere`` (``prism`` is read as ``box``).
    params : tuple of float
        Its numbers as the file gives them.
    matrix : tuple of 16 float
        The local-to-world matrix, row by row (``matrix[4*i + j]`` is row ``i``, column ``j``).
    material : tuple of float or None
        The numbers of the last ``material`` command (up to 17), None before the first.
    """

    kind: str
    params: tuple[float, ...]
    matrix: tuple[float, ...]
    material: tuple[float, ...] | None


_IDENTITY = (1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0)


def _mul(a, b) -> tuple[float, ...]:
    """The 4×4 product ``a · b`` of two row-major matrices."""
    return tuple(sum(a[4 * i + k] * b[4 * k + j] for k in range(4))
                 for i in range(4) for j in range(4))  # fmt: skip


def _transform(word: str, v: list[float]) -> tuple[float, ...] | None:
    """The matrix of one transformation command (row-major), None for the stack words."""
    if word == "translate":
        return (1, 0, 0, v[0], 0, 1, 0, v[1], 0, 0, 1, v[2], 0, 0, 0, 1)
    if word == "scale":
        return (v[0], 0, 0, 0, 0, v[1], 0, 0, 0, 0, v[2], 0, 0, 0, 0, 1)
    if word == "rotate":  # glRotate: angle in degrees about (x, y, z)
        n = math.sqrt(v[1] ** 2 + v[2] ** 2 + v[3] ** 2)
        if n == 0.0:
            return _IDENTITY
        x, y, z = v[1] / n, v[2] / n, v[3] / n
        c, s = math.cos(math.radians(v[0])), math.sin(math.radians(v[0]))
        t = 1.0 - c
        return (t * x * x + c, t * x * y - s * z, t * x * z + s * y, 0.0,
                t * x * y + s * z, t * y * y + c, t * y * z - s * x, 0.0,
                t * x * z - s * y, t * y * z + s * x, t * z * z + c, 0.0,
                0.0, 0.0, 0.0, 1.0)  # fmt: skip
    if word in ("multmatrix", "mulmatrix", "loadmatrix"):  # OpenGL: column by column
        return tuple(v[4 * j + i] for i in range(4) for j in range(4))
    return None


def read_scene(text: str, filename: str | None = None) -> tuple[Primitive, ...]:
    """The primitives of a background scene file's text (see the module notes).

    Raises
    ------
    LSystemSyntaxError
        For a word that is no command, a command short of numbers, a ``popmatrix`` without
        ``pushmatrix``, naming the file, line and column.

    Examples
    --------
    >>> p = read_scene("translate 1 2 3\\nsphere 0.5\\n")
    >>> p[0].kind, p[0].params, p[0].matrix[3], p[0].matrix[7], p[0].matrix[11]
    ('sphere', (0.5,), 1.0, 2.0, 3.0)
    """
    result = _cpp.preprocess(text, filename)
    tokens: list[tuple[str, _cpp.Origin]] = []
    for line in result.lines:
        if line.define is not None:
            continue
        for m in re.finditer(r"\S+", line.text):
            tokens.append((m.group(), line.at(m.start() + 1)))

    def error(message: str, origin) -> SylvaError:
        return result.error(message, origin)

    def number(word: str):
        if _NUM.match(word):
            return float(word)
        m = _SIGNED_NAME.match(word)
        if m and m.group(2) in result.values:
            value = float(result.values[m.group(2)])
            return -value if m.group(1) == "-" else value
        return None

    out: list[Primitive] = []
    matrix, stack, material = _IDENTITY, [], None
    k, n = 0, len(tokens)
    while k < n:
        word, origin = tokens[k]
        key = word.lower()
        k += 1
        values: list[float] = []
        while k < n:
            v = number(tokens[k][0])
            if v is None:
                break
            values.append(v)
            k += 1
        if key in _SKIPPED:
            warnings.warn(f"{origin[0] or '<scene>'}:{origin[1]}: background scene command "
                          f"{word!r} (lighting or projection) is skipped; a background does "
                          "not need it", SylvaWarning, stacklevel=3)  # fmt: skip
            continue
        if number(word) is not None:
            raise error(f"the number {word!r} follows no command; expected one of "
                        f"{', '.join(_WORDS)}", origin)  # fmt: skip
        if key not in _PRIMITIVES and key not in _MATRIX and key != "material":
            raise error(f"unknown background scene command {word!r}; expected one of "
                        f"{', '.join(_WORDS)}", origin)  # fmt: skip
        if key == "material":
            if not values:
                raise error("material needs its numbers (ambient, diffuse, specular, "
                            "emissive RGBA, the specular exponent)", origin)  # fmt: skip
            material = tuple(values[:17])
        elif key in _MATRIX:
            need = _MATRIX[key]
            if len(values) < need:
                raise error(f"{word} needs {need} numbers, got {len(values)}", origin)
            if key == "pushmatrix":
                stack.append(matrix)
            elif key == "popmatrix":
                if not stack:
                    raise error("popmatrix without a pushmatrix", origin)
                matrix = stack.pop()
            elif key == "loadidentity":
                matrix = _IDENTITY
            elif key == "loadmatrix":
                matrix = _transform(key, values)  # type: ignore[assignment]
            else:
                matrix = _mul(matrix, _transform(key, values))
        else:
            need, group = _PRIMITIVES[key]
            if len(values) < need:
                raise error(f"{word} needs at least {need} numbers, got {len(values)}", origin)
            if key == "mesh" and (len(values) // 3) % 2:
                values = values[: len(values) - 3]  # cpfg reads whole pairs of points
            values = values[: len(values) - len(values) % group]
            out.append(Primitive("box" if key == "prism" else key, tuple(values), matrix,
                                 material))  # fmt: skip
    return tuple(out)


def load_scene(names: str, view: str | None, number: int, source: str | None,
               ) -> tuple[Primitive, ...]:  # fmt: skip
    """The primitives of the files a view file's ``background scene:`` names (several,
    separated by spaces, commas or semicolons, as cpfg reads them), relative to the view
    file's folder; ``view``/``number``/``source`` name the line for a missing file."""
    out: list[Primitive] = []
    files = [w for w in re.split(r"[\s,;]+", names) if w]
    if not files:
        raise LSystemSyntaxError("background scene: expected a file name", filename=view,
                                 line=number, column=len(source or "") + 1,
                                 source_line=source)  # fmt: skip
    for name in files:
        path = Path(name)
        if not path.is_absolute() and view and not view.startswith("<"):
            path = Path(view).parent / path
        try:
            data = path.read_bytes()
        except OSError as e:
            col = (source or "").find(name) + 1 or None
            raise LSystemSyntaxError(f"background scene: cannot read {path} "
                                     f"({e.strerror or e})", filename=view, line=number,
                                     column=col, source_line=source) from None  # fmt: skip
        out.extend(read_scene(data.decode("latin-1"), str(path)))
    return tuple(out)
