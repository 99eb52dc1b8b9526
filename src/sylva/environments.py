"""The built-in environments of open L-systems: light, obstacle shapes, and the world's.

An open L-system (Měch & Prusinkiewicz 1996) talks to its environment through
communication modules ``?E(…)``: after every derivation step (and on the axiom) the word is
interpreted, the environment receives every ``?E`` module at once with the turtle's state
there (:class:`~sylva.lsystem.environment.Communication`) and writes their parameters, which
the next step's productions read.  Any function ``environment(communication) ->
float64[m, k]`` is an environment; these are the ones a program can name
(``environment = light`` in ``.lsys``, ``sylva render … --environment light``,
``sylva.grow(…, environment="light")``):

``light`` — :class:`Light`
    A shadow-propagation grid (Palubicki et al. 2009, "Self-organizing tree models for
    image synthesis", §4.2).  Each ``?E`` module is a bud that shades the voxels in a
    pyramid below it, and so does each leaf of the plant (and, when asked, each segment);
    a bud gets ``?E(q, vx, vy, vz)``: its light ``q`` in [0, 1] and the unit
    direction ``v`` of the least shaded neighbouring voxel ahead of it, so trees compete
    and turn to the light.
``obstacle`` — :class:`Obstacle`
    A shape (sphere, box, ellipsoid, vertical cylinder): ``?E(d, …)`` gets the signed
    distance ``d`` of the module to its surface (negative inside), for pruning to a hedge
    or topiary.
``density`` — :class:`Density`
    Crowding (Honda 1981, vlab's ``honda81`` environment program): ``?E(v, g)`` gets 1 where
    no other ``?E`` module of the same group ``g`` and at least the vigour ``v`` lies within
    ``radius`` of it, else 0, so branches stop where they would collide.
``world`` — :class:`sylva.world.environment.WorldEnvironment`
    The voxel terrain of :mod:`sylva.world`: ground height, blocks and biome, so roots and
    branches stop at the terrain and at rocks.

Examples
--------
>>> from sylva.lsystem import Derivation, loads
>>> from sylva.plant import turtle_locate
>>> p = loads("axiom = F(2)?E(0)\\n?E(d) : d < 0 -> F(1)?E(0)")
>>> d = Derivation(p, environment=Obstacle("sphere", r=3.5), locate=turtle_locate(p))
>>> str(d.advance(3))   # grows until it leaves the sphere of radius 3.5
'F(2)F(1)F(1)"?E"(0.5)'
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ._jit import lazy
from .errors import SylvaError
from .lsystem.ast import Program
from .lsystem.environment import (
    ENVIRONMENTS,
    OBSTACLE_SHAPES,
    Communication,
    Environment,
    EnvironmentSpecError,
    parse_environment,
)

K = lazy("sylva._light_kernels")

__all__ = ["Density", "Light", "Obstacle", "builtin", "resolve_environment"]


def _positions(comm: Communication, who: str) -> np.ndarray:
    if comm.positions is None:
        raise SylvaError(f"the {who} environment needs the turtle's positions: derive with "
                         "locate=sylva.plant.turtle_locate(program)")  # fmt: skip
    return comm.positions


class Light:
    """The light of Palubicki et al. (2009): a shadow-propagation grid over the buds.

    Space is cut into cubic voxels of edge ``voxel``.  Every ``?E`` module (a bud) adds
    ``shadow · falloff**-q`` to the voxels ``(x ± p, y − q, z ± p)`` for ``0 <= p <= q <=
    depth``, a pyramid below it, and so does every organ of the plant that casts shadow:
    each leaf (its centre) with the weight ``leaves`` (``leaves · shadow · falloff**-q``),
    each segment (its midpoint) with the weight ``segments``, as the paper fills the grid
    from the tree's organs.  A bud in a voxel of shadow ``s`` gets the light ``max(full −
    s + shadow, 0) / full`` (its own shadow does not count) and the direction of the least
    shaded of its 26 neighbouring voxels within ``cone`` degrees of its heading (the
    tree's perception cone; ties go to the one nearest the heading).

    Parameters
    ----------
    voxel, shadow, falloff, depth, full, cone : float
        The paper's voxel size, ``a``, ``b``, ``q_max`` and ``C``, and the half-angle of
        the cone (90: the half-space ahead).
    leaves, segments : float
        The shadow of a leaf and of a segment, as a multiple of a bud's (0: none; default
        1 and 0).

    Notes
    -----
    ``?E(q, vx, vy, vz)`` receives ``q`` and ``v``; a module with fewer parameters gets the
    first ones.  ``y`` is up.  Leaves and segments cast shadow when the derivation's
    ``locate`` gives the organs (:func:`sylva.plant.turtle_locate` with ``organs=True``,
    which every front end passes for this environment: :attr:`wants_organs`); with a
    plain ``locate`` only the buds do.

    Examples
    --------
    >>> import numpy as np
    >>> light = Light(shadow=1, falloff=2, depth=3)
    >>> light.light(np.array([[0.5, 0.5, 0.5], [0.5, 1.5, 0.5]]))   # the lower is shaded
    array([0.5, 1. ])
    """

    name = "light"

    def __init__(self, voxel: float = 1.0, shadow: float = 1.0, falloff: float = 2.0,
                 depth: float = 4, full: float = 1.0, cone: float = 90.0,
                 leaves: float = 1.0, segments: float = 0.0) -> None:  # fmt: skip
        for key, v in (("leaves", leaves), ("segments", segments)):
            if not (math.isfinite(v) and v >= 0):
                raise SylvaError(f"light: {key!r} must be a number >= 0, got {v}")
        self.leaves, self.segments = float(leaves), float(segments)
        for key, v in (("voxel", voxel), ("shadow", shadow), ("full", full)):
            if not (math.isfinite(v) and v > 0):
                raise SylvaError(f"light: {key!r} must be a positive number, got {v}")
        if not (math.isfinite(falloff) and falloff >= 1):
            raise SylvaError(f"light: 'falloff' must be a number >= 1, got {falloff}")
        if not (float(depth).is_integer() and 0 <= depth <= 64):
            raise SylvaError(f"light: 'depth' must be a whole number from 0 to 64, got {depth}")
        if not (math.isfinite(cone) and 0 <= cone <= 180):
            raise SylvaError(f"light: 'cone' must be an angle from 0 to 180 degrees, got {cone}")
        self.voxel, self.shadow, self.falloff = float(voxel), float(shadow), float(falloff)
        self.depth, self.full, self.cone = int(depth), float(full), float(cone)

    def _cells(self, positions: np.ndarray):
        cells = np.floor(np.asarray(positions, np.float64) / self.voxel).astype(np.int64)
        d = self.depth
        lo = cells.min(axis=0) - np.array([d, d, d])
        hi = cells.max(axis=0) + np.array([d, 0, d])
        shape = hi - lo + 1
        return cells - lo, shape

    @property
    def wants_organs(self) -> bool:
        """Whether leaves or segments cast shadow (the ``locate`` should give the organs)."""
        return self.leaves > 0.0 or self.segments > 0.0

    def grid(self, positions: np.ndarray, organs: np.ndarray | None = None,
             kinds: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
        """The shadow grid of buds at ``positions`` (``float64[m, 3]``) and of the
        ``organs`` (``float64[n, 3]``, of ``kinds`` 0 leaf / 1 segment), and the voxel
        index of each bud in it: ``(float64[nx, ny, nz], int64[m, 3])``."""
        positions = np.asarray(positions, np.float64).reshape(-1, 3)
        m = positions.shape[0]
        weights = np.ones(m)
        if organs is not None and len(organs):
            organs = np.asarray(organs, np.float64).reshape(-1, 3)
            kinds = np.zeros(len(organs), np.int8) if kinds is None else np.asarray(kinds)
            w = np.where(kinds == 0, self.leaves, self.segments)
            keep = (w > 0) & np.all(np.isfinite(organs), axis=1)
            positions = np.concatenate([positions, organs[keep]])
            weights = np.concatenate([weights, w[keep]])
        cells, shape = self._cells(positions)
        g = K.shadow_grid(cells, weights, int(shape[0]), int(shape[1]), int(shape[2]),
                          self.shadow, self.falloff, self.depth)  # fmt: skip
        return g, np.ascontiguousarray(cells[:m])

    def light(self, positions: np.ndarray, organs: np.ndarray | None = None,
              kinds: np.ndarray | None = None) -> np.ndarray:  # fmt: skip
        """``float64[m]``: the light of buds at ``positions`` (with the shadow of
        ``organs``, as in :meth:`grid`)."""
        return self.answer(np.asarray(positions, np.float64), None, organs, kinds)[:, 0]

    def answer(self, positions: np.ndarray, heading: np.ndarray | None,
               organs: np.ndarray | None = None,
               kinds: np.ndarray | None = None) -> np.ndarray:  # fmt: skip
        """``float64[m, 4]``: light and the least shaded direction of buds at
        ``positions`` heading along ``heading`` (``None``: every neighbour counts), in
        the shadow of the buds and of ``organs``."""
        m = positions.shape[0]
        if m == 0:
            return np.zeros((0, 4))
        g, cells = self.grid(positions, organs, kinds)
        if heading is None:
            heading = np.tile([0.0, 1.0, 0.0], (m, 1))
            cos_cone = -1.0
        else:
            cos_cone = math.cos(math.radians(self.cone))
        return K.light_at(g, cells, np.ascontiguousarray(heading, np.float64), self.full,
                          self.shadow, cos_cone)  # fmt: skip

    def __call__(self, comm: Communication) -> np.ndarray:
        pos = _positions(comm, "light")
        out = self.answer(pos, comm.heading, comm.organs, comm.organ_kinds)
        k = comm.params.shape[1]
        res = comm.params.copy()
        res[:, : min(k, 4)] = out[:, : min(k, 4)]
        return res + 0.0


def _sdf(shape: str, p: np.ndarray, r: float, size: np.ndarray) -> np.ndarray:
    if shape == "sphere":
        return np.linalg.norm(p, axis=1) - r
    if shape == "box":
        q = np.abs(p) - size
        return np.linalg.norm(np.maximum(q, 0), axis=1) + np.minimum(q.max(axis=1), 0)
    if shape == "ellipsoid":  # scaled-sphere bound: exact on the axes
        k = np.linalg.norm(p / size, axis=1)
        return (k - 1.0) * size.min()
    # cylinder about +y, radius r, half height sy
    d = np.stack([np.hypot(p[:, 0], p[:, 2]) - r, np.abs(p[:, 1]) - size[1]], axis=1)
    return np.linalg.norm(np.maximum(d, 0), axis=1) + np.minimum(d.max(axis=1), 0)


class Obstacle:
    """A shape the plant is clipped to: ``?E(d)`` gets the signed distance to its surface.

    Parameters
    ----------
    shape : {"sphere", "box", "ellipsoid", "cylinder"}
        A sphere of radius ``r``; a box of half sizes ``sx, sy, sz``; an ellipsoid of
        semi-axes ``sx, sy, sz``; a cylinder about the ``y`` axis of radius ``r`` and half
        height ``sy``.
    x, y, z : float
        The centre.

    Notes
    -----
    The distance is negative inside, so ``?E(d) < A : d > 0 -> %`` cuts what grows out:
    a hedge from a box, a topiary from a sphere.  The first parameter is set; the others
    keep their values.
    """

    name = "obstacle"

    def __init__(self, shape: str = "sphere", *, x: float = 0.0, y: float = 0.0,
                 z: float = 0.0, r: float = 1.0, sx: float = 1.0, sy: float = 1.0,
                 sz: float = 1.0) -> None:  # fmt: skip
        if shape not in OBSTACLE_SHAPES:
            raise SylvaError(f"unknown obstacle shape {shape!r}; expected "
                             + ", ".join(OBSTACLE_SHAPES))  # fmt: skip
        for key, v in (("r", r), ("sx", sx), ("sy", sy), ("sz", sz)):
            if not (math.isfinite(v) and v > 0):
                raise SylvaError(f"obstacle: {key!r} must be a positive number, got {v}")
        self.shape = shape
        self.centre = np.array([x, y, z], np.float64)
        self.r = float(r)
        self.size = np.array([sx, sy, sz], np.float64)

    def distance(self, positions: np.ndarray) -> np.ndarray:
        """``float64[m]``: the signed distance of ``positions`` to the surface."""
        p = np.asarray(positions, np.float64).reshape(-1, 3) - self.centre
        return _sdf(self.shape, p, self.r, self.size)

    def __call__(self, comm: Communication) -> np.ndarray:
        res = comm.params.copy()
        if res.shape[1]:
            res[:, 0] = self.distance(_positions(comm, "obstacle"))
        return res + 0.0


class Density:
    """Crowding: a bud may grow on unless another as vigorous is within ``radius``.

    Honda's (1981) model of a tree's branches, as vlab's environment program ``honda81``
    answers it: every ``?E(v, g)`` module is a bud of vigour ``v`` in group ``g`` (0 when
    the module has one parameter); it gets ``1`` when no other bud of the same group with a
    vigour ``>= v`` lies within ``radius`` of it, else ``0`` (the first parameter; the
    others keep their values).  A bud stopped by a weaker one grows on.

    Parameters
    ----------
    radius : float
        The distance within which two buds collide.
    planar : bool
        Measure the distance in the ``x``-``z`` plane only (``honda81`` without its ``3d
        case: on``), not in space.

    Examples
    --------
    >>> import numpy as np
    >>> Density(radius=1).free(np.array([[0.0, 0, 0], [0.5, 0, 0], [3, 0, 0]]),
    ...                        np.array([1.0, 2.0, 1.0]))   # the first is crowded out
    array([0., 1., 1.])
    """

    name = "density"

    def __init__(self, radius: float = 1.0, planar: float = 0.0) -> None:
        if not (math.isfinite(radius) and radius >= 0):
            raise SylvaError(f"density: 'radius' must be a number >= 0, got {radius}")
        self.radius = float(radius)
        self.planar = bool(planar)

    def free(self, positions: np.ndarray, vigour: np.ndarray,
             group: np.ndarray | None = None) -> np.ndarray:  # fmt: skip
        """``float64[m]``: 1 for the buds at ``positions`` that may grow on, 0 for the
        crowded ones."""
        from scipy.spatial import cKDTree

        p = np.asarray(positions, np.float64).reshape(-1, 3)
        out = np.ones(p.shape[0])
        if p.shape[0] < 2:
            return out
        if self.planar:
            p = p[:, [0, 2]]
        v = np.asarray(vigour, np.float64)
        g = np.zeros(p.shape[0]) if group is None else np.asarray(group, np.float64)
        # honda81 compares squared distances <= radius**2: pairs at the radius collide
        pairs = cKDTree(p).query_pairs(self.radius * (1 + 1e-12), output_type="ndarray")
        if pairs.size:
            i, j = pairs[:, 0], pairs[:, 1]
            d2 = ((p[i] - p[j]) ** 2).sum(axis=1)
            same = (g[i] == g[j]) & (d2 <= self.radius**2)
            out[i[same & (v[i] <= v[j])]] = 0.0
            out[j[same & (v[j] <= v[i])]] = 0.0
        return out

    def __call__(self, comm: Communication) -> np.ndarray:
        res = comm.params.copy()
        if res.shape[1] == 0:
            return res
        pos = _positions(comm, "density")
        group = np.where(comm.counts > 1, res[:, 1], 0.0) if res.shape[1] > 1 else None
        res[:, 0] = self.free(pos, np.nan_to_num(res[:, 0]), group)
        return res + 0.0


def builtin(name: str, options: dict | None = None) -> Environment:
    """The built-in environment ``name`` (of
    :data:`~sylva.lsystem.environment.ENVIRONMENTS`) with ``options``."""
    if name not in ENVIRONMENTS:
        raise SylvaError(f"unknown environment {name!r}; expected " + ", ".join(ENVIRONMENTS))
    opts = dict(ENVIRONMENTS[name])
    opts.update(options or {})
    if name == "light":
        return Light(**opts)  # type: ignore[arg-type]
    if name == "obstacle":
        shape = str(opts.pop("shape"))
        return Obstacle(shape, **opts)  # type: ignore[arg-type]
    if name == "density":
        return Density(**opts)  # type: ignore[arg-type]
    from .world.environment import WorldEnvironment

    return WorldEnvironment.from_options(opts)


def resolve_environment(
    environment: str | Callable | None, program: Program | None = None
) -> Environment | None:
    """The environment to derive ``program`` with.

    ``environment`` is a name with options (``"light(voxel = 0.5)"``, as the ``.lsys``
    directive writes it), a callable (returned as it is), or None for the program's own
    ``environment = …`` (None when it names none).  A program with ``?E`` modules and no
    environment is an error when derived (:class:`~sylva.lsystem.Derivation`).
    """
    if environment is None:
        if program is None:
            return None
        spec = program.settings.get("environment")
        if spec is None:
            return None
        environment = str(spec)
    if callable(environment):
        return environment
    if not isinstance(environment, str):
        raise SylvaError(
            f"environment: expected a name ({', '.join(ENVIRONMENTS)}) or a function of a "
            f"Communication, got {type(environment).__name__}"
        )
    try:
        name, options = parse_environment(environment)
    except EnvironmentSpecError as exc:
        raise SylvaError(f"environment {environment!r}: {exc}") from None
    return builtin(name, options)

