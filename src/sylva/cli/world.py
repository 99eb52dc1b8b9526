"""``sylva world``: generate a voxel world with biomes and vegetation; render it or export it.

Examples::

    sylva world --seed 4 --size 512x512 -o world.png            # rendered at an angle
    sylva world --seed 4 --size 256x256 -o top.png --view top --biomes
    sylva world --seed 4 --size 512x512 -o world.glb --chunk 32 # EXT_mesh_gpu_instancing
    sylva world --seed 4 --size 16384x16384 -o world.zarr      # the world store
    sylva world --seed 4 --size 16384x16384 -o world.zarr --resume
    sylva world --seed 4 --size 2048x2048 -o tiles/ --format 3dtiles
    sylva world --seed 4 --size 16384x16384 -o /shared/world.zarr --scheduler tcp://head:8786

The same seed gives the same world, on one core or on a cluster.  Chunks are Dask tasks
(:mod:`sylva.cluster`): a local cluster of worker processes by default (``--workers N``),
an existing one with ``--scheduler`` (or ``SYLVA_SCHEDULER``).  A ``.zarr`` output is the
world store (:mod:`sylva.world.store`); PNG and GLB outputs are made from a store in a
temporary folder (``--keep DIR`` keeps it).
"""

from __future__ import annotations

import argparse
import re
import sys
import tempfile
import time
from pathlib import Path

from .._atomic import save_buffered
from ..errors import SylvaError


def _size(text: str) -> tuple[int, int]:
    try:
        w, _, h = text.lower().partition("x")
        out = (int(w), int(h or w))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected WxD (e.g. 512x512), got {text!r}") from None
    if min(out) < 1:
        raise argparse.ArgumentTypeError(f"sizes must be positive, got {text!r}")
    return out


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "world",
        help="generate a voxel world with biomes and L-system vegetation",
        description="Generate a chunked voxel world (seed 004): terrain from octave noise, "
                    "biomes from the humidity/temperature table, L-system plants; render it "
                    "to PNG or export it to GLB with instanced plants.",
    )  # fmt: skip
    p.add_argument("-o", "--output", dest="out", required=True, metavar="OUT",
                   help="output: .png (rendered image), .glb (glTF with instancing), .zarr "
                        "(the world store) or a folder with --format 3dtiles")  # fmt: skip
    p.add_argument("--format", choices=("auto", "3dtiles"), default="auto",
                   help="3dtiles: an OGC 3D Tiles 1.1 tileset in the folder OUT (default: "
                        "from OUT's suffix)")  # fmt: skip
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT", default=None,
                   help="run on an existing Dask cluster (default $SYLVA_SCHEDULER; else a "
                        "local cluster); its workers need OUT on a shared file system")
    p.add_argument("--resume", action="store_true",
                   help="continue an interrupted .zarr store (only the missing chunks)")
    p.add_argument("--seed", type=int, default=0, help="world seed (default 0)")
    p.add_argument("--size", type=_size, default=(512, 512), metavar="WxD",
                   help="columns along x and z (default 512x512)")
    p.add_argument("--chunk", type=int, default=32, metavar="N", help="chunk size (default 32)")
    p.add_argument("--biomes", action="store_true",
                   help="also write the biome map image, OUT with .biomes.png for its suffix")
    p.add_argument("--view", choices=("angle", "top"), default="angle",
                   help="PNG camera: at an angle (default) or from above")
    p.add_argument("--image-size", type=_size, default=(1600, 1000), metavar="WxH",
                   help="PNG size in pixels (default 1600x1000)")
    p.add_argument("--workers", type=int, default=None,
                   help="worker processes of the local Dask cluster (default: all cores; 1: "
                        "in this process)")  # fmt: skip
    p.add_argument("--caves", action="store_true", help="carve caves")
    p.add_argument("--no-plants", action="store_true", help="no vegetation")
    p.add_argument("--no-grass", action="store_true", help="no grass tufts")
    p.add_argument("--no-shadows", action="store_true", help="PNG: no shadows")
    p.add_argument("--tree-variants", type=int, default=16, metavar="N",
                   help="individuals per tree species (0: every tree grown from its own "
                        "position, as seed 004 does)")  # fmt: skip
    p.add_argument("--plant", action="append", default=[], metavar="BIOME=NAME[,NAME]",
                   help="plants of a biome (repeatable): built-in species (acacia, oak, birch, "
                        "jungle, baobab, shrub, cactus), tree:SPECIES (a sylva.tree species) "
                        "or an L-system file")  # fmt: skip
    p.add_argument("--keep", metavar="DIR",
                   help="PNG/GLB/3dtiles: keep the world store made on the way in DIR")
    p.add_argument("--impostors", type=float, default=None, metavar="DIST",
                   help=".glb: plants farther than DIST blocks from the centre are drawn as "
                        "impostors (crossed quads with a baked image of the plant)")
    p.add_argument("--quiet", action="store_true", help="no progress output")
    p.set_defaults(func=run)


def render_store(store, out: Path, *, view: str, size, shadows: bool, grass: bool) -> None:
    """Render a generated world to an image file (terrain + expanded plants)."""
    from ..grown import render_world
    from ..render import save_image

    save_image(render_world(store, size=size, view=view, shadows=shadows, grass=grass), out)


def _plants(specs: list[str]) -> tuple[dict | None, dict | None]:
    """``--plant`` options as WorldConfig ``plants`` and ``species``."""
    from ..world import SPECIES, Biome, Species

    if not specs:
        return None, None
    biomes = {b.name.lower(): b for b in Biome}
    plants: dict[str, list[str]] = {}
    extra: dict = {}
    for spec in specs:
        biome, sep, names = spec.partition("=")
        biome = biome.strip().lower()
        if not sep or biome not in biomes:
            raise SylvaError(f"--plant {spec!r}: expected BIOME=NAME[,NAME] with a biome among "
                             + ", ".join(biomes))  # fmt: skip
        out = []
        for name in filter(None, (n.strip() for n in names.split(","))):
            if name.startswith("tree:"):
                key = name.replace(":", "_")
                extra[key] = Species.from_tree(key, name[5:])
                name = key
            elif Path(name).suffix in (".lsys", ".txt"):
                key = "lsys_" + re.sub(r"\W", "_", Path(name).stem)
                extra[key] = Species.from_lsystem(key, name)
                name = key
            elif name not in SPECIES and name != "shrub":
                raise SylvaError(f"--plant: unknown plant {name!r}; expected one of "
                                 + ", ".join([*SPECIES, "shrub"]) + ", tree:SPECIES or a file")
            out.append(name)
        plants[biome] = out
    return plants, extra or None


def run(args) -> int:
    from ..world import World, WorldConfig, WorldStore

    out = Path(args.out)
    ext = out.suffix.lower()
    kind = "3dtiles" if args.format == "3dtiles" else {
        ".png": "png", ".jpg": "png", ".jpeg": "png", ".glb": "glb", ".zarr": "store"
    }.get(ext)  # fmt: skip
    if kind is None:
        raise SylvaError(f"cannot write {str(out)!r}: expected a .png, .glb or .zarr output "
                         "(or --format 3dtiles and a folder)")  # fmt: skip
    if args.resume and kind != "store" and not args.keep:
        raise SylvaError("--resume continues a world store: expected a .zarr output or --keep")
    if getattr(args, "impostors", None) is not None and (ext != ".glb" or args.impostors < 0):
        raise SylvaError("--impostors: expected a distance >= 0 in blocks and a .glb output, "
                         f"got {args.impostors:g} and {ext or str(out)!r}")
    plants, species = _plants(args.plant)
    cfg = WorldConfig(
        seed=args.seed, chunk_size=args.chunk, caves=args.caves,
        vegetation=not args.no_plants, grass=not args.no_grass,
        tree_variants=args.tree_variants or None, plants=plants, species=species,
    )  # fmt: skip
    world = World(cfg, size=args.size)
    say = (lambda *a: None) if args.quiet else (lambda *a: print(*a, file=sys.stderr))

    from ..cluster import connect

    t0 = time.perf_counter()
    target = out if kind == "store" else (Path(args.keep) if args.keep else None)
    n_tasks = len(world.blocks())
    # one cluster for the whole command: the chunks, then the models or the tiles
    with connect(args.scheduler, workers=args.workers, tasks=n_tasks) as run:
        store = world.generate(target, progress=not args.quiet, resume=args.resume,
                               runner=run)  # fmt: skip
        try:
            _write(args, out, kind, store, run, say, t0)
        finally:
            if isinstance(store, WorldStore):
                store.close()
    return 0


def _write(args, out: Path, kind: str, store, run, say, t0: float) -> None:
    """Everything made from the store: the biome map, then the models, tiles, GLB or PNG."""
    say(f"generated {len(store)} chunks in {time.perf_counter() - t0:.1f} s: "
        f"{store.n_quads} quads, {store.n_plants} plants and grass tufts")  # fmt: skip
    if args.biomes:
        from PIL import Image

        bpath = out.with_name(out.stem + ".biomes.png")
        image = Image.fromarray(store.biome_map())  # row 0: lowest z, as --view top
        save_buffered(bpath, lambda fh: image.save(fh, format="PNG"))
        say(f"wrote {bpath}")
    if kind == "store":
        from ..world.store import write_models

        n = write_models(store, runner=run)
        say(f"wrote {out}: {len(store)} chunks, {store.n_plants} plant instances, "
            f"{n} plant models")  # fmt: skip
    elif kind == "3dtiles":
        from .._impostor import world_impostor
        from ..world.tiles import write_tileset

        info = write_tileset(store, out, grass=not args.no_grass, progress=not args.quiet,
                             runner=run, impostor=world_impostor())  # fmt: skip
        say(f"wrote {out}/tileset.json: {info['tiles']} tiles in {info['levels']} levels, "
            f"{info['impostors']} far plants as impostors of {info['impostor_models']} "
            "models")  # fmt: skip
    elif kind == "glb":
        from ..world.export import write_world_glb

        far = {}
        if args.impostors is not None:
            from .._impostor import world_impostor

            far = {"impostor": world_impostor(), "near": args.impostors}
        with tempfile.TemporaryDirectory(prefix="sylva-tiles-") as tiles:
            info = write_world_glb(store, out, tiles=tiles, grass=not args.no_grass, **far)
        far_txt = (f" ({info['impostor_instances']} far ones as impostors)"
                   if args.impostors is not None else "")
        say(f"wrote {out}: {info['models']} plant models, {info['instances']} instances"
            f"{far_txt}, {info['terrain_triangles']} terrain triangles")  # fmt: skip
    else:
        render_store(store, out, view=args.view, size=args.image_size,
                     shadows=not args.no_shadows, grass=not args.no_grass)  # fmt: skip
        say(f"wrote {out}")
