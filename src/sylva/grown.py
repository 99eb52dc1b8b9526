"""The one-line API: ``sylva.grow``, ``sylva.tree`` and ``sylva.world``.

Each returns an object that renders, saves, animates and shows itself (:class:`Shown`):

>>> import sylva
>>> plant = sylva.grow("axiom = F\\nF -> F[+F]F[-F]F", 2)
>>> plant.stats["segments"]
25
>>> plant.render(size=(64, 48)).size
(64, 48)

A species name (or a tree configuration file) grows a Weber–Penn tree instead, as does
:func:`tree`; :func:`world` generates a voxel world.  The work is done by
:mod:`sylva.plant`, :mod:`sylva.tree` and :mod:`sylva.world`; this module only wires them to
the renderer and the exporters, the way the ``sylva tree`` and ``sylva world`` commands do.
"""

from __future__ import annotations

import os
import shutil
import tempfile
import weakref
from pathlib import Path

from ._shown import Shown, check_size
from .errors import SylvaError

__all__ = ["TreePlant", "WorldView", "grow", "render_world", "tree", "world", "world_lights"]


# --------------------------------------------------------------------------- grow
def _is_species(source) -> bool:
    """A species name, or a tree configuration file (its ``[global]`` block)."""
    if not isinstance(source, (str, os.PathLike)):
        return False
    text = os.fspath(source)
    if "\n" in text:
        return False
    from .tree.species import species_names

    key = text.strip().lower().replace(" ", "_").replace("-", "_")
    if key in species_names():
        return True
    path = Path(os.path.expanduser(text))
    if path.suffix.lower() == ".txt" and path.is_file():
        with open(path, encoding="utf-8", errors="replace") as fh:
            head = fh.read(4096)
        return any(line.strip().lower() == "[global]" for line in head.splitlines())
    return False


def grow(source, steps: int | None = None, *, seed: int | None = None, **options):
    """Grow a plant from anything sylva reads, in one call.

    Parameters
    ----------
    source : Program, path, example name, L-system text, species name or tree file
        An L-system (any dialect; ``sylva examples`` lists the built-in names), or a tree
        species (``sylva tree --list``) or a tree configuration file, which grows a tree
        (:func:`tree`; ``steps`` is then its age in years).
    steps : int, optional
        Derivation steps (default: the program's own count).
    seed : int, optional
        The seed of every random choice (default: the program's ``seed``, else 1; 0 for
        trees).
    **options
        For L-systems: ``detail``, ``mode``, ``taper``, ``limit`` of
        :func:`sylva.plant.grow`; for trees those of :func:`tree`.

    Returns
    -------
    sylva.plant.Plant or TreePlant

    Examples
    --------
    >>> import sylva
    >>> sylva.grow("koch-snowflake", 1).stats["modules"] > 4
    True
    """
    if _is_species(source):
        return tree(source, age=steps, seed=0 if seed is None else seed, **options)
    from .plant import grow as grow_plant

    return grow_plant(source, steps, seed=seed, **options)


# --------------------------------------------------------------------------- trees
class TreePlant(Shown):
    """A Weber–Penn tree grown to an age, with its mesh (see :func:`tree`).

    Attributes
    ----------
    model : sylva.tree.Tree
        The tree model (grow it on with ``model.grow(age)``, then :meth:`regrow`).
    mesh : sylva.tree.TreeMesh
        Its mesh with skinning data (for wind); ``scene`` wraps the (wind-bent) mesh.
    wind : float
        Wind strength the still images are bent by (0: calm).
    """

    def __init__(self, model, *, seed: int, wind: float = 0.0, leaves: bool = True) -> None:
        self.model = model
        self.seed = seed
        self.wind = float(wind)
        self.leaves = bool(leaves)
        self._scene = None
        self.mesh = model.mesh(leaves=self.leaves)

    @property
    def age(self) -> float:
        return self.model.age

    @property
    def scene(self):
        if self._scene is None:
            from .geometry.mesh import Scene

            mesh = self.mesh.mesh
            if self.wind:
                from .tree import Wind

                mesh = Wind(self.wind, seed=self.seed).mesh_at(self.mesh, 0.0)
            self._scene = Scene([mesh], name=self.model.name.replace(" ", "_"))
        return self._scene

    @property
    def stats(self) -> dict:
        """``name``, ``seed``, ``age``, ``height`` (m), ``stems`` per level, ``leaves``,
        ``triangles``."""
        s = self.model.stats()
        return {"name": self.model.name, "seed": self.seed, "age": round(self.age, 6),
                "height": round(float(s["height"]), 6), "stems": list(s["stems"]),
                "leaves": int(s["leaves"]), "triangles": int(self.scene.n_triangles)}  # fmt: skip

    def animate(self, path, *, kind: str = "growth", seconds: float = 4.0,
                fps: float | None = None, size=(640, 640), wind: float | None = None) -> Path:
        """Write the tree growing (age 0 to its age) or swaying in the wind.

        ``.gif`` and ``.mp4`` are rendered frames; ``.glb`` is a skinned glTF animation (as
        ``sylva tree --animate``).  Returns the path written.
        """
        from .tree import Wind
        from .tree.animation import growth_animation, growth_meshes, wind_animation, wind_meshes

        path = Path(path)
        ext = path.suffix.lower()
        if kind not in ("growth", "wind"):
            raise SylvaError(f"kind: expected 'growth' or 'wind', got {kind!r}")
        if not seconds > 0:
            raise SylvaError(f"seconds: expected a positive duration, got {seconds!r}")
        fps = fps or (24.0 if kind == "wind" else 12.0)
        if not fps > 0:
            raise SylvaError(f"fps: expected a positive number, got {fps!r}")
        age = self.age
        w = Wind((self.wind or 1.0) if wind is None else wind, seed=self.seed)
        if ext == ".glb":
            from .geometry.exchange.gltf_animation import write_animated_glb

            if kind == "wind":
                anim = wind_animation(self.mesh, w, seconds, fps)
            else:
                anim = growth_animation(self.model, min(0.05 * age, 0.5), age, seconds, fps)
                self.model.grow(age)
            write_animated_glb(anim, path)
            return path
        if ext not in (".gif", ".mp4", ".m4v", ".mov"):
            raise SylvaError(f"{path}: a tree animation is .glb, .gif or .mp4")
        from .render import growth_frames, write_animation

        size = check_size(size)
        frames = max(2, int(round(seconds * fps)))
        if kind == "wind":
            meshes = list(wind_meshes(self.mesh, w, seconds, fps))
        else:
            meshes = list(growth_meshes(self.model, min(0.05 * age, 0.5), age, frames,
                                        leaves=self.leaves))
            self.model.grow(age)
        write_animation(growth_frames(meshes, size), path, fps=fps, total=len(meshes),
                        progress=False)
        return path


def tree(species: str | os.PathLike = "black_oak", *, age: float | None = None, seed: int = 0,
         wind: float = 0.0, leaves: bool = True) -> TreePlant:
    """Grow a tree of a species (Weber–Penn, events in time; seed 002) in one call.

    Parameters
    ----------
    species : str or path
        A species name (:func:`sylva.tree.species_names`) or a configuration file.
    age : float, optional
        Years (default: the species' ``Age``).
    seed : int
        The individual: the same seed grows the same tree.
    wind : float
        Wind strength still images are bent by (0 calm, 1 breeze, 3 storm).
    leaves : bool
        Leave the leaves out when false.

    Returns
    -------
    TreePlant

    Examples
    --------
    >>> import sylva
    >>> oak = sylva.tree("black_oak", age=2.0, seed=1, leaves=False)
    >>> oak.stats["stems"][0]
    1
    """
    from .tree import Tree

    if isinstance(seed, bool) or not isinstance(seed, int):
        raise SylvaError(f"seed: expected a whole number, got {seed!r}")
    try:
        model = Tree(os.fspath(species), seed=seed)
    except ValueError as exc:  # a bad parameter in a configuration file
        if isinstance(exc, SylvaError):
            raise
        raise SylvaError(f"{species}: {exc}") from None
    a = model.default_age if age is None else age
    if isinstance(a, bool) or not isinstance(a, (int, float)) or not a > 0:
        raise SylvaError(f"age: expected a positive number of years, got {age!r}")
    if not isinstance(wind, (int, float)) or wind < 0:
        raise SylvaError(f"wind: expected a strength >= 0, got {wind!r}")
    model.grow(float(a))
    return TreePlant(model, seed=seed, wind=wind, leaves=leaves)


# --------------------------------------------------------------------------- worlds
def world_lights(store) -> list:
    """A world's lights: a low sun and seed 004's point light above its middle."""
    from .render import ATTENUATION, PointLight, Sun

    w, d = store.size
    ox, oz = store.origin
    top = store.config.height
    return [
        Sun(direction=(-0.5, -1.0, -0.35), color=0.9, ambient=0.32, specular=0.15),
        # seed 004's point light: attenuation 1 / (1 + 0.045 d + 0.0075 d^2)
        PointLight(position=(ox + w / 2, top * 0.8, oz + d / 2), color=(1.0, 0.85, 0.6),
                   specular=0.2, attenuation=ATTENUATION),
    ]  # fmt: skip


def world_camera(scene, view: str, aspect: float):
    """The camera of a world image: ``"angle"`` (perspective from above) or ``"top"``."""
    from .render import Camera

    if view == "top":
        return Camera.auto(scene, "orthographic", yaw=0.0, pitch=89.0, aspect=aspect,
                           margin=0.02)  # fmt: skip
    return Camera.auto(scene, "perspective", yaw=35.0, pitch=38.0, aspect=aspect, margin=0.02)


def render_world(store, *, size=(1600, 1000), view: str = "angle", shadows: bool = True,
                 grass: bool = True, tiles=None, **options):
    """Render a generated world (terrain and expanded plants) to a PIL image.

    ``tiles`` is a folder for the block textures (default: a temporary one).
    """
    from .render import render
    from .world.atlas import make_atlas, tile_materials

    size = check_size(size)
    with tempfile.TemporaryDirectory(prefix="sylva-tiles-") as tmp:
        paths = make_atlas(32, store.config.seed).save_tiles(tiles or tmp)
        materials = tile_materials({k: str(v) for k, v in paths.items()})
        scene = store.scene(materials=materials, grass=grass)
        cam = world_camera(scene, view, size[0] / size[1])
        opts = dict(lights=world_lights(store), bg="#9fc8ef", ground=False, shadows=shadows,
                    shadow_size=4096)  # fmt: skip
        return render(scene, size=size, camera=cam, **{**opts, **options})


class WorldView(Shown):
    """A generated voxel world (see :func:`world`); its chunks live in a temporary folder
    until the object is gone (or :meth:`close`)."""

    def __init__(self, store, *, grass: bool = True) -> None:
        self.store = store
        self.grass = grass
        self._tiles = tempfile.mkdtemp(prefix="sylva-tiles-")
        self._finalizer = weakref.finalize(self, _close_world, store, self._tiles)
        self._scene = None

    def close(self) -> None:
        """Remove the chunk and texture folders now."""
        self._finalizer()

    @property
    def scene(self):
        if self._scene is None:
            from .world.atlas import make_atlas, tile_materials

            paths = make_atlas(32, self.store.config.seed).save_tiles(self._tiles)
            materials = tile_materials({k: str(v) for k, v in paths.items()})
            self._scene = self.store.scene(materials=materials, grass=self.grass)
        return self._scene

    @property
    def stats(self) -> dict:
        """``seed``, ``size`` (columns), ``chunks``, ``quads``, ``plants``, ``triangles``."""
        s = self.store
        return {"seed": s.config.seed, "size": list(s.size), "chunks": len(s),
                "quads": int(s.n_quads), "plants": int(s.n_plants),
                "triangles": int(self.scene.n_triangles)}  # fmt: skip

    def biome_map(self):
        """The biome map as a PIL image (row 0: lowest z, as the top view)."""
        from PIL import Image

        return Image.fromarray(self.store.biome_map())

    def render(self, size=(800, 500), camera=None, **options):
        """An image of the world: ``camera`` is ``"angle"`` (default), ``"top"``, another
        mode name or a :class:`sylva.render.Camera`; ``options`` go to
        :func:`sylva.render.render`."""
        from .render import Camera, render

        size = check_size(size)
        view = camera or "angle"
        if view in ("angle", "top"):
            cam = world_camera(self.scene, view, size[0] / size[1])
        elif isinstance(view, (str, Camera)):
            return Shown.render(self, size, camera, **{**self._render_options(size), **options})
        else:
            raise SylvaError(f"camera: expected 'angle', 'top', a mode name or a Camera, "
                             f"got {camera!r}")  # fmt: skip
        return render(self.scene, size=size, camera=cam, **{**self._render_options(size),
                                                             **options})

    def _render_options(self, size) -> dict:
        return dict(lights=world_lights(self.store), bg="#9fc8ef", ground=False,
                    shadow_size=4096)  # fmt: skip

    def _write(self, path, fmt: str, options: dict) -> None:
        if fmt == "glb":  # plants once each, drawn by EXT_mesh_gpu_instancing
            from .world.export import write_world_glb

            write_world_glb(self.store, path, tiles=self._tiles, grass=self.grass, **options)
            return
        super()._write(path, fmt, options)

    def animate(self, path, *, frames: int = 48, size=(640, 400), fps: float = 12.0) -> Path:
        """Write a turntable of the world (``.gif`` or ``.mp4``)."""
        from .render import turntable_frames, write_animation

        path = Path(path)
        if path.suffix.lower() not in (".gif", ".mp4", ".m4v", ".mov"):
            raise SylvaError(f"{path}: an animation must end in .gif or .mp4")
        if isinstance(frames, bool) or not isinstance(frames, int) or frames < 2:
            raise SylvaError(f"frames: expected a whole number >= 2, got {frames!r}")
        size = check_size(size)
        out = turntable_frames(self.scene, frames, size, "perspective", pitch=38.0,
                               **self._render_options(size))
        write_animation(out, path, fps=fps, progress=False)
        return path


def _close_world(store, tiles: str) -> None:
    store.close()
    shutil.rmtree(tiles, ignore_errors=True)


def world(seed: int = 0, size=64, *, chunk: int = 32, plants: bool = True, grass: bool = True,
          caves: bool = False, workers: int | None = 1, **config) -> WorldView:
    """Generate a voxel world with biomes and L-system vegetation (seed 004) in one call.

    Parameters
    ----------
    seed : int
        The same seed gives the same world.
    size : int or (int, int)
        Columns along x and z.
    chunk : int
        Chunk size in columns.
    plants, grass, caves : bool
        Vegetation, grass tufts, caves.
    workers : int or None
        Worker processes (1, the default, works everywhere, a Dask worker included;
        ``None`` uses every core).
    **config
        Other :class:`sylva.world.WorldConfig` fields (``sea_level``, ``plants=`` …).

    Returns
    -------
    WorldView

    Examples
    --------
    >>> import sylva
    >>> w = sylva.world(seed=3, size=16, chunk=16, plants=False)
    >>> w.stats["chunks"], w.stats["quads"] > 0
    (1, True)
    """
    from .world import World, WorldConfig

    if isinstance(seed, bool) or not isinstance(seed, int):
        raise SylvaError(f"seed: expected a whole number, got {seed!r}")
    cols = check_size(size, "size")
    try:
        cfg = WorldConfig(seed=seed, chunk_size=chunk, caves=caves, vegetation=plants,
                          grass=grass, **config)  # fmt: skip
    except TypeError as exc:
        raise SylvaError(f"world: {exc}") from None
    store = World(cfg, size=cols).generate(workers=workers)
    return WorldView(store, grass=grass)
