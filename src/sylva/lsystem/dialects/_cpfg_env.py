"""cpfg's environment files (``cpfg -e plant.e``): which built-in environment answers them.

An open cpfg model names, in its environment file, the external program that answers its
communication modules ``?E`` and that program's specification file::

    executable: honda81 -e plant.e density.spec
    communication type: files
    turtle position:P:%.4f %.4f %.4f

sylva runs no external program; where one of its built-in environments computes what the
program computes, :func:`environment_spec` returns that environment (as the ``environment
= …`` text of :mod:`sylva.lsystem.environment`) with options read from the specification
file:

``honda81`` (vlab's ``ENVIRO/honda81``: Honda's 1981 crowding of branch tips)
    ``density(radius = R, planar = P)``: the spec's ``radius:``, and ``planar = 1`` unless it
    says ``3d case: on``.  ``?E(v, g)`` gets 1 (may grow) or 0 (crowded), as honda81 sends.
``chiba`` (Chiba et al. 1994's light on leaf balls)
    ``light(shadow = 1 - t)``: sylva's shadow-propagation light (Palubicki et al. 2009)
    with the spec's ``transmittance: t``.  ``?E(r, …)`` gets the light in [0, 1] of its
    position and, with four parameters, the least shaded direction, as chiba sends; the
    light is a voxel grid's, not chiba's rays cast through spheres of radius ``r``, so the
    values differ while the order (a shaded bud gets less) is the same.

Any other program is a :class:`EnvironmentProgramError` naming it.
"""

from __future__ import annotations

import shlex
from pathlib import Path

from ...errors import SylvaError

__all__ = ["EnvironmentProgramError", "environment_program", "environment_spec"]


class EnvironmentProgramError(SylvaError):
    """An environment file names a program sylva has no built-in environment for."""

    def __init__(self, message: str, program: str) -> None:
        super().__init__(message)
        self.program = program


def _read(path: Path) -> list[str]:
    try:
        return path.read_text("latin-1").splitlines()
    except OSError as exc:
        raise SylvaError(f"{path}: cannot read the environment file ({exc.strerror})") from None


def environment_program(path: str | Path) -> tuple[str, list[str]]:
    """The program an environment file names and its arguments (``-e file`` left out)."""
    path = Path(path)
    for number, line in enumerate(_read(path), 1):
        key, _, value = line.partition(":")
        if key.strip().lower() != "executable":
            continue
        try:
            words = shlex.split(value)
        except ValueError:
            words = value.split()
        if not words:
            raise SylvaError(f"{path}:{number}: 'executable:' names no program; expected "
                             "'executable: program [arguments]'")  # fmt: skip
        args, k = [], 1
        while k < len(words):
            if words[k] in ("-e", "-k", "-ext") and k + 1 < len(words):
                k += 2
                continue
            args.append(words[k])
            k += 1
        return Path(words[0]).name, args
    raise SylvaError(f"{path}: no 'executable:' line; expected the environment program's "
                     "name, 'executable: program [arguments]'")  # fmt: skip


def _spec(path: Path, args: list[str]) -> dict[str, tuple[str, int]]:
    """The specification file's ``key: value`` lines (lower-case keys, with line numbers)."""
    if not args:
        return {}
    spec = path.parent / args[-1]
    out: dict[str, tuple[str, int]] = {}
    for number, line in enumerate(_read(spec), 1):
        key, colon, value = line.partition(":")
        if colon:
            out.setdefault(" ".join(key.lower().split()), (value.strip(), number))
    out["\0file"] = (str(spec), 0)
    return out


def _number(spec: dict, key: str, default: float) -> float:
    if key not in spec:
        return default
    text, number = spec[key]
    word = text.replace(",", " ").replace(";", " ").split()
    try:
        return float(word[0])
    except (IndexError, ValueError):
        raise SylvaError(f"{spec[chr(0) + 'file'][0]}:{number}: {key}: expected a number, "
                         f"got {text!r}") from None


def environment_spec(path: str | Path) -> str:
    """The built-in environment (``environment = …`` text) that serves the environment
    file ``path``, or :class:`EnvironmentProgramError` naming a program sylva lacks.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "density.spec").write_text("verbose: off\\nradius: 0.5\\n3d case: on\\n")
    >>> _ = (d / "plant.e").write_text("executable: honda81 -e plant.e density.spec\\n")
    >>> environment_spec(d / "plant.e")
    'density(radius = 0.5, planar = 0)'
    """
    path = Path(path)
    program, args = environment_program(path)
    if program == "honda81":
        spec = _spec(path, args)
        radius = _number(spec, "radius", 0.0)
        three_d = spec.get("3d case", ("off", 0))[0].split()[:1] == ["on"]
        return f"density(radius = {radius:g}, planar = {0 if three_d else 1})"
    if program == "chiba":
        spec = _spec(path, args)
        t = min(max(_number(spec, "transmittance", 0.6), 0.0), 0.99)
        return f"light(shadow = {1.0 - t:g})"
    raise EnvironmentProgramError(
        f"{path}: needs environment program {program}, which sylva does not provide (its "
        "built-in environments serve honda81 and chiba)", program)
