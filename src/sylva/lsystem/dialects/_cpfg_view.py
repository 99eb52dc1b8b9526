"""cpfg's view file (``.v``): the drawing settings of an L-system, read beside the ``.l``.

Each line is ``keyword: value``.  Honoured (mapped onto sylva's settings):

``angle increment: a``
    the turn angle ``rot`` in degrees; ``angle factor: n`` sets it to ``360/n``.
``initial line width: w``
    the width ``thick``, when ``line style:`` is ``polygon`` or ``cylinder`` (a width in
    units, as sylva draws); with cpfg's default ``pixel`` style the width is in pixels of the
    screen, which sylva's cylinders do not have, and a warning says so.  As cpfg reads the
    line, it sets the style too: ``pixel`` when a word starting with ``p`` follows the width
    (``2 pixels``), ``cylinder`` for one starting with ``s``, else ``polygon``; the last of
    it and ``line style:`` wins.
``line width increment: d``
    ``width_step``: what cpfg's ``!`` subtracts from the width and ``#`` adds to it (in
    units, with ``polygon`` or ``cylinder`` lines, as the initial width; 0 when the file
    does not say, as in cpfg, so a plain ``!`` or ``#`` keeps the width).
``line style: pixel | polygon | cylinder | wireframe``
    decides what the width means (above).
``tropism direction: x, y, z`` (normalised), ``initial elasticity: e``, ``elasticity increment: d``
    cpfg's old tropism (``tropism``, ``elasticity``, ``elasticity_step``), as when these lines
    appear in the ``.l``: after each ``F f G g`` the heading bends toward ``T``
    (``interpret.c``'s ``bend``); cpfg's ``_`` adds the increment to the elasticity,
    ``_(e)`` sets it.
``tropism: T: x y z [A: angle] [I: intensity] [E: elasticity] [S: step]``, ``torque: …``
    cpfg's movements (setting ``tropisms``, in the file's order: ``@Ts(k, e)``,
    ``@Ti(k[, d])``, ``@Td(k[, d])`` set and step the elasticity of the k-th): before each
    ``F f G g`` the tropisms together turn the heading, the torques roll the turtle about
    it (manual §8.1.8; :mod:`sylva.turtle._movements`).

``surface: X file.s scale [s t] [texture]``
    the predefined surface drawn by ``~X`` (the setting ``surfaces``: the Bézier patches of
    the ``.s`` file, a path relative to the view file's folder, scaled by ``scale``, each
    patch ``s × t`` quads; :mod:`sylva.geometry.surfaces`), and the number of its texture
    (one number after the scale is the texture, as cpfg reads it).
``texture: F: image [E: m|d|b] [S:] [R: r] [H: f] [L: f]``
    the setting ``textures``, numbered from 1: the image (PNG, SGI ``.rgb``), how it
    combines, whether it spans the whole surface; ``@Tx(n)`` and the surface lines choose
    them (``sylva.turtle._surfaces``).  A line whose image cannot be read, or with a
    subcommand cpfg does not know, takes no number (a warning says so), as in cpfg.
``background scene: file``
    the setting ``background_scene``: the objects of the file
    (:mod:`._cpfg_scene`), drawn around the plant.
``contour: id file.con``
    the setting ``contours`` (id -> :class:`._cpfg_contour.Contour`): the cross-sections
    of generalised cylinders that ``@#(id)`` selects.
``color map: f.map``, ``material: f.mat``, ``initial color: i``
    the colours of the indices ``;(n)`` / ``,(n)`` (settings ``colormap`` and
    ``materials``, read by the turtle; cpfg names these files on its command line, ``-m``
    and ``-M``, which a program can pass as the same settings) and the first index
    (``color_index``).
``function: f.func``, ``function set: f.fset``, ``curve: c.con``
    the functions ``func(k, x)`` and curves ``curveX(k, t)`` … of expressions and blocks
    (:mod:`._cpfg_functions`).

``viewpoint``, ``view reference point``, ``twist``, ``projection``, ``scale factor``
    the camera (:func:`read_camera`): ``sylva render`` of a cpfg file looks from the
    viewpoint to the reference point, twisted, parallel or in perspective, the plant
    fitted to the image times the scale factor (``sylva.render.Camera.from_view``).

Every other line (``front distance``, ``back distance``, ``z buffer``, ``render mode``, ``light:``,
``color increment``, ``generalized cylinders`` …, and lines
sylva does not know) is reported once as a :class:`~sylva.errors.SylvaWarning` naming the
file and line, never dropped silently.  Settings of the ``.l`` itself win over the view
file's.
"""

from __future__ import annotations

import math
import os
import re
import warnings
from pathlib import Path

from ...errors import LSystemSyntaxError, SylvaError, SylvaWarning
from . import _cpp

__all__ = ["read_view", "view_path"]

_LINE = re.compile(r"\s*([A-Za-z][A-Za-z _-]*?)\s*:(.*)\Z")
_NUMBER = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)")
#: Lines of cpfg's view files that sylva knows but does not draw, with what it lacks.
_UNHONOURED = {
    "front distance": "the renderer clips nothing",
    "back distance": "the renderer clips nothing",
    "z buffer": "the renderer always hides what is behind",
    "render mode": "the renderer's shading is its own",
    "light": "the renderer's lights are its own",
    "color increment": "colour indices step by 1",
    "generalized cylinders": "generalised cylinders are drawn as cpfg's Hermite curves, "
                             "their sections the view file's contours (@#), radii linear",
    "maximum depth": "the stack depth is not limited",
    "box": "bounding boxes are not drawn",
    "shadow map": "the renderer's shadows are its own",
}


#: The camera lines: not settings of the program; ``sylva render`` and the corpus runner
#: place their camera with them (:func:`read_camera`, ``sylva.render.Camera.from_view``).
_CAMERA = frozenset({"projection", "viewpoint", "view reference point", "twist", "scale",
                     "scale factor", "viewing angle"})  # fmt: skip


def view_path(lsystem_file: str | None) -> Path | None:
    """The view file beside ``lsystem_file`` (same stem, ``.v``), if there is one."""
    if not lsystem_file:
        return None
    path = Path(lsystem_file).with_suffix(".v")
    return path if path.is_file() else None


def _numbers(text: str, count: int, err) -> list[float]:
    values, pos = [], 0
    for _ in range(count):
        m = _NUMBER.match(text, pos)
        if m is None:
            raise err(pos)
        values.append(float(m.group(1)))
        pos = m.end()
        while pos < len(text) and text[pos] in " ,\t":
            pos += 1
    return values


def read_view(text: str, filename: str | None = None) -> dict[str, object]:
    """The sylva settings a view file sets; warns (:class:`~sylva.errors.SylvaWarning`) once
    for each line it cannot honour.

    Raises
    ------
    LSystemSyntaxError
        For a value sylva honours that is not a number (or a zero tropism direction), naming
        the file, line and column.

    Examples
    --------
    >>> read_view("angle factor: 8\\ntropism direction: 0, -2, 0\\n")
    {'rot': 45.0, 'tropism': (0.0, -1.0, 0.0)}
    """
    source = text.removeprefix("\ufeff").split("\n")
    lines = _cpp.strip_comments(text.removeprefix("\ufeff")).split("\n")
    found: list[tuple[int, str, str, int]] = []
    style = "pixel"
    for number, line in enumerate(lines, start=1):
        line = line.rstrip("\r")
        if not line.strip():
            continue
        m = _LINE.match(line)
        key = " ".join(m.group(1).lower().split()) if m else ""
        if m is None or (key not in _UNHONOURED and key not in _HONOURED
                         and key not in _CAMERA):
            warnings.warn(f"{filename or '<view>'}:{number}: unknown view setting "
                          f"{line.strip()!r}; sylva ignores it", SylvaWarning,
                          stacklevel=4)  # fmt: skip
            continue
        if key in _CAMERA:  # the renderer's, through read_camera
            continue
        if key in _UNHONOURED:
            warnings.warn(f"{filename or '<view>'}:{number}: view setting {key!r} is not "
                          f"honoured ({_UNHONOURED[key]})", SylvaWarning, stacklevel=4)  # fmt: skip
            continue
        found.append((number, key, m.group(2), m.start(2)))
        style = _line_style(key, m.group(2), style)
    settings: dict[str, object] = {}
    for number, key, value, at in found:
        try:
            _honour(settings, number, key, value, at, style, filename, source)
        except _Unreadable as exc:  # cpfg says "Invalid parameters" and keeps its default
            warnings.warn(f"{filename or '<view>'}:{number}:{exc.column}: {key}: {exc.what} "
                          f"{exc.text!r} is not a number; the setting keeps its default (as "
                          "cpfg does)", SylvaWarning, stacklevel=4)  # fmt: skip
    return settings


class _Unreadable(Exception):
    def __init__(self, column: int, text: str, what: str = "the value") -> None:
        self.column, self.text, self.what = column, text, what


def _line_style(key: str, value: str, style: str) -> str:
    """The line style after the view line ``key: value`` (``style`` before it), as cpfg
    reads them in order: ``line style: s`` sets it; ``initial line width: w`` sets it too,
    to ``pixel`` when a word starting with ``p`` follows the width (``2 pixels``),
    ``cylinder`` for one starting with ``s``, else ``polygon`` (a width in units)."""
    if key == "line style":
        return value.strip().lower()
    if key == "initial line width":
        m = _NUMBER.match(value)
        rest = value[m.end():].strip().lower() if m else ""
        if not m:
            return style  # cpfg's fscanf fails: nothing changes
        return "pixel" if rest.startswith("p") else "cylinder" if rest.startswith(
            "s") else "polygon"  # fmt: skip
    return style


def _honour(settings, number, key, value, at, style, filename, source) -> None:
    """Set what the view line ``key: value`` sets."""

    def err(pos, message=None, _n=number, _at=at, _k=key):
        if message is None:  # a value cpfg's fscanf cannot read: a warning
            return _Unreadable(_at + pos + 1, value.strip())
        return LSystemSyntaxError(message, filename=filename, line=_n,
                                  column=_at + pos + 1,
                                  source_line=source[_n - 1].rstrip("\r"))  # fmt: skip

    if key == "angle increment":
        settings["rot"] = _numbers(value, 1, err)[0]
    elif key == "angle factor":
        n = _numbers(value, 1, err)[0]
        if n == 0:
            raise err(0, "angle factor: expected a number other than 0")
        settings["rot"] = 360.0 / n
    elif key in ("initial line width", "line width increment"):
        w = _numbers(value, 1, err)[0]
        if style in ("polygon", "polygons", "cylinder", "cylinders"):
            settings["thick" if key == "initial line width" else "width_step"] = w
        else:
            warnings.warn(f"{filename or '<view>'}:{number}: {key!r} is in pixels with "
                          f"line style {style!r}; not honoured (sylva draws widths in "
                          "units: set line style: cylinder)", SylvaWarning,
                          stacklevel=4)  # fmt: skip
    elif key == "twist of cylinders":  # cpfg: 'on' keeps each control point's own up
        settings["cylinder_twist"] = value.strip().lower().startswith("on")
    elif key == "contour sides":  # the points of a generalised cylinder's contour ring
        n = _numbers(value, 1, err)[0]
        if n < 3:
            warnings.warn(f"{filename or '<view>'}:{number}: 'contour sides: {n:g}': cpfg "
                          "cannot draw cylinders with less than 3 sides; 3 used",
                          SylvaWarning, stacklevel=4)  # fmt: skip
        settings["contour_sides"] = max(3, int(n))
    elif key == "line style":
        if style == "wireframe":  # cpfg draws lines: as pixel, sylva's tubes
            warnings.warn(f"{filename or '<view>'}:{number}: line style 'wireframe' is "
                          "drawn as 'pixel' (sylva's tubes)", SylvaWarning,
                          stacklevel=4)  # fmt: skip
        elif style not in ("pixel", "pixels", "polygon", "polygons", "cylinder",
                           "cylinders"):  # fmt: skip
            raise err(0, f"line style {style!r}: expected pixel, polygon, cylinder or "
                      "wireframe")  # fmt: skip
    elif key == "tropism direction":
        t = _numbers(value, 3, err)
        norm = math.sqrt(sum(c * c for c in t))
        if norm == 0.0:
            raise err(0, "the tropism direction is the zero vector; expected a direction "
                      "such as 0,-1,0")  # fmt: skip
        settings["tropism"] = tuple(c / norm for c in t)
    elif key == "initial elasticity":
        settings["elasticity"] = _numbers(value, 1, err)[0]
    elif key == "elasticity increment":
        settings["elasticity_step"] = _numbers(value, 1, err)[0]
    elif key in ("tropism", "torque"):
        movements = settings.get("tropisms", ())
        if len(movements) == MAX_MOVEMENTS:
            raise err(0, f"{key}: more than {MAX_MOVEMENTS} tropism and torque lines; sylva "
                      f"draws at most {MAX_MOVEMENTS}")  # fmt: skip
        settings["tropisms"] = (*movements, _movement(key, value, err))
    elif key in _FILES_KEYS:
        _files(settings, key, value, err, filename, number, source[number - 1].rstrip("\r"),
               at)


#: The most ``tropism:`` and ``torque:`` lines sylva draws (cpfg allows 10; vlab's models
#: use up to 4).
MAX_MOVEMENTS = 4
_SUB = re.compile(r"([A-Za-z]+)\s*:?")


def _movement(key: str, value: str, err) -> tuple:
    """``(kind, (tx, ty, tz), angle, elasticity, step)`` of a ``tropism:`` or ``torque:``
    line.  The vector is scaled as cpfg's ``read_movement`` does (``movements.c``): by
    ``intensity / |T|`` clipped to [-1, 1], so a unit vector of intensity 1 stays one."""
    vec = None
    scale = 0.0
    angle = elasticity = step = 0.0
    pos = 0
    while True:
        while pos < len(value) and value[pos] in " \t,":
            pos += 1
        if pos >= len(value):
            break
        m = _SUB.match(value, pos)
        name = m.group(1).upper() if m else ""
        if name not in ("T", "A", "I", "E", "S"):
            raise err(pos, f"{key}: unknown subcommand {value[pos:].split()[0]!r}; expected "
                      "T: x y z, A: angle, I: intensity, E: elasticity or S: step")  # fmt: skip
        at, pos = pos, m.end()
        count = 3 if name == "T" else 1
        want = f"{key}: {name}: expected {count} number{'s' if count > 1 else ''}"
        numbers = _numbers(value[pos:], count, lambda p, _p=pos, _w=want: err(_p + p, _w))
        for _ in range(count):  # past the numbers just read
            m2 = _NUMBER.match(value, pos)
            pos = m2.end()
            while pos < len(value) and value[pos] in " ,\t":
                pos += 1
        if name == "T":
            norm = math.sqrt(sum(c * c for c in numbers))
            if norm == 0.0:
                raise err(at, f"{key}: the vector T is the zero vector; expected a "
                          "direction such as 0 1 0")  # fmt: skip
            vec, scale = numbers, 1.0 / norm
        elif name == "I":
            scale *= numbers[0]
            if scale == 0.0:
                raise err(at, f"{key}: intensity 0 (or before T:); expected T: x y z "
                          "first and an intensity other than 0")  # fmt: skip
            scale = max(-1.0, min(1.0, scale))
        elif name == "A":
            angle = numbers[0]
        elif name == "E":
            elasticity = numbers[0]
        else:
            step = numbers[0]
    if vec is None:
        raise err(len(value), f"{key}: expected the vector, T: x y z (cpfg's mandatory "
                  "subcommand)")  # fmt: skip
    return (key, tuple(c * scale for c in vec), angle, elasticity, step)


_HONOURED = frozenset({"angle increment", "angle factor", "initial line width", "line style",
                       "line width increment",
                       "tropism direction", "initial elasticity",
                       "elasticity increment", "function", "function set", "curve",
                       "surface", "color map", "colormap", "material",
                       "initial color", "tropism", "torque", "background scene",
                       "texture", "contour", "contour sides",
                       "twist of cylinders"})  # fmt: skip


def load_view(view, filename: str | None) -> dict[str, object]:
    """The settings of the view file ``view`` (a path; ``None``: the one beside
    ``filename``, if any; ``False``: none)."""
    if view is False:
        return {}
    path = view_path(filename) if view is None else Path(view)
    if path is None:
        return {}
    try:
        data = path.read_bytes()
    except OSError as e:
        raise SylvaError(f"{path}: cannot read the view file ({e.strerror or e})") from None
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = data.decode("latin-1")
    return read_view(text, str(path))


_CAMERA_KEYS = {"viewpoint": 3, "view reference point": 3, "twist": 1, "scale factor": 1,
                "scale": 1, "viewing angle": 1}  # fmt: skip


def read_camera(view, filename: str | None = None) -> dict[str, object]:
    """The camera lines of a view file as plain values: ``viewpoint`` and ``view reference
    point`` (3 floats each), ``twist`` (degrees), ``projection`` (``"parallel"`` or
    ``"perspective"``), ``scale`` (the ``scale factor``) and ``viewing angle`` (the
    perspective's field of view, degrees), and how lines are drawn:
    ``line style`` (``"pixel"`` …) and ``line width`` (the ``initial line width``); only the
    lines present (empty for no file).  ``view`` as in :func:`load_view`; ``sylva render``
    and the corpus runner make their camera from them (``sylva.render.Camera.from_view``)."""
    if view is False:
        return {}
    path = view_path(filename) if view is None else Path(view)
    if path is None or not path.is_file():
        return {}
    out: dict[str, object] = {}
    for line in path.read_text("latin-1").splitlines():
        m = _LINE.match(line.split("//")[0])
        if m is None:
            continue
        key = " ".join(m.group(1).lower().split())
        value = m.group(2)
        if key in ("line style", "initial line width"):  # how wide lines are drawn
            style = _line_style(key, value, str(out.get("line style", "pixel")))
            out["line style"] = (style.split() or ["pixel"])[0]
        if key == "projection":
            out["projection"] = value.strip().lower()
        elif key == "initial line width":
            nums = re.findall(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?", value)
            if nums:
                out["line width"] = float(nums[0])
        elif key in _CAMERA_KEYS:
            nums = [float(x) for x in re.findall(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?",
                                                  value)][: _CAMERA_KEYS[key]]  # fmt: skip
            if len(nums) == _CAMERA_KEYS[key]:
                name = "scale" if key == "scale factor" else key
                out[name] = tuple(nums) if len(nums) > 1 else nums[0]
    return out


# --------------------------------------------------------------------------- files (surfaces)
_FILES_KEYS = frozenset({"surface", "color map", "colormap", "material", "initial color",
                         "background scene", "texture", "contour"})  # fmt: skip


def _beside(name: str, filename: str | None) -> str:
    """``name`` relative to the folder of the view file ``filename``."""
    path = Path(name)
    if not path.is_absolute() and filename and not filename.startswith("<"):
        path = Path(filename).parent / path
    return str(path)


def _files(settings: dict, key: str, value: str, err, filename: str | None,
           number: int, line: str = "", at: int = 0) -> None:  # fmt: skip
    """The view lines that name files (``surface:``, ``color map:``, ``material:``,
    ``background scene:``, ``texture:``) and ``initial color:``, into ``settings``."""
    if key == "background scene":
        from ._cpfg_scene import load_scene

        settings["background_scene"] = (tuple(settings.get("background_scene") or ())
                                        + load_scene(value, filename, number, line))  # fmt: skip
        return
    if key == "texture":
        _texture(settings, value, filename, number, at)
        return
    if key == "contour":
        _contour(settings, value, err, filename, number)
        return
    if key == "initial color":
        i = _numbers(value, 1, err)[0]
        if not (i >= 0 and i == int(i)):
            raise err(0, "initial color: expected a whole number >= 0")
        settings["color_index"] = int(i)
        return
    words = [(m.group(), m.start()) for m in re.finditer(r"\S+", value)]
    if key == "surface":
        if len(words) < 3:
            raise err(len(value), "surface: expected an id, a file name and a scale "
                      "(surface: l leaf.s 1.0 [s t])")  # fmt: skip
        value_at = at
        (name, _), (file, file_at), (scale, at) = words[:3]
        numbers = [_numbers(value[at:], 1, lambda p, _a=at: err(_a + p))[0]]
        for text, pos in words[3:6]:
            if _NUMBER.fullmatch(text) is None:
                break
            numbers.append(_numbers(text, 1, lambda p, _a=pos: err(_a + p))[0])
        if len(words) > 2 + len(numbers):
            warnings.warn(f"{filename or '<view>'}:{number}: surface {name!r}: "
                          f"{words[2 + len(numbers)][0]!r} is not a texture number; cpfg "
                          "reads 'surface: id file scale [s t] [texture]'", SylvaWarning,
                          stacklevel=5)  # fmt: skip
        # cpfg: one number after the scale is the texture, two the precision, three both
        s, t = (int(numbers[1]), int(numbers[2])) if len(numbers) >= 3 else (None, None)
        tex = int(numbers[3]) if len(numbers) >= 4 else int(numbers[1]) if len(
            numbers) == 2 else None  # fmt: skip
        path = _beside(file, filename)
        if not os.path.isfile(path):  # cpfg's interpret.c: access() fails, the line is skipped
            col = value_at + file_at + 1
            warnings.warn(f"{filename or '<view>'}:{number}:{col}: surface {name!r}: no "
                          f"file {path}; as in cpfg, the line is skipped and ~{name} draws "
                          "nothing", SylvaWarning, stacklevel=5)  # fmt: skip
            return
        table = dict(settings.get("surfaces") or {})
        entry = (path, numbers[0], s, t)
        table[name] = entry if tex is None else (*entry, tex)  # the texture's number
        settings["surfaces"] = table
        return
    if not words:
        raise err(len(value), f"{key}: expected a file name")
    settings["colormap" if key in ("color map", "colormap") else "materials"] = _beside(
        words[0][0], filename)


def _texture(settings: dict, value: str, filename: str | None, number: int, at: int) -> None:
    """A ``texture:`` line: its subcommands ``F: file`` (mandatory), ``E: mode``, ``S:``,
    ``R: ratio``, ``H:`` / ``L:`` filters (the cpfg manual §8.1.7) into the setting
    ``textures``, numbered from 1 in file order.  As in cpfg, a line whose file cannot be
    read, or with a subcommand cpfg does not know, takes no number (a warning says so)."""
    where = f"{filename or '<view>'}:{number}"
    tokens = [(m.group(), at + m.start() + 1) for m in re.finditer(r"[^\s:]+", value)]
    tex: dict[str, object] = {"file": None, "mode": "modulate", "per_surface": False,
                              "ratio": 1.0}  # fmt: skip
    k = 0
    while k < len(tokens):
        word, col = tokens[k]
        k += 1
        c = word[0]
        if c == "S":
            tex["per_surface"] = True
            continue
        if c not in "FELHR" or len(word) > 1:
            warnings.warn(f"{where}:{col}: texture: unknown subcommand {word!r} (expected F:, "
                          "E:, S:, R:, H: or L:); cpfg drops the texture, and so does sylva",
                          SylvaWarning, stacklevel=6)  # fmt: skip
            return
        if k >= len(tokens):
            break
        arg, acol = tokens[k]
        k += 1
        if c == "F":
            tex["file"] = _beside(arg.rstrip(","), filename)
        elif c == "E":
            tex["mode"] = {"m": "modulate", "d": "decal", "b": "blend"}.get(arg[0], "modulate")
        elif c == "R":
            try:
                tex["ratio"] = float(arg)
            except ValueError:
                warnings.warn(f"{where}:{acol}: texture: R: {arg!r} is not a number; the "
                              "ratio stays 1", SylvaWarning, stacklevel=6)  # fmt: skip
    if tex["file"] is None or not Path(str(tex["file"])).is_file():
        what = ("has no file (F: name)" if tex["file"] is None
                else f"file {tex['file']} cannot be read")  # fmt: skip
        warnings.warn(f"{where}: texture {what}; cpfg drops it (it takes no number), and so "
                      "does sylva", SylvaWarning, stacklevel=6)  # fmt: skip
        return
    settings["textures"] = (*tuple(settings.get("textures") or ()), tex)


def _contour(settings: dict, value: str, err, filename: str | None, number: int) -> None:
    """A ``contour: id file`` line: the contour (:mod:`._cpfg_contour`) into the setting
    ``contours`` under its id, for the generalised cylinders (``@#(id)``)."""
    from ._cpfg_contour import load_contour

    words = [(m.group(), m.start()) for m in re.finditer(r"\S+", value)]
    if len(words) < 2:
        raise err(len(value), "contour: expected an id and a file name (contour: 1 leaf.con)")
    (ident, at), (name, _) = words[:2]
    if not re.fullmatch(r"[-+]?\d+", ident):
        raise err(at, f"contour: the id {ident!r} is not a whole number")
    try:
        contour = load_contour(name, filename)
    except OSError as e:  # cpfg: "Cannot open the contour file", and goes on
        warnings.warn(f"{filename or '<view>'}:{number}: contour {ident}: cannot read "
                      f"{name} ({e.strerror or e}); @#({ident}) draws the default circle",
                      SylvaWarning, stacklevel=6)  # fmt: skip
        return
    table = dict(settings.get("contours") or {})
    table[int(ident)] = contour
    settings["contours"] = table
