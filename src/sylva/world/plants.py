"""Plant species of the world, their models, and the plant caches.

A :class:`Species` says how to grow one kind of plant: an engine-format L-system run
through seed 004's executor (:func:`sylva.world.executor.grow`) with its parameters
(Appendix A.4 table: angleVar, derivations, scale range), the textures of its output buffers
(buffer 0 trunk, 1 leaves; the last texture serves further buffers), or a built-in
block model (cactus, grass tuft), or **any sylva L-system** (``.lsys``, classic or engine
text; :meth:`Species.from_lsystem`) meshed by :mod:`sylva.geometry.build`.

:class:`PlantLibrary` makes the models on demand and remembers them:

* **shrubs** come from seed 004's shrub cache: ``shrub_count`` entries per shrub species,
  entry ``i`` at growth stage ``i mod 3`` (2/3/4 derivations, scale 0.10/0.15/0.20), salts
  from the chain ``hash1d(seed), hash1d(hash1d(seed)), …``; a shrub at ``(x, z)`` takes
  entry ``floor(hash2D(x, z)/UINT_MAX · cache_size)`` (:meth:`PlantLibrary.shrub_entry`);
* **trees** take ``salt = hash2D(x, z)`` (seed 004), or, with ``tree_variants = V``, one of
  ``V`` individuals per species picked the same way as shrubs so they can be instanced.

Every model is a :class:`~sylva.geometry.mesh.Mesh` in plant coordinates (base at the
origin, +Y up) whose material ids index the world's tile materials
(:func:`sylva.world.atlas.tile_materials`).

Examples
--------
>>> lib = PlantLibrary(seed=4)
>>> k = lib.shrub_entry(10, 20)
>>> k == lib.shrub_entry(10, 20) and 0 <= k < lib.cache_size
True
>>> SPECIES["acacia"].derivations, SPECIES["acacia"].angle_var
(4, 0.15)
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np

from ..errors import SylvaError
from ..geometry.build import build_mesh
from ..geometry.mesh import Material, Mesh, Scene
from ..lsystem import Program, derive, load, load_all
from ..turtle import interpret
from .atlas import tile_materials
from .blocks import texture_id
from .executor import PlantBlocks, grow
from .hashing import UINT_MAX, hash1d, hash2d

__all__ = [
    "SPECIES",
    "PlantLibrary",
    "Species",
    "blocks_mesh",
    "engine_program",
    "grass_tuft_mesh",
]


def _data(name: str) -> Path:
    return Path(str(resources.files("sylva.data") / "world" / name))


@functools.lru_cache(maxsize=32)
def engine_program(source: str, index: int = 0) -> Program:
    """An engine-format L-system: ``"acacia"`` (the thesis's, from the built-in examples),
    or the ``index``-th system of a file in ``sylva/data/world`` (``"shrubs"``, ``"tree"``,
    ``"jungle"``) or at a path."""
    if source == "acacia":
        from ..data import find

        return load(find("acacia").path, dialect="engine")
    path = _data(f"{source}.txt")
    if not path.is_file():
        path = Path(source)
    if not path.is_file():
        raise SylvaError(f"no engine-format L-system {source!r}: expected a name or a file")
    programs = load_all(path, dialect="engine")
    if not 0 <= index < len(programs):
        raise SylvaError(
            f"{source!r} holds {len(programs)} L-systems; index {index} is out of range"
        )
    return programs[index]


@dataclass(frozen=True)
class Species:
    """How to grow one kind of plant.

    Parameters
    ----------
    name : str
    kind : {"engine", "cactus", "grass", "lsystem", "tree"}
        Seed 004's executor on an engine-format system, a built-in block model, any
        sylva L-system meshed with branches and leaves, or a :mod:`sylva.tree` species.
    source, index : str, int
        The engine-format system (see :func:`engine_program`), for ``"lsystem"`` a file
        path, for ``"tree"`` a species name of :func:`sylva.tree.species_names`.
    textures : tuple of str
        Atlas tile of each output buffer (the last one serves higher buffers).
    derivations : int
        Base derivation count (the growth stage for shrubs).
    min_scale, max_scale : float
        Block scale range.
    derivation_var : int or None
        ``ScaleDerivations`` range (3 gives 3–5 derivations for trees).
    angle_var : float
    optimize : bool
        Drop branch blocks hidden in leaf blocks.
    height : float
        For ``"lsystem"`` and ``"tree"`` plants: the height the model is scaled to, in
        blocks (a ``"tree"`` keeps its age in ``max_scale``).
    """

    name: str
    kind: str = "engine"
    source: str = ""
    index: int = 0
    textures: tuple[str, ...] = ("bark", "leaves")
    derivations: int = 3
    min_scale: float = 1.0
    max_scale: float | None = None
    derivation_var: int | None = None
    angle_var: float = 0.2
    optimize: bool = True
    height: float = 6.0

    @classmethod
    def from_lsystem(cls, name: str, path, *, height: float = 6.0,
                     derivations: int | None = None) -> Species:  # fmt: skip
        """Any sylva L-system file as a plant (meshed tubes and leaves, scaled to ``height``)."""
        p = Path(path)
        if not p.is_file():
            raise SylvaError(f"no L-system file {str(p)!r}")
        return cls(name, kind="lsystem", source=str(p), height=float(height),
                   derivations=-1 if derivations is None else int(derivations))  # fmt: skip

    @classmethod
    def from_tree(cls, name: str, species: str, *, height: float = 8.0,
                  age: float | None = None) -> Species:  # fmt: skip
        """A :mod:`sylva.tree` species (``"black_oak"``, ``"hazel_shrub"`` …) grown to ``age``
        (default: the species' own) and scaled to ``height`` blocks."""
        return cls(name, kind="tree", source=species, height=float(height),
                   max_scale=None if age is None else float(age))  # fmt: skip

    def program(self) -> Program:
        if self.kind == "engine":
            return engine_program(self.source, self.index)
        if self.kind == "lsystem":
            return load(self.source)
        raise SylvaError(f"species {self.name!r} is a built-in model, not an L-system")

    def blocks(self, salt: int, seed: int = 0, derivations: int | None = None,
               scale: float | None = None) -> PlantBlocks:  # fmt: skip
        """The blocks of one individual (``"engine"`` and ``"cactus"`` species)."""
        if self.kind == "cactus":
            h = 3 if salt % 4 else 2
            s = 0.8
            c = np.array([[0.0, s / 2 + i * s, 0.0] for i in range(h)], np.float32)
            return PlantBlocks(c, np.full(h, s, np.float32), np.zeros(h, np.int32), 0, s)
        if self.kind != "engine":
            raise SylvaError(f"species {self.name!r} has no blocks")
        if derivations is not None:
            return grow(self.program(), salt, derivations=derivations,
                        min_scale=self.min_scale if scale is None else scale,
                        angle_var=self.angle_var, optimize=self.optimize, seed=seed)  # fmt: skip
        return grow(self.program(), salt, derivations=self.derivations,
                    min_scale=self.min_scale, max_scale=self.max_scale,
                    derivation_var=self.derivation_var, angle_var=self.angle_var,
                    optimize=self.optimize, seed=seed)  # fmt: skip


#: The species of the world (seed 004 Appendix A.4 parameters).
SPECIES: dict[str, Species] = {
    "acacia": Species("acacia", source="acacia", textures=("bark_orange", "leaves_orange"),
                      derivations=4, min_scale=1.0, angle_var=0.15),
    "oak": Species("oak", source="tree", textures=("bark", "leaves"), derivations=3,
                   min_scale=0.7, max_scale=1.0, derivation_var=3, angle_var=0.1),
    "birch": Species("birch", source="tree", textures=("bark_white", "leaves_birch"),
                     derivations=3, min_scale=0.7, max_scale=1.0, derivation_var=3,
                     angle_var=0.1),
    "jungle": Species("jungle", source="jungle", index=0, textures=("bark", "leaves_jungle"),
                      derivations=3, min_scale=0.35, max_scale=0.5, derivation_var=3,
                      angle_var=0.1),
    "baobab": Species("baobab", source="jungle", index=1,
                      textures=("bark_orange", "leaves_jungle"), derivations=3,
                      min_scale=0.35, max_scale=0.5, derivation_var=3, angle_var=0.1),
    "shrub_a": Species("shrub_a", source="shrubs", index=0, textures=("bark", "leaves_shrub"),
                       derivations=2, min_scale=0.10, angle_var=0.2),
    "shrub_b": Species("shrub_b", source="shrubs", index=1, textures=("bark", "leaves_shrub"),
                       derivations=2, min_scale=0.10, angle_var=0.2),
    "cactus": Species("cactus", kind="cactus", textures=("cactus",)),
    "grass": Species("grass", kind="grass", textures=("grass_tuft",)),
}  # fmt: skip

SHRUBS = ("shrub_a", "shrub_b")
#: Growth stages of the shrub cache: (derivations, scale) for stage 0, 1, 2 (§4.11).
SHRUB_STAGES = ((2, 0.10), (3, 0.15), (4, 0.20))


# ------------------------------------------------------------------------- meshes
_FACES = np.array(  # normal, u axis, v axis (u x v = normal), seed 004 cube faces
    [[[1, 0, 0], [0, 0, -1], [0, 1, 0]], [[-1, 0, 0], [0, 0, 1], [0, 1, 0]],
     [[0, 1, 0], [1, 0, 0], [0, 0, -1]], [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
     [[0, 0, 1], [1, 0, 0], [0, 1, 0]], [[0, 0, -1], [-1, 0, 0], [0, 1, 0]]], np.float64,
)  # fmt: skip
_CORNERS = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], np.float64)


def _cube_template():
    v = 0.5 * (_FACES[:, None, 0] + _CORNERS[None, :, 0:1] * _FACES[:, None, 1]
               + _CORNERS[None, :, 1:2] * _FACES[:, None, 2])  # fmt: skip
    n = np.repeat(_FACES[:, 0], 4, axis=0)
    uv = np.tile((_CORNERS + 1) / 2, (6, 1))
    t = np.array([[0, 1, 2], [0, 2, 3]])
    tris = (np.arange(6)[:, None, None] * 4 + t[None]).reshape(-1, 3)
    return v.reshape(-1, 3), n, uv, tris


_CUBE_V, _CUBE_N, _CUBE_UV, _CUBE_T = _cube_template()


def blocks_mesh(center, size, material_ids, *, materials: list[Material] | None = None,
                name: str = "plant") -> Mesh:  # fmt: skip
    """Axis-aligned cubes as one mesh, with faces shared by touching equal cubes removed.

    Parameters
    ----------
    center : float[n, 3]
    size : float[n]
    material_ids : int[n]
        Material (tile) of each cube.
    materials : list of Material, optional
        Default: :func:`sylva.world.atlas.tile_materials`.

    Returns
    -------
    Mesh
        Up to 12 triangles per cube, UVs 0..1 per face.
    """
    c = np.asarray(center, np.float64).reshape(-1, 3)
    s = np.asarray(size, np.float64).reshape(-1)
    mids = np.asarray(material_ids, np.int32).reshape(-1)
    n = c.shape[0]
    keep = np.ones((n, 6), np.bool_)
    if n > 1:
        # a face is hidden when an equal cube of the same material sits right against it
        key = {}
        q = np.round(c / s[:, None] * 2.0).astype(np.int64)
        for i in range(n):
            key[(q[i, 0], q[i, 1], q[i, 2], round(float(s[i]) * 4096), int(mids[i]))] = i
        for f in range(6):
            d = _FACES[f, 0].astype(np.int64) * 2
            for i in range(n):
                k = (q[i, 0] + d[0], q[i, 1] + d[1], q[i, 2] + d[2], round(float(s[i]) * 4096),
                     int(mids[i]))  # fmt: skip
                j = key.get(k)
                if j is not None and np.allclose(c[j] - c[i], _FACES[f, 0] * s[i], atol=1e-4):
                    keep[i, f] = False
    faces = np.argwhere(keep)  # (cube, face)
    m = faces.shape[0]
    cube, face = faces[:, 0], faces[:, 1]
    corner = np.arange(4)
    vidx = face[:, None] * 4 + corner[None, :]
    verts = c[cube][:, None, :] + _CUBE_V[vidx] * s[cube][:, None, None]
    normals = _CUBE_N[vidx]
    uvs = _CUBE_UV[vidx]
    t = np.array([[0, 1, 2], [0, 2, 3]])
    tris = (np.arange(m)[:, None, None] * 4 + t[None]).reshape(-1, 3)
    return Mesh(verts.reshape(-1, 3), tris, normals=normals.reshape(-1, 3),
                uvs=uvs.reshape(-1, 2), material_ids=np.repeat(mids[cube], 2),
                materials=list(materials if materials is not None else tile_materials()),
                name=name)  # fmt: skip


def grass_tuft_mesh(variant: int = 0, *, materials: list[Material] | None = None) -> Mesh:
    """A grass tuft: two crossed, double-sided quads (half a block tall, as in seed 004's
    grass block scaled 0.5), ``variant`` 0..3 changes height and spread."""
    h = 0.45 + 0.1 * (variant % 4)
    r = 0.35 + 0.05 * ((variant // 2) % 2)
    v = np.array([[-r, 0, -r], [r, 0, r], [r, h, r], [-r, h, -r],
                  [-r, 0, r], [r, 0, -r], [r, h, -r], [-r, h, r]], np.float64)  # fmt: skip
    uv = np.array([[0, 0], [1, 0], [1, 1], [0, 1]] * 2, np.float64)
    tris = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    nrm = np.array([[1, 0, -1]] * 4 + [[1, 0, 1]] * 4, np.float64) / np.sqrt(2.0)
    return Mesh(v, tris, normals=nrm, uvs=uv,
                material_ids=np.full(4, texture_id("grass_tuft"), np.int32),
                materials=list(materials if materials is not None else tile_materials()),
                name=f"grass_{variant}")  # fmt: skip


def _lsystem_mesh(sp: Species, salt: int, materials) -> Mesh:
    if sp.kind == "tree":
        from ..tree import Tree

        tree = Tree(sp.source, seed=int(salt) & 0x7FFFFFFF).grow(sp.max_scale)
        mesh = tree.scene().merged()
    else:
        program = sp.program()
        steps = sp.derivations if sp.derivations >= 0 else (program.steps or 4)
        word = derive(program, steps, seed=int(salt) & 0x7FFFFFFF)
        built = build_mesh(interpret(word, program))
        mesh = built.merged() if isinstance(built, Scene) else built
    lo, hi = mesh.bounds()
    height = float(hi[1] - lo[1]) or 1.0
    k = sp.height / height
    v = (mesh.vertices - np.array([(lo[0] + hi[0]) / 2, lo[1], (lo[2] + hi[2]) / 2])) * k
    # map the plant's own materials to tiles: leaves -> leaves, the rest -> bark
    tiles = np.array([texture_id(sp.textures[-1] if "leaf" in m.name.lower() else sp.textures[0])
                      for m in mesh.materials], np.int32)  # fmt: skip
    return Mesh(v, mesh.indices, normals=mesh.normals, uvs=mesh.uvs,
                material_ids=tiles[mesh.triangle_materials()], materials=list(materials),
                name=sp.name)  # fmt: skip


# ------------------------------------------------------------------------- library
@dataclass
class PlantLibrary:
    """Plant models on demand, cached by key.

    Parameters
    ----------
    seed : int
        The world seed (salt chains and the executor's hash seed).
    shrub_count : int
        Cache entries per shrub species.
    tree_variants : int or None
        Individuals per tree species; ``None``: one per position salt.
    species : dict, optional
        Species by name (default :data:`SPECIES`).
    """

    seed: int = 0
    shrub_count: int = 12
    tree_variants: int | None = 16
    species: dict[str, Species] = field(default_factory=lambda: dict(SPECIES))
    materials: list[Material] = field(default_factory=tile_materials)
    _models: dict[str, Mesh] = field(default_factory=dict, repr=False)
    _blocks: dict[str, PlantBlocks] = field(default_factory=dict, repr=False)

    @classmethod
    def for_config(cls, cfg) -> PlantLibrary:
        """The library of a :class:`~sylva.world.terrain.WorldConfig` (its seed, shrub
        count, tree variants and extra species)."""
        return cls(cfg.seed, cfg.shrub_count, cfg.tree_variants,
                   species={**SPECIES, **(cfg.species or {})})  # fmt: skip

    # ------------------------------------------------------------------ keys
    @property
    def cache_size(self) -> int:
        """Entries of the shrub cache (``shrub_count`` per shrub species)."""
        return self.shrub_count * len(SHRUBS)

    def shrub_salts(self) -> np.ndarray:
        """The salt chain of the shrub cache: int64[cache_size], starting at hash1d(seed)."""
        out = np.empty(self.cache_size, np.int64)
        s = hash1d(self.seed)
        for i in range(self.cache_size):
            out[i] = s
            s = hash1d(s)
        return out

    def shrub_entry(self, x, z):
        """Cache index of the shrub at column ``(x, z)``: ``floor(hash2D/UINT_MAX·size)``."""
        h = hash2d(np.asarray(x, np.int64), np.asarray(z, np.int64), seed=self.seed)
        idx = np.minimum((np.asarray(h, np.float64) / UINT_MAX * self.cache_size)
                         .astype(np.int64), self.cache_size - 1)  # fmt: skip
        return int(idx) if np.ndim(idx) == 0 else idx

    def shrub_key(self, entry: int) -> str:
        """Model key of shrub cache entry ``entry`` (species block, stage = i mod 3)."""
        return f"{SHRUBS[entry // self.shrub_count]}#{entry % self.shrub_count}"

    def tree_key(self, species: str, x: int, z: int) -> str:
        """Model key of a tree of ``species`` at column ``(x, z)``."""
        h = hash2d(int(x), int(z), seed=self.seed)
        if self.tree_variants is None:
            return f"{species}@{h}"
        return f"{species}#{min(int(h / UINT_MAX * self.tree_variants), self.tree_variants - 1)}"

    # ------------------------------------------------------------------ models
    def _salt(self, species: str, variant: int) -> int:
        return hash1d(hash2d(variant, sum(map(ord, species)), seed=self.seed))

    def blocks(self, key: str) -> PlantBlocks | None:
        """The blocks of a block-made model (None for meshed L-systems and grass)."""
        if key in self._blocks:
            return self._blocks[key]
        name, sep, rest = key.partition("#")
        if not sep:
            name, _, rest = key.partition("@")
        sp = self.species.get(name)
        if sp is None:
            raise SylvaError(f"unknown plant species {name!r} in model key {key!r}")
        if sp.kind not in ("engine", "cactus"):
            return None
        if "@" in key:
            blocks = sp.blocks(int(rest), self.seed)
        elif name in SHRUBS:
            entry = SHRUBS.index(name) * self.shrub_count + int(rest)
            d, s = SHRUB_STAGES[int(rest) % 3]
            blocks = sp.blocks(int(self.shrub_salts()[entry]), self.seed, derivations=d, scale=s)
        else:
            blocks = sp.blocks(self._salt(name, int(rest)), self.seed)
        self._blocks[key] = blocks
        return blocks

    def model(self, key: str) -> Mesh:
        """The mesh of the model ``key`` (``"oak#3"``, ``"shrub_b#7"``, ``"grass#2"``,
        ``"acacia@123456"`` …), in plant coordinates with its base at the origin."""
        if key in self._models:
            return self._models[key]
        name = key.partition("#")[0].partition("@")[0]
        sp = self.species.get(name)
        if sp is None:
            raise SylvaError(f"unknown plant species {name!r} in model key {key!r}")
        if sp.kind == "grass":
            mesh = grass_tuft_mesh(int(key.partition("#")[2] or 0), materials=self.materials)
        elif sp.kind in ("lsystem", "tree"):
            mesh = _lsystem_mesh(sp, self._salt(name, int(key.partition("#")[2] or 0)),
                                 self.materials)  # fmt: skip
        else:
            b = self.blocks(key)
            assert b is not None
            tex = np.array([texture_id(t) for t in sp.textures], np.int32)
            mids = tex[np.minimum(b.buffer, len(tex) - 1)]
            mesh = blocks_mesh(b.center, b.size, mids, materials=self.materials, name=key)
        self._models[key] = mesh
        return mesh
