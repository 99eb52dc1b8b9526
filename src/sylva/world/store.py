"""The world store: Zarr arrays, Parquet tables, GLB models and a JSON manifest in a folder.

A store written by :meth:`sylva.world.World.generate` (or ``sylva world -o world.zarr``)::

    world.zarr/
      zarr.json            the Zarr v3 group
      voxels/              uint8 [x, y, z]  one Zarr chunk per world chunk (s × height × s)
      height/ biome/       int32 / uint8 [x, z], chunks s × s (height −1: not written yet)
      humidity/ temperature/
      plants/b_CX_CZ.parquet   the plant instances of a block of chunks: model, x, y, z,
                               yaw, scale, biome, stage, column_x, column_z, cx, cz
      skin/b_CX_CZ.parquet     the greedy-merged skin quads of those chunks (cx, cz, and
                               :data:`~sylva.world.meshing.QUAD_FIELDS`)
      done/b_CX_CZ.json        written last: the block is complete (its chunks' counts)
      models/KEY.glb           every plant model the world uses (when asked)
      textures/                the block texture tiles the models use
      manifest.json            config, size, origin, versions; "complete" once all is done

The arrays cover whole chunks: index 0 is the first column of the world's first chunk,
so world chunks and Zarr chunks coincide and no two tasks write one Zarr chunk.  Every
file is written beside its target and renamed (Zarr's local store does so too, and sylva
writes the Parquet and JSON files through :mod:`sylva._atomic`), so a reader sees a chunk
either whole or not at all, and a block counts only once its ``done`` file exists:
:meth:`WorldStore.missing` lists the blocks an interrupted run still owes and
``generate(..., resume=True)`` writes only those.

:func:`open_world` (``sylva.world.open``) reads a store in pieces:
``open_world(path)[x0:x1, z0:z1]`` is a :class:`Region` that reads only the Zarr chunks and
Parquet files it overlaps.

Examples
--------
>>> import tempfile
>>> from sylva.world import World, WorldConfig
>>> d = tempfile.mkdtemp()
>>> store = World(WorldConfig(seed=3, chunk_size=8), size=(16, 8)).generate(d + "/w.zarr")
>>> region = open_world(d + "/w.zarr")[4:12, 0:8]
>>> region.height.shape, region.voxels.shape
((8, 8), (8, 96, 8))
>>> store.complete, store.missing()
(True, [])
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Iterator
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from .._atomic import atomic_path, atomic_write, make_folder
from ..errors import SylvaError
from ..geometry.mesh import Material, Mesh, Scene
from .biomes import BIOME_COLORS, Biome
from .chunks import Chunk
from .meshing import QUAD_FIELDS, quads_to_mesh
from .plants import SHRUBS, PlantLibrary, Species
from .terrain import WorldConfig
from .vegetation import Placement

__all__ = ["FORMAT", "Instances", "Region", "WorldStore", "biome_image", "expand_instances",
           "open_world"]  # fmt: skip

#: The ``format`` field of a store's manifest, and its version.
FORMAT = ("sylva-world", 1)

_FIELDS = {"height": ("int32", -1), "humidity": ("uint8", 0), "temperature": ("uint8", 0),
           "biome": ("uint8", 0)}  # fmt: skip


@dataclass
class Instances:
    """Copies of one plant model: ``translation`` float32[k, 3], ``yaw`` float32[k]."""

    key: str
    translation: np.ndarray
    yaw: np.ndarray

    def __len__(self) -> int:
        return int(self.translation.shape[0])

    def rotation(self) -> np.ndarray:
        """Unit quaternions ``(x, y, z, w)`` about +Y: float32[k, 4]."""
        q = np.zeros((len(self), 4), np.float32)
        q[:, 1] = np.sin(self.yaw / 2.0)
        q[:, 3] = np.cos(self.yaw / 2.0)
        return q


def expand_instances(mesh: Mesh, inst: Instances) -> Mesh:
    """One mesh with a transformed copy of ``mesh`` per instance (for rasterisers that do
    not instance)."""
    k = len(inst)
    c, s = np.cos(inst.yaw)[:, None], np.sin(inst.yaw)[:, None]
    v = mesh.vertices.astype(np.float64)[None]
    x = c * v[..., 0] + s * v[..., 2]
    z = -s * v[..., 0] + c * v[..., 2]
    verts = np.stack([x, np.broadcast_to(v[..., 1], x.shape), z], -1)
    verts = verts + inst.translation[:, None, :]
    n = mesh.normals.astype(np.float64)[None]
    nx = c * n[..., 0] + s * n[..., 2]
    nz = -s * n[..., 0] + c * n[..., 2]
    normals = np.stack([nx, np.broadcast_to(n[..., 1], nx.shape), nz], -1)
    idx = mesh.indices.astype(np.int64)[None] + (np.arange(k) * mesh.n_vertices)[:, None, None]
    return Mesh(verts.reshape(-1, 3), idx.reshape(-1, 3), normals=normals.reshape(-1, 3),
                uvs=None if mesh.uvs is None else np.tile(mesh.uvs, (k, 1)),
                material_ids=np.tile(mesh.triangle_materials(), k),
                materials=list(mesh.materials), name=f"{mesh.name}_x{k}")  # fmt: skip


def biome_image(biomes: np.ndarray) -> np.ndarray:
    """Colour a biome array with :data:`~sylva.world.biomes.BIOME_COLORS`: uint8[..., 3]."""
    lut = np.array([BIOME_COLORS[b] for b in Biome], np.uint8)
    return lut[np.asarray(biomes, np.int64)]


# --------------------------------------------------------------------------- config
def config_to_json(cfg: WorldConfig) -> dict:
    """A :class:`WorldConfig` as plain JSON values (species as dicts)."""
    d = asdict(cfg)
    if d.get("species"):
        d["species"] = {k: {f: list(v) if isinstance(v, tuple) else v for f, v in s.items()}
                        for k, s in d["species"].items()}  # fmt: skip
    return json.loads(json.dumps(d, default=str))


def config_from_json(d: dict) -> WorldConfig:
    """The inverse of :func:`config_to_json`."""
    d = dict(d)
    if d.get("species"):
        d["species"] = {k: Species(**{f: tuple(v) if isinstance(v, list) else v
                                      for f, v in s.items()})
                        for k, s in d["species"].items()}  # fmt: skip
    return WorldConfig(**d)


def _versions() -> dict:
    from importlib.metadata import PackageNotFoundError, version

    import numpy
    import pyarrow
    import zarr

    try:
        sylva = version("sylva")
    except PackageNotFoundError:  # a source tree on PYTHONPATH
        sylva = "unknown"
    return {"sylva": sylva, "numpy": numpy.__version__, "zarr": zarr.__version__,
            "pyarrow": pyarrow.__version__}  # fmt: skip


def _stage(key: str) -> int:
    """Growth stage of a model: shrub cache entry ``i`` → ``i mod 3``; −1 otherwise."""
    name, sep, rest = key.partition("#")
    if sep and name in SHRUBS and rest.isdigit():
        return int(rest) % 3
    return -1


# --------------------------------------------------------------------------- store
class WorldStore:
    """A world store on disk (see the module docstring).

    Parameters
    ----------
    path : path
        The store's folder (with its ``manifest.json``).
    owned : bool
        Remove the folder on :meth:`close` (a store made in a temporary folder).
    """

    def __init__(self, path, *, owned: bool = False) -> None:
        self.path = Path(path)
        mpath = self.path / "manifest.json"
        try:
            self.manifest = json.loads(mpath.read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise SylvaError(f"{str(self.path)!r} is not a sylva world store: "
                             "expected a folder with a manifest.json") from None  # fmt: skip
        except (OSError, ValueError) as exc:
            raise SylvaError(f"{str(mpath)!r}: cannot read the manifest ({exc})") from None
        if self.manifest.get("format") != FORMAT[0]:
            raise SylvaError(f"{str(mpath)!r}: expected format {FORMAT[0]!r}, got "
                             f"{self.manifest.get('format')!r}")  # fmt: skip
        self.config = config_from_json(self.manifest["config"])
        self.size = tuple(self.manifest["size"])
        self.origin = tuple(self.manifest["origin"])
        self.closed = bool(self.manifest["closed"])
        self.owned = owned
        s = self.config.chunk_size
        self.chunk0 = tuple(self.manifest["chunk0"])
        self.chunks_shape = tuple(self.manifest["chunks"])
        self.base = (self.chunk0[0] * s, self.chunk0[1] * s)  # world column of index 0
        self._group = None

    # ------------------------------------------------------------------ create
    @classmethod
    def create(cls, path, world, *, block_columns: int) -> WorldStore:
        """Make an empty store for ``world`` (a :class:`~sylva.world.World`)."""
        import zarr
        from zarr.codecs import BloscCodec

        # Blosc-zstd level 1: 6x faster than Zarr's default zstd for 10 % more bytes
        fast = BloscCodec(cname="zstd", clevel=1, shuffle="noshuffle")
        path = Path(path)
        if path.exists() and any(path.iterdir()):
            raise SylvaError(f"{str(path)!r} exists and is not empty: remove it, or resume "
                             "it with --resume (resume=True)")  # fmt: skip
        make_folder(path)
        cfg = world.config
        s = cfg.chunk_size
        c0, c1 = world._c0, world._c1
        nx, nz = (c1[0] - c0[0]) * s, (c1[1] - c0[1]) * s
        root = zarr.open_group(str(path), mode="w", zarr_format=3)
        root.create_array("voxels", shape=(nx, cfg.height, nz), chunks=(s, cfg.height, s),
                          dtype="uint8", fill_value=0, dimension_names=("x", "y", "z"),
                          compressors=fast)  # fmt: skip
        for name, (dtype, fill) in _FIELDS.items():
            root.create_array(name, shape=(nx, nz), chunks=(s, s), dtype=dtype,
                              fill_value=fill, dimension_names=("x", "z"),
                              compressors=fast)  # fmt: skip
        for sub in ("plants", "skin", "done"):
            make_folder(path / sub)
        manifest = {
            "format": FORMAT[0], "format_version": FORMAT[1],
            "config": config_to_json(cfg), "size": list(world.size),
            "origin": list(world.origin), "closed": world.closed,
            "chunk0": list(c0), "chunks": [c1[0] - c0[0], c1[1] - c0[1]],
            "block_columns": int(block_columns),
            "blocks": len(world.blocks(block_columns)), "complete": False,
            "versions": _versions(),
        }  # fmt: skip
        with atomic_write(path / "manifest.json", "w") as fh:
            fh.write(json.dumps(manifest, indent=1))
        return cls(path)

    def check_matches(self, world, block_columns: int) -> None:
        """Raise unless this store was started for the same world (for resuming)."""
        want = {"config": config_to_json(world.config), "size": list(world.size),
                "origin": list(world.origin), "closed": world.closed,
                "block_columns": int(block_columns)}  # fmt: skip
        for k, v in want.items():
            if self.manifest.get(k) != v:
                raise SylvaError(f"cannot resume {str(self.path)!r}: its {k} is "
                                 f"{self.manifest.get(k)!r}, this run's is {v!r}")  # fmt: skip

    # ------------------------------------------------------------------ blocks
    @staticmethod
    def block_name(block) -> str:
        return f"b_{block[0]}_{block[1]}"

    def done(self) -> dict[tuple[int, int], dict]:
        """The complete blocks: ``(cx0, cz0)`` → their ``done`` record."""
        out = {}
        for p in sorted((self.path / "done").glob("b_*.json")):
            rec = json.loads(p.read_text(encoding="utf-8"))
            out[tuple(rec["block"][:2])] = rec
        return out

    def missing(self, block_columns: int | None = None) -> list[tuple[int, int, int, int]]:
        """The blocks ``(cx0, cz0, ncx, ncz)`` not written yet."""
        from .world import World

        w = World(self.config, self.size, self.origin, closed=self.closed)
        done = self.done()
        bc = block_columns or self.manifest["block_columns"]
        return [b for b in w.blocks(bc) if (b[0], b[1]) not in done]

    @property
    def complete(self) -> bool:
        """Every block written and the manifest closed."""
        return bool(self.manifest.get("complete"))

    def _arrays(self):
        if self._group is None:
            import zarr

            self._group = zarr.open_group(str(self.path), mode="r+", zarr_format=3)
        return self._group

    def write_block(self, block, chunks: list[Chunk]) -> dict:
        """Store a generated block of chunks (in a worker): arrays, tables, then ``done``."""
        import pyarrow as pa
        import pyarrow.parquet as pq

        g = self._arrays()
        s = self.config.chunk_size
        i0 = (block[0] - self.chunk0[0]) * s
        k0 = (block[1] - self.chunk0[1]) * s
        xs = slice(i0, i0 + block[2] * s)
        zs = slice(k0, k0 + block[3] * s)
        vox = np.zeros((block[2] * s, self.config.height, block[3] * s), np.uint8)
        fields = {n: np.zeros((block[2] * s, block[3] * s), d) for n, (d, _) in _FIELDS.items()}
        plants, skins, record = [], [], []
        for ch in chunks:
            a, b = (ch.cx - block[0]) * s, (ch.cz - block[1]) * s
            vox[a : a + s, :, b : b + s] = ch.voxels
            for n in fields:
                fields[n][a : a + s, b : b + s] = getattr(ch, n)
            plants.append(self._plant_table(ch))
            q = ch.quads
            skins.append(np.concatenate([np.full((len(q), 2), (ch.cx, ch.cz), np.int32), q], 1))
            record.append([ch.cx, ch.cz, int(len(q)), len(ch.plants)])
        g["voxels"][xs, :, zs] = vox
        for n, arr in fields.items():
            g[n][xs, zs] = arr
        name = self.block_name(block)
        table = pa.concat_tables(plants)
        with atomic_path(self.path / "plants" / f"{name}.parquet") as tmp:
            pq.write_table(table, tmp, compression="zstd")
        skin = np.concatenate(skins)
        cols = {f: pa.array(skin[:, i]) for i, f in enumerate(("cx", "cz", *QUAD_FIELDS))}
        with atomic_path(self.path / "skin" / f"{name}.parquet") as tmp:
            pq.write_table(pa.table(cols), tmp, compression="zstd")
        keys = sorted(set(table.column("model").to_pylist()))
        rec = {"block": list(block), "chunks": record, "models": keys}
        with atomic_write(self.path / "done" / f"{name}.json", "w") as fh:
            fh.write(json.dumps(rec))
        return rec

    def _plant_table(self, ch: Chunk):
        import pyarrow as pa

        p = ch.plants
        n = len(p)
        x0, z0 = ch.origin
        col = p.column.astype(np.int64)
        bi = ch.biome[np.clip(col[:, 0] - x0, 0, ch.size - 1), np.clip(col[:, 1] - z0, 0,
                                                                       ch.size - 1)]
        keys = [str(k) for k in p.keys]
        stage_of = {k: _stage(k) for k in set(keys)}
        return pa.table({
            "model": pa.array(keys, pa.string()),
            "x": pa.array(p.position[:, 0], pa.float32()),
            "y": pa.array(p.position[:, 1], pa.float32()),
            "z": pa.array(p.position[:, 2], pa.float32()),
            "yaw": pa.array(p.yaw, pa.float32()),
            "scale": pa.array(np.ones(n, np.float32)),
            "biome": pa.array(bi.astype(np.uint8)),
            "stage": pa.array(np.array([stage_of[k] for k in keys], np.int8)),
            "column_x": pa.array(col[:, 0].astype(np.int32)),
            "column_z": pa.array(col[:, 1].astype(np.int32)),
            "cx": pa.array(np.full(n, ch.cx, np.int32)),
            "cz": pa.array(np.full(n, ch.cz, np.int32)),
        })  # fmt: skip

    def finish(self) -> None:
        """Close the manifest: chunk counts and models, ``complete: true``."""
        missing = self.missing()
        if missing:
            raise SylvaError(f"{str(self.path)!r}: {len(missing)} blocks are missing")
        done = self.done()
        rows = sorted((r for rec in done.values() for r in rec["chunks"]),
                      key=lambda r: (r[1], r[0]))  # fmt: skip
        models = sorted({k for rec in done.values() for k in rec["models"]})
        self.manifest.update(complete=True, quads=sum(r[2] for r in rows),
                             plants=sum(r[3] for r in rows), models=models)  # fmt: skip
        with atomic_write(self.path / "manifest.json", "w") as fh:
            fh.write(json.dumps(self.manifest, indent=1))

    # ------------------------------------------------------------------ reading
    def __len__(self) -> int:
        return self.chunks_shape[0] * self.chunks_shape[1]

    def __getitem__(self, key) -> Region:
        if not (isinstance(key, tuple) and len(key) == 2
                and all(isinstance(k, slice) and k.step in (None, 1) for k in key)):  # fmt: skip
            raise SylvaError("a store reads regions: store[x0:x1, z0:z1] (world columns)")
        x0, z0, x1, z1 = self.bounds
        xs = slice(x0 if key[0].start is None else key[0].start,
                   x1 if key[0].stop is None else key[0].stop)  # fmt: skip
        zs = slice(z0 if key[1].start is None else key[1].start,
                   z1 if key[1].stop is None else key[1].stop)  # fmt: skip
        if xs.start < x0 or zs.start < z0 or xs.stop > x1 or zs.stop > z1:
            raise SylvaError(f"region [{xs.start}:{xs.stop}, {zs.start}:{zs.stop}] lies "
                             f"outside the world [{x0}:{x1}, {z0}:{z1}]")  # fmt: skip
        if xs.start >= xs.stop or zs.start >= zs.stop:
            raise SylvaError("an empty region: expected x0 < x1 and z0 < z1")
        return Region(self, xs.start, zs.start, xs.stop, zs.stop)

    @property
    def bounds(self) -> tuple[int, int, int, int]:
        """``(x0, z0, x1, z1)`` in world columns."""
        return (self.origin[0], self.origin[1], self.origin[0] + self.size[0],
                self.origin[1] + self.size[1])  # fmt: skip

    def chunk_coords(self) -> list[tuple[int, int]]:
        """Chunk coordinates, row by row (z outer)."""
        (a, b), (n, m) = self.chunk0, self.chunks_shape
        return [(cx, cz) for cz in range(b, b + m) for cx in range(a, a + n)]

    def _read(self, name, xs, zs):
        import zarr

        arr = zarr.open_array(str(self.path / name), mode="r", zarr_format=3)
        i = slice(xs.start - self.base[0], xs.stop - self.base[0])
        k = slice(zs.start - self.base[1], zs.stop - self.base[1])
        return arr[i, :, k] if name == "voxels" else arr[i, k]

    def _tables(self, sub: str, x0, z0, x1, z1):
        """The Parquet files of ``sub`` whose blocks overlap the columns, as one table."""
        import pyarrow as pa
        import pyarrow.compute as pc
        import pyarrow.parquet as pq

        s = self.config.chunk_size
        out = []
        for (cx, cz), rec in sorted(self.done().items(), key=lambda kv: (kv[0][1], kv[0][0])):
            b = rec["block"]
            if cx * s >= x1 or (cx + b[2]) * s <= x0 or cz * s >= z1 or (cz + b[3]) * s <= z0:
                continue
            out.append(pq.read_table(self.path / sub / f"{self.block_name(b)}.parquet"))
        if not out:
            return None
        t = pa.concat_tables(out)
        return t.take(pc.sort_indices(t, [("cz", "ascending"), ("cx", "ascending")]))

    def plants(self):
        """Every plant instance as one ``pyarrow.Table`` (block by block, chunk order)."""
        return self[:, :].plants()

    def __iter__(self) -> Iterator[Chunk]:
        """The chunks, row by row, rebuilt from the store (voxels left out)."""
        s = self.config.chunk_size
        for cz in range(self.chunk0[1], self.chunk0[1] + self.chunks_shape[1]):
            row = self._chunk_row(cz)
            for cx in range(self.chunk0[0], self.chunk0[0] + self.chunks_shape[0]):
                x0 = cx * s
                i = slice(x0 - self.base[0], x0 - self.base[0] + s)
                f = {n: row[n][i, :] for n in _FIELDS}
                yield Chunk(cx, cz, s, f["height"], f["humidity"], f["temperature"],
                            f["biome"], row["skin"].get((cx, cz), _NO_QUADS),
                            row["plants"].get((cx, cz), Placement.empty()))  # fmt: skip

    def _chunk_row(self, cz: int) -> dict:
        """One row of chunks: fields [x, s], skins and plants by chunk."""
        import zarr

        s = self.config.chunk_size
        k = slice(cz * s - self.base[1], cz * s - self.base[1] + s)
        out: dict = {n: zarr.open_array(str(self.path / n), mode="r", zarr_format=3)[:, k]
                     for n in _FIELDS}  # fmt: skip
        x0, x1 = self.base[0], self.base[0] + self.chunks_shape[0] * s
        skin = self._tables("skin", x0, cz * s, x1, cz * s + s)
        out["skin"] = {}
        if skin is not None:
            a = np.stack([skin.column(c).to_numpy() for c in ("cx", "cz", *QUAD_FIELDS)], 1)
            a = a[a[:, 1] == cz]
            for cx in np.unique(a[:, 0]):
                out["skin"][(int(cx), cz)] = np.ascontiguousarray(a[a[:, 0] == cx, 2:], np.int32)
        plants = self._tables("plants", x0, cz * s, x1, cz * s + s)
        out["plants"] = {}
        if plants is not None:
            pc = plants.column("cz").to_numpy()
            px = plants.column("cx").to_numpy()
            for cx in np.unique(px[pc == cz]):
                sel = np.flatnonzero((pc == cz) & (px == cx))
                t = plants.take(sel)
                out["plants"][(int(cx), cz)] = _placement(t)
        return out

    # ------------------------------------------------------------------ summaries
    @property
    def n_quads(self) -> int:
        return sum(r[2] for rec in self.done().values() for r in rec["chunks"])

    @property
    def n_plants(self) -> int:
        return sum(r[3] for rec in self.done().values() for r in rec["chunks"])

    def biome_map(self) -> np.ndarray:
        """The world's biomes as an sRGB image, uint8[z, x, 3] (row 0 at the lowest z)."""
        return biome_image(self[:, :].biome.T)

    # ------------------------------------------------------------------ geometry
    def quads(self) -> np.ndarray:
        """Every chunk's skin quads, int32[q, 7], in chunk order."""
        return self[:, :].quads()

    def terrain_mesh(self, materials: list[Material] | None = None) -> Mesh:
        """All chunks' skins in one mesh (world coordinates)."""
        return quads_to_mesh(self.quads(), materials=materials, name="terrain")

    def instances(self) -> dict[str, Instances]:
        """Plant instances grouped by model key (sorted keys)."""
        return self[:, :].instances()

    def scene(self, library: PlantLibrary | None = None,
              materials: list[Material] | None = None, *, plants: bool = True,
              grass: bool = True) -> Scene:  # fmt: skip
        """Terrain plus every plant expanded into meshes (one mesh per model)."""
        lib = library or PlantLibrary.for_config(self.config)
        if materials is not None:
            lib.materials = materials
        scene = Scene([self.terrain_mesh(materials or lib.materials)], name="world")
        if plants:
            for key, inst in self.instances().items():
                if not grass and key.startswith("grass#"):
                    continue
                scene.add(expand_instances(lib.model(key), inst))
        return scene

    # ------------------------------------------------------------------ life
    @property
    def directory(self) -> Path:
        return self.path

    def __enter__(self) -> WorldStore:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Remove the folder when this store owns it."""
        if self.owned and self.path.exists():
            shutil.rmtree(self.path, ignore_errors=True)


_NO_QUADS = np.zeros((0, 7), np.int32)


def _placement(t) -> Placement:
    n = t.num_rows
    pos = np.zeros((n, 3), np.float32)
    for i, c in enumerate("xyz"):
        pos[:, i] = t.column(c).to_numpy()
    keys = np.array(t.column("model").to_pylist()) if n else np.zeros(0, "U1")
    col = np.stack([t.column("column_x").to_numpy(), t.column("column_z").to_numpy()], 1)
    return Placement(keys, pos, t.column("yaw").to_numpy().astype(np.float32),
                     col.astype(np.int32))  # fmt: skip


class Region:
    """A rectangle of a store, read on demand (``store[x0:x1, z0:z1]``).

    Attributes ``voxels`` (uint8[x, y, z]), ``height`` (int32[x, z]), ``biome``,
    ``humidity``, ``temperature`` (uint8[x, z]) read only the Zarr chunks they overlap;
    :meth:`plants` and :meth:`quads` only the overlapping blocks' Parquet files.
    """

    def __init__(self, store: WorldStore, x0: int, z0: int, x1: int, z1: int) -> None:
        self.store = store
        self.bounds = (x0, z0, x1, z1)
        self._xs, self._zs = slice(x0, x1), slice(z0, z1)

    @property
    def shape(self) -> tuple[int, int]:
        return self._xs.stop - self._xs.start, self._zs.stop - self._zs.start

    @property
    def voxels(self) -> np.ndarray:
        return self.store._read("voxels", self._xs, self._zs)

    @property
    def height(self) -> np.ndarray:
        return self.store._read("height", self._xs, self._zs)

    @property
    def biome(self) -> np.ndarray:
        return self.store._read("biome", self._xs, self._zs)

    @property
    def humidity(self) -> np.ndarray:
        return self.store._read("humidity", self._xs, self._zs)

    @property
    def temperature(self) -> np.ndarray:
        return self.store._read("temperature", self._xs, self._zs)

    def plants(self):
        """The plant instances standing in the region: a ``pyarrow.Table``."""
        import pyarrow.compute as pc

        x0, z0, x1, z1 = self.bounds
        t = self.store._tables("plants", x0, z0, x1, z1)
        if t is None:
            return _empty_plants()
        cx, cz = t.column("column_x"), t.column("column_z")
        inside = pc.and_(pc.and_(pc.greater_equal(cx, x0), pc.less(cx, x1)),
                         pc.and_(pc.greater_equal(cz, z0), pc.less(cz, z1)))  # fmt: skip
        return t.filter(inside).combine_chunks()

    def quads(self) -> np.ndarray:
        """The skin quads of the chunks the region overlaps, int32[q, 7] (whole chunks)."""
        x0, z0, x1, z1 = self.bounds
        t = self.store._tables("skin", x0, z0, x1, z1)
        if t is None:
            return _NO_QUADS.copy()
        a = np.stack([t.column(c).to_numpy() for c in ("cx", "cz", *QUAD_FIELDS)], 1)
        s = self.store.config.chunk_size
        keep = ((a[:, 0] + 1) * s > x0) & (a[:, 0] * s < x1) & ((a[:, 1] + 1) * s > z0) & (
            a[:, 1] * s < z1)
        return np.ascontiguousarray(_chunk_sorted(a[keep])[:, 2:], np.int32)

    def instances(self) -> dict[str, Instances]:
        """The region's plant instances grouped by model key (sorted keys)."""
        t = self.plants()
        if t.num_rows == 0:
            return {}
        keys = np.array(t.column("model").to_pylist())
        pos = np.stack([t.column(c).to_numpy() for c in "xyz"], 1).astype(np.float32)
        yaw = t.column("yaw").to_numpy().astype(np.float32)
        return {k: Instances(k, pos[keys == k], yaw[keys == k]) for k in sorted(set(keys))}


def _chunk_sorted(a: np.ndarray) -> np.ndarray:
    """Rows of (cx, cz, …) in chunk order (z outer), keeping their order within a chunk."""
    if not len(a):
        return a
    order = np.lexsort((a[:, 0], a[:, 1]))  # stable: last key primary
    return a[order]


def _empty_plants():
    import pyarrow as pa

    return pa.table({"model": pa.array([], pa.string()),
                     **{c: pa.array([], pa.float32()) for c in ("x", "y", "z", "yaw", "scale")},
                     "biome": pa.array([], pa.uint8()), "stage": pa.array([], pa.int8()),
                     **{c: pa.array([], pa.int32()) for c in ("column_x", "column_z", "cx",
                                                               "cz")}})  # fmt: skip


def open_world(path) -> WorldStore:
    """Open a world store (``sylva.world.open``) to read it, whole or in pieces.

    Parameters
    ----------
    path : path
        A folder written by :meth:`~sylva.world.World.generate` or ``sylva world -o
        world.zarr``.

    Returns
    -------
    WorldStore
        ``store[x0:x1, z0:z1]`` is a :class:`Region` of world columns.
    """
    return WorldStore(path)


# --------------------------------------------------------------------------- models
def model_file(key: str) -> str:
    """The file name of model ``key`` under ``models/`` (``oak#3`` → ``oak-3.glb``)."""
    return key.replace("#", "-").replace("@", "_") + ".glb"


def _model_task(job) -> list[str]:
    """One Dask task: write a batch of plant models of a store as GLBs."""
    from ..geometry.exchange.gltf_instanced import write_glb_instanced
    from .atlas import tile_materials
    from .blocks import TEXTURES

    path, keys = job
    store = WorldStore(path)
    lib = PlantLibrary.for_config(store.config)
    tiles = Path(path) / "textures"
    lib.materials = tile_materials({t: str(tiles / f"{t}.png") for t in TEXTURES})
    for key in keys:
        with atomic_path(Path(path) / "models" / model_file(key)) as tmp:
            write_glb_instanced([lib.model(key)], [], tmp, name=key)
    return keys


def write_models(store: WorldStore, *, scheduler: str | None = None,
                 workers: int | None = None, batch: int = 8, runner=None) -> int:  # fmt: skip
    """Write every plant model ``store`` uses as ``models/KEY.glb`` (Dask tasks).

    The block textures go to ``textures/`` once, embedded in each model; the manifest's
    ``model_files`` maps model keys to files.  Returns the number of models.
    """
    from ..cluster import using
    from .atlas import make_atlas

    keys = list(store.manifest.get("models", []))
    make_folder(store.path / "models")
    make_atlas(32, store.config.seed).save_tiles(store.path / "textures")
    jobs = [(str(store.path), keys[i : i + batch]) for i in range(0, len(keys), batch)]
    with using(runner, scheduler, workers=workers, tasks=len(jobs)) as run:
        for _ in run.map(_model_task, jobs, progress=False):
            pass
    store.manifest["model_files"] = {k: f"models/{model_file(k)}" for k in keys}
    with atomic_write(store.path / "manifest.json", "w") as fh:
        fh.write(json.dumps(store.manifest, indent=1))
    return len(keys)
