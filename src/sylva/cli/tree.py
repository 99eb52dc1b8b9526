"""``sylva tree``: grow a Weber–Penn tree and write it as a mesh, an image or an animation.

Examples::

    sylva tree --list                                    # shipped and user species
    sylva tree --example > my_tree.txt                   # the annotated species file
    sylva tree --sheet -o sheet.png                      # every species at three ages
    sylva tree silver_birch -o birch.png --season autumn # autumn colours (winter: bare)
    sylva tree silver_birch -o b.png --season autumn --leaf-turn 0.5 --leaf-fall 0.2
    sylva tree quaking_aspen -o aspen.glb --age 30 --seed 4
    sylva tree black_oak -o oak.png                      # a rendered image
    sylva tree weeping_willow -o willow.pov              # POV-Ray scene (mesh2)
    sylva tree scots_pine -o pine.glb --animate wind --wind 1.5 --seconds 4
    sylva tree fan_palm -o palm.mp4 --animate growth --seconds 6
    sylva tree my_tree.txt -o mine.obj                   # a configuration file

The output format follows the extension: any mesh format of ``sylva export`` (``.glb``,
``.gltf``, ``.obj``, ``.ply``, ``.stl``, ``.pov``, ``.usd``…), an image (``.png``, ``.jpg``),
or with ``--animate``: ``.glb`` (skinned glTF animation), ``.gif`` or ``.mp4``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import SylvaError

_IMAGES = {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp", ".webp"}
_MOVIES = {".gif", ".mp4", ".m4v", ".mov"}


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "tree",
        help="grow a tree of a species (Weber-Penn, events in time) with wind and growth",
        description="Grow a tree from a species preset or a configuration file and write a "
                    "mesh, an image, a POV-Ray scene, or a growth/wind animation (glTF, GIF, "
                    "MP4).  See --list for the species.",
    )
    p.add_argument("species", nargs="?", metavar="SPECIES_OR_CONFIG",
                   help="species name (see --list) or a configuration file")
    p.add_argument("-o", "--output", dest="out", metavar="OUT",
                   help="output: mesh (.glb .obj .ply .stl .pov …), image (.png), or with "
                        "--animate: .glb, .gif or .mp4")
    p.add_argument("--list", action="store_true",
                   help="list the shipped and the user's species and exit")
    p.add_argument("--example", action="store_true",
                   help="print the annotated example species file (every key and its range)")
    p.add_argument("--sheet", action="store_true",
                   help="write a contact sheet (-o PNG): every species at three ages, one scale")
    p.add_argument("--only", default=None, metavar="A,B",
                   help="with --sheet: only these species (comma-separated)")
    p.add_argument("--age", type=float, default=None, metavar="T",
                   help="age in years (default: the species' Age)")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="random seed (default 0)")
    p.add_argument("--wind", type=float, default=None, metavar="STRENGTH",
                   help="wind strength: 0 calm, 1 breeze, 3 storm (default 1 with --animate "
                        "wind; a still image is bent by the wind at t=0)")
    p.add_argument("--animate", choices=("growth", "wind"), default=None,
                   help="write an animation of growth (age 0 to --age) or of wind")
    p.add_argument("--seconds", type=float, default=4.0, metavar="N",
                   help="animation length in seconds (default 4)")
    p.add_argument("--fps", type=float, default=None,
                   help="frames per second (default 24 for wind, 12 for growth)")
    p.add_argument("--size", default="640x640", metavar="WxH", help="image/video size")
    p.add_argument("--no-leaves", action="store_true", help="leave the leaves out")
    p.add_argument("--textures", metavar="SIZE", default=None,
                   help="bake the bark and leaf textures the renderer draws to SIZE x SIZE "
                        "PNG images (a power of two, e.g. 512) that the file references "
                        "(glTF/GLB, OBJ, USD, POV-Ray; default: colours only)")  # fmt: skip
    p.add_argument("--season", choices=("spring", "summer", "autumn", "winter"), default=None,
                   help="show a deciduous tree in this season (default: the species' Season)")
    p.add_argument("--leaf-turn", type=float, default=None, metavar="F",
                   help="autumn: the fraction of the leaves turned, 0…1 (default: the "
                        "species' LeafTurn, 1)")
    p.add_argument("--leaf-fall", type=float, default=None, metavar="F",
                   help="autumn: the fraction of the leaves fallen, 0…1 (1: bare; default: "
                        "the species' LeafFall, 0)")
    from ._lod import add_lod

    add_lod(p)
    p.set_defaults(func=run)


def _size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(x) for x in text.lower().split("x"))
    except ValueError:
        raise SylvaError(f"--size: expected WxH such as 640x480, got {text!r}") from None
    if w < 16 or h < 16:
        raise SylvaError(f"--size: expected at least 16x16, got {text!r}")
    return w, h


def run(args: argparse.Namespace) -> int:
    from ..tree import Tree, Wind, species_info, species_names

    if args.list:
        from ..tree.species import user_species_dirs

        for name in species_names():
            info = species_info(name)
            origin = "" if info["origin"] == "shipped" else f"  [user: {info['origin']}]"
            print(f"{name:20s} {info['Name']}: {info['Description']}{origin}")
            print(f"{'':20s} source: {info['Source']}")
        print("user species folders: " + ", ".join(str(d) for d in user_species_dirs()))
        return 0
    if args.example:
        from ..tree.species import example_text

        print(example_text(), end="")
        return 0
    if args.sheet:
        return _sheet(args)
    if not args.species:
        raise SylvaError("tree: expected a species name or a configuration file (or --list)")
    if not args.out:
        raise SylvaError("tree: expected an output file (-o OUT)")
    out = Path(args.out)
    ext = out.suffix.lower()
    from ._lod import lod_levels

    n_lod = lod_levels(args, out)
    from ._lod import check_textures

    check_textures(args, out, n_lod)
    if n_lod is not None and (args.animate or args.wind):
        raise SylvaError("--lod: write levels of detail of the still tree (leave out "
                         "--animate and --wind; the levels carry wind as _WIND vertex data)")
    if args.textures is not None:
        from ..assets import textured_export
        from ..geometry.mesh import Scene

        textured_export(Scene(), ext.lstrip("."), args.textures)  # fail before growing
    tree = Tree(args.species, seed=args.seed, season=args.season, leaf_turn=args.leaf_turn,
                leaf_fall=args.leaf_fall)
    age = tree.default_age if args.age is None else args.age
    if age <= 0:
        raise SylvaError(f"--age: expected a positive age in years, got {age}")
    mesh_opts = {"leaves": not args.no_leaves}
    if args.animate:
        return _animate(args, tree, age, out, ext, mesh_opts)
    tree.grow(age)
    if n_lod is not None:
        from ..tree.lod import tree_lods
        from ._lod import describe, finish_chain, write_chain

        chain = finish_chain(tree_lods(tree, levels=min(n_lod, 3), **mesh_opts), n_lod, args)
        if args.textures is not None:
            from ._lod import bake_chain

            chain = bake_chain(chain, args.textures)
        write_chain(chain, out)
        print(f"{tree.name}, seed {args.seed}, age {age:g}: {describe(chain)}")
        print(f"wrote {out}")
        return 0
    tm = tree.mesh(**mesh_opts)
    mesh = tm.mesh
    if args.wind:
        mesh = Wind(args.wind, seed=args.seed).mesh_at(tm, 0.0)
    from ..geometry.mesh import Scene

    scene = Scene([mesh], name=tree.name.replace(" ", "_"))
    s = tree.stats()
    print(f"{tree.name}, seed {args.seed}, age {age:g}: height {s['height']:.2f} m, stems per "
          f"level {s['stems']}, {s['leaves']} leaves, {mesh.n_triangles} triangles")
    if ext in _IMAGES:
        from ..render import render, save_image

        save_image(render(scene, size=_size(args.size)), out)
    elif ext in _MOVIES:
        raise SylvaError(f"{ext} needs --animate growth or --animate wind")
    else:
        from ..geometry.exchange import write

        if args.textures is not None:
            from ..assets import textured_export

            scene = textured_export(scene, ext.lstrip("."), args.textures)
        write(scene, out)
    print(f"wrote {out}")
    return 0


def _animate(args, tree, age: float, out: Path, ext: str, mesh_opts: dict) -> int:
    from ..tree import Wind
    from ..tree.animation import growth_animation, growth_meshes, wind_animation, wind_meshes

    seconds = args.seconds
    if seconds <= 0:
        raise SylvaError(f"--seconds: expected a positive duration, got {seconds}")
    fps = args.fps or (24.0 if args.animate == "wind" else 12.0)
    wind = Wind(1.0 if args.wind is None else args.wind, seed=args.seed)
    if ext == ".glb":
        from ..geometry.exchange.gltf_animation import write_animated_glb

        if args.animate == "wind":
            tm = tree.grow(age).mesh(**mesh_opts)
            anim = wind_animation(tm, wind, seconds, fps)
        else:
            anim = growth_animation(tree, min(0.05 * age, 0.5), age, seconds, fps)
        write_animated_glb(anim, out)
        print(f"wrote {out}: {len(anim.times)} keyframes, {len(anim.bind_matrices)} joints")
        return 0
    if ext not in _MOVIES:
        raise SylvaError(f"--animate writes .glb, .gif or .mp4, not {ext or out.name!r}")
    from ..render import growth_frames, write_animation

    size = _size(args.size)
    frames = max(2, int(round(seconds * fps)))
    if args.animate == "wind":
        tm = tree.grow(age).mesh(**mesh_opts)
        meshes = list(wind_meshes(tm, wind, seconds, fps))
    else:
        meshes = list(growth_meshes(tree, min(0.05 * age, 0.5), age, frames, **mesh_opts))
    write_animation(growth_frames(meshes, size), out, fps=fps, total=len(meshes))
    print(f"wrote {out}: {len(meshes)} frames")
    return 0


def _sheet(args) -> int:
    import time

    from PIL import Image

    from .._atomic import save_buffered
    from ._tree_sheet import contact_sheet

    if not args.out or Path(args.out).suffix.lower() not in _IMAGES:
        raise SylvaError("tree --sheet: expected an image to write (-o sheet.png)")
    names = [n.strip() for n in args.only.split(",") if n.strip()] if args.only else None
    t = time.perf_counter()
    img = contact_sheet(names, seed=args.seed, log=print)
    fmt = Image.registered_extensions()[Path(args.out).suffix.lower()]
    rgb = img.convert("RGB") if fmt == "JPEG" else img
    save_buffered(args.out, lambda fh: rgb.save(fh, format=fmt))
    print(f"wrote {args.out} in {time.perf_counter() - t:.1f} s")
    return 0

