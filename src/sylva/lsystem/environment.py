"""The query protocol: modules whose parameters the turtle fills between steps.

cpfg's query modules (Prusinkiewicz, James & Měch 1994, "Synthetic topiary") ``?P(x,y,z)``,
``?H(x,y,z)``, ``?U(x,y,z)`` and ``?L(x,y,z)`` are set, after every derivation step and on
the axiom before the first, to the turtle's position, heading, up or left vector at the
module, so that the next step's productions can test them (``?P(x,y,z) < A : y > 5 -> …``
prunes against a shape).  The turtle draws nothing for them.

:mod:`sylva.lsystem` does not import the turtle: a :class:`~sylva.lsystem.Derivation` takes
a *query* callback, ``query(word, index) -> values``, that receives the word and the indices
of its query modules (``int64[m]``, in word order) and returns their new values as a
``float64[m, 3]`` array, all at once.  :func:`sylva.plant.turtle_query` is the callback that
interprets the word with the program's turtle; :func:`sylva.grow` and :func:`sylva.derive`
wire it in.

Examples
--------
>>> from sylva.lsystem import Derivation, loads
>>> p = loads("axiom = ?P(0,0,0)\\n?P(x,y,z) : x < 2 -> ?P(x,y,z)A")
>>> d = Derivation(p, query=lambda word, index: [[len(word), 0, 0]] * len(index))
>>> str(d.advance(2))
'"?P"(2,0,0)A'
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..errors import SylvaError
from .ast import Program
from .lstring import ModuleString

__all__ = [
    "COMMUNICATION",
    "ENVIRONMENTS",
    "QUERY_MODULES",
    "Communication",
    "EnvironmentSpecError",
    "Environment",
    "Locate",
    "Query",
    "apply_environment",
    "apply_query",
    "communication_index",
    "has_communication",
    "has_queries",
    "parse_environment",
    "query_index",
]

#: The query modules and what the turtle puts in them.
QUERY_MODULES = {"?P": "position", "?H": "heading", "?U": "up", "?L": "left"}

#: ``query(word, index) -> float64[len(index), 3]``
Query = Callable[[ModuleString, np.ndarray], np.ndarray]


def _written(program: Program) -> frozenset[str]:
    """The symbols of ``program``'s axiom and successors, found once and kept on the
    (frozen) program: an axiom of 100 k modules is not walked again for every derivation."""
    found = program.__dict__.get("_sylva_written")
    if found is None:
        names = {m.symbol for m in program.axiom}
        for rule in program.rules:
            names.update(m.symbol for m in rule.successor)
        found = frozenset(names)
        object.__setattr__(program, "_sylva_written", found)
    return found


def has_queries(program: Program) -> bool:
    """True when a query module appears in the axiom or in a successor of ``program``."""
    return not _written(program).isdisjoint(QUERY_MODULES)


def query_index(word: ModuleString) -> np.ndarray:
    """``int64[m]``: the positions of the query modules in ``word``."""
    ids = [word.alphabet.get(name) for name in QUERY_MODULES]
    ids = [i for i in ids if i >= 0]
    if not ids:
        return np.zeros(0, np.int64)
    return np.flatnonzero(np.isin(word.ids, ids)).astype(np.int64)


def apply_query(word: ModuleString, query: Query, step: int) -> ModuleString:
    """``word`` with the parameters of its query modules set by ``query``.

    A query module keeps as many parameters as it has (at most 3 are set).  A callback
    that raises, or returns the wrong shape or a value that is not finite, is a
    :class:`~sylva.errors.SylvaError` naming the step.
    """
    index = query_index(word)
    if index.size == 0:
        return word
    try:
        out = query(word, index)
    except SylvaError:
        raise
    except Exception as exc:  # the user's environment: say where it failed
        raise SylvaError(
            f"step {step}: the query callback raised {type(exc).__name__}: {exc}"
        ) from exc
    try:
        values = np.asarray(out, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise SylvaError(
            f"step {step}: the query callback returned {type(out).__name__}; expected "
            f"float values of shape ({index.size}, 3)"
        ) from exc
    if values.shape != (index.size, 3):
        raise SylvaError(
            f"step {step}: the query callback returned shape {values.shape}; expected "
            f"({index.size}, 3), one (x, y, z) per query module"
        )
    if not np.isfinite(values).all():
        raise SylvaError(f"step {step}: the query callback returned a value that is not finite")
    offsets = word.offsets
    start = offsets[index]
    count = np.minimum(offsets[index + 1] - start, 3)
    new = word.values.copy()
    for k in range(3):
        has = count > k
        new[start[has] + k] = values[has, k]
    return ModuleString(word.alphabet, word.ids, offsets, new)


def missing_query(program: Program) -> SylvaError:
    """The error for a program with query modules derived without a query callback."""
    where = ""
    span = None
    for rule in program.rules:
        if any(m.symbol in QUERY_MODULES for m in rule.successor):
            span = rule.span
            break
    if span is not None:
        name = span.filename or "<string>"
        where = f"{name}:{span.line}:{span.column}: "
    return SylvaError(
        f"{where}the program has query modules (?P ?H ?U ?L), whose values the turtle sets "
        "between steps; expected a query callback: derive it with sylva.derive or "
        "sylva.grow, or pass query=sylva.plant.turtle_query(program)"
    )


# --------------------------------------------------------------------------- open L-systems
#: The communication module of open L-systems (Měch & Prusinkiewicz 1996).
COMMUNICATION = "?E"

#: The environments a program may name (``environment = light`` in ``.lsys``) and the
#: options each takes, with their defaults (numbers, or a word for ``shape``).  Their code
#: lives with what they sense: :mod:`sylva.environments` (light, obstacle, density) and
#: :mod:`sylva.world.environment` (world); :mod:`sylva.lsystem` only knows their names.
ENVIRONMENTS: dict[str, dict[str, float | str]] = {
    "light": {"voxel": 1.0, "shadow": 1.0, "falloff": 2.0, "depth": 4.0, "full": 1.0,
              "cone": 90.0, "leaves": 1.0, "segments": 0.0},
    "obstacle": {"shape": "sphere", "x": 0.0, "y": 0.0, "z": 0.0, "r": 1.0, "sx": 1.0,
                 "sy": 1.0, "sz": 1.0},
    "density": {"radius": 1.0, "planar": 0.0},
    "world": {"seed": 1.0, "x": 0.0, "z": 0.0, "size": 32.0, "scale": 1.0, "rock_x": 0.0,
              "rock_y": 0.0, "rock_z": 0.0, "rock_r": 0.0},
}  # fmt: skip
#: The shapes of the obstacle environment.
OBSTACLE_SHAPES = ("sphere", "box", "ellipsoid", "cylinder")


@dataclass(frozen=True)
class Communication:
    """What an environment receives: every ``?E`` module of a word at once.

    Attributes
    ----------
    step : int
        The derivation step just made (0 for the axiom).
    word : ModuleString
        The whole word.
    index : int64[m]
        The positions of its ``?E`` modules, in word order.
    params : float64[m, k]
        Their parameters (``k`` is the most any of them has; NaN past a module's own).
    counts : int64[m]
        How many parameters each has.
    positions : float64[m, 3] or None
        The turtle's position at each (None when the derivation has no turtle).
    frames : float64[m, 3, 3] or None
        The turtle's heading, left and up vectors at each (rows H, L, U).
    organs : float64[n, 3] or None
        Points of the plant's organs, for an environment that asks for them (the light's
        shadow casters): each leaf's centre, then each segment's midpoint; None unless the
        ``locate`` callback gives them (:func:`sylva.plant.turtle_locate` with ``organs``).
    organ_kinds : int8[n] or None
        0 for a leaf, 1 for a segment.
    """

    step: int
    word: ModuleString
    index: np.ndarray
    params: np.ndarray
    counts: np.ndarray
    positions: np.ndarray | None = None
    frames: np.ndarray | None = None
    organs: np.ndarray | None = None
    organ_kinds: np.ndarray | None = None

    def __len__(self) -> int:
        return int(self.index.size)

    @property
    def heading(self) -> np.ndarray | None:
        """``float64[m, 3]``: the turtle's heading at each module (None without a turtle)."""
        return None if self.frames is None else self.frames[:, 0]


#: ``environment(communication) -> float64[m, k]`` (or ``[m]`` when ``k`` is 1): the new
#: parameters of the ``?E`` modules, one row per module, one column per parameter.
Environment = Callable[[Communication], np.ndarray]
#: ``locate(word, index) -> (positions float64[m, 3], frames float64[m, 3, 3])``
#: ``locate(word, index) -> (positions, frames)`` of the ``?E`` modules at ``index``, or
#: ``(positions, frames, organs, organ_kinds)`` (see :class:`Communication`).
Locate = Callable[[ModuleString, np.ndarray], tuple[np.ndarray, ...]]


def has_communication(program: Program) -> bool:
    """True when a ``?E`` module appears in the axiom or in a successor of ``program``."""
    return COMMUNICATION in _written(program)


def communication_index(word: ModuleString) -> np.ndarray:
    """``int64[m]``: the positions of the ``?E`` modules in ``word``."""
    i = word.alphabet.get(COMMUNICATION)
    if i < 0:
        return np.zeros(0, np.int64)
    return np.flatnonzero(word.ids == i).astype(np.int64)


def environment_name(environment: object) -> str:
    """How an error names ``environment``: its ``name``, else its function name."""
    name = getattr(environment, "name", None) or getattr(environment, "__name__", None)
    return repr(str(name)) if name else type(environment).__name__


def apply_environment(
    word: ModuleString, environment: Environment, step: int, locate: Locate | None = None
) -> ModuleString:
    """``word`` with the parameters of its ``?E`` modules set by ``environment``.

    The environment gets a :class:`Communication` of every ``?E`` module of the word and
    returns their new parameters, ``float64[m, k]`` (a module keeps its own number of
    parameters: columns past it are dropped).  An environment that raises, or answers
    with the wrong shape or a value that is not finite, is a
    :class:`~sylva.errors.SylvaError` naming the environment, the step and the module.

    Examples
    --------
    >>> from sylva.lsystem import loads
    >>> w = ModuleString.from_text("A ?E(1, 0) B ?E(2, 0)")
    >>> str(apply_environment(w, lambda c: c.params * [1, 10], 1))
    'A"?E"(1,0)B"?E"(2,0)'
    >>> str(apply_environment(w, lambda c: c.params[:, ::-1] + [5, 0], 1))
    'A"?E"(5,1)B"?E"(5,2)'
    """
    index = communication_index(word)
    if index.size == 0:
        return word
    offsets = word.offsets
    start = offsets[index]
    counts = (offsets[index + 1] - start).astype(np.int64)
    k = int(counts.max(initial=0))
    params = np.full((index.size, k), np.nan)
    for j in range(k):
        has = counts > j
        params[has, j] = word.values[start[has] + j]
    positions = frames = organs = kinds = None
    if locate is not None:
        got = locate(word, index)
        positions, frames = got[0], got[1]
        if len(got) > 2:
            organs, kinds = got[2], got[3]
    comm = Communication(step, word, index, params, counts, positions, frames, organs, kinds)
    who = environment_name(environment)
    first = f"the first at word position {int(index[0])}"
    try:
        out = environment(comm)
    except SylvaError as exc:
        raise SylvaError(f"step {step}: environment {who}: {exc}") from exc
    except Exception as exc:  # the user's environment: say where it failed
        raise SylvaError(
            f"step {step}: environment {who} raised {type(exc).__name__}: {exc} (while "
            f"answering {index.size} ?E module(s), {first})"
        ) from exc
    try:
        values = np.asarray(out, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise SylvaError(
            f"step {step}: environment {who} returned {type(out).__name__}; expected float "
            f"values of shape ({index.size}, {k}) for the ?E modules ({first})"
        ) from exc
    if values.ndim == 1 and k == 1 and values.shape[0] == index.size:
        values = values[:, None]
    if values.shape != (index.size, k):
        raise SylvaError(
            f"step {step}: environment {who} returned shape {values.shape}; expected "
            f"({index.size}, {k}): one row per ?E module ({index.size} in the word, {first}) "
            f"and one column per parameter (at most {k})"
        )
    used = np.arange(k)[None, :] < counts[:, None]
    bad = used & ~np.isfinite(values)
    if bad.any():
        r, c = np.argwhere(bad)[0]
        raise SylvaError(
            f"step {step}: environment {who} gave {values[r, c]} to parameter {c + 1} of the "
            f"?E module at word position {int(index[r])}; expected finite numbers"
        )
    new = word.values.copy()
    for j in range(k):
        has = counts > j
        new[start[has] + j] = values[has, j]
    return ModuleString(word.alphabet, word.ids, offsets, new)


def missing_environment(program: Program) -> SylvaError:
    """The error for a program with ``?E`` modules derived without an environment."""
    where = ""
    for rule in program.rules:
        if any(m.symbol == COMMUNICATION for m in rule.successor) and rule.span is not None:
            where = f"{rule.span.filename or '<string>'}:{rule.span.line}:{rule.span.column}: "
            break
    names = ", ".join(ENVIRONMENTS)
    return SylvaError(
        f"{where}the program has communication modules ?E, whose values an environment sets "
        f"between steps; expected an environment: write 'environment = light' (or {names}) "
        "in the program, pass environment= to sylva.grow / sylva.derive, or --environment "
        "on the command line"
    )


_SPEC = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*(?:\((.*)\))?\s*\Z", re.DOTALL)
_OPTION = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*=\s*([^,=]*?)\s*(?:,|\Z)")
_NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\Z")


class EnvironmentSpecError(ValueError):
    """A bad ``environment = …`` value; ``column`` is 0-based in the value's text."""

    def __init__(self, message: str, column: int = 0) -> None:
        super().__init__(message)
        self.column = column


def parse_environment(text: str) -> tuple[str, dict[str, float | str]]:
    """Read ``name`` or ``name(option = value, …)``, an environment a program names.

    The name is one of :data:`ENVIRONMENTS`; each option is one of its options, with a
    number (or, for ``shape``, a word).  Options left out keep their defaults.

    >>> parse_environment("obstacle(shape = box, y = 2, sx = 3)")[1]["shape"]
    'box'
    >>> parse_environment("light")[1]["depth"]
    4.0
    """
    m = _SPEC.match(text)
    names = ", ".join(ENVIRONMENTS)
    if not m:
        raise EnvironmentSpecError(
            f"expected an environment name ({names}), optionally with options in "
            "parentheses, e.g. 'light(voxel = 0.5)'"
        )
    name, inner = m.group(1), m.group(2)
    if name not in ENVIRONMENTS:
        raise EnvironmentSpecError(f"unknown environment {name!r}; expected {names}",
                                   m.start(1))  # fmt: skip
    options = dict(ENVIRONMENTS[name])
    if inner is None or not inner.strip():
        return name, options
    base = m.start(2)
    pos = 0
    while pos < len(inner):
        o = _OPTION.match(inner, pos)
        if not o:
            raise EnvironmentSpecError(
                "expected 'option = value' separated by commas", base + pos
            )
        key, value = o.group(1), o.group(2)
        if key not in options:
            raise EnvironmentSpecError(
                f"the {name} environment has no option {key!r}; expected "
                + ", ".join(options),
                base + o.start(1),
            )
        if isinstance(options[key], str):
            if not re.fullmatch(r"[A-Za-z_]+", value):
                raise EnvironmentSpecError(f"{key!r} expected a word, got {value!r}",
                                           base + o.start(2))  # fmt: skip
            if key == "shape" and value not in OBSTACLE_SHAPES:
                raise EnvironmentSpecError(
                    f"unknown shape {value!r}; expected " + ", ".join(OBSTACLE_SHAPES),
                    base + o.start(2),
                )
            options[key] = value
        else:
            if not _NUMBER.match(value):
                raise EnvironmentSpecError(f"{key!r} expected a number, got {value!r}",
                                           base + o.start(2))  # fmt: skip
            options[key] = float(value)
        pos = o.end()
    return name, options
