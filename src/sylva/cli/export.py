"""``sylva export FILE -o OUT``: derive an L-system, interpret it, mesh it and write OUT.

The format comes from OUT's extension (``.glb .gltf .obj .ply .stl .scad .pov .svg``, and
``.usd .usda .usdc`` with usd-core).  ``.svg`` draws the turtle's lines (for 2D systems);
the other formats write meshes.  Programs in seed 004's engine format are interpreted as its
executor does, with random angles of ±0.2 × the header angle drawn from ``--seed``.
"""

from __future__ import annotations

import argparse
import sys

from ..errors import SylvaError
from ._common import limit_type, steps_type

__all__ = ["register", "run"]


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "export",
        help="derive an L-system and write its geometry as a mesh (or SVG) file",
        description=__doc__.split("\n\n")[1] if __doc__ else None,
    )
    p.add_argument("file", metavar="FILE",
                   help="L-system file (.lsys, classic or engine format), or a built-in "
                        "example name (`sylva examples` lists them)")  # fmt: skip
    p.add_argument("-o", "--output", required=True, metavar="OUT",
                   help="output file; its extension picks the format")  # fmt: skip
    p.add_argument(
        "-n", "--steps", type=steps_type, default=None, metavar="STEPS",
        help="derivation steps (default: the file's own, if any)",
    )  # fmt: skip
    p.add_argument(
        "-r", "--seed", type=int, default=None, metavar="S",
        help="random seed for stochastic rules (and the engine turtle's salt)",
    )  # fmt: skip
    p.add_argument(
        "--detail", type=int, default=None, metavar="N",
        help="sides around each branch (default: the file's detail, else 8)",
    )  # fmt: skip
    p.add_argument("--mode", choices=("tube", "prism", "cone"), default="tube",
                   help="branch construction (default: tube)")  # fmt: skip
    p.add_argument("--taper", choices=("none", "leonardo"), default="none",
                   help="radii from the turtle, or by Leonardo's rule")  # fmt: skip
    p.add_argument("--limit", type=limit_type, default=None, metavar="N",
                   help="stop before a word passes N modules (default 50,000,000)")  # fmt: skip
    p.add_argument("--keep-last", action="store_true",
                   help="when the module limit stops the derivation, export the word of the "
                        "last step that fits")  # fmt: skip
    p.add_argument("--up", choices=("y", "z"), default=None,
                   help="up axis of the file (default: the format's convention: Z for STL, "
                        "PLY and OpenSCAD, Y for glTF, OBJ, USD and POV-Ray)")  # fmt: skip
    p.add_argument("--textures", metavar="SIZE", default=None,
                   help="bake the bark, leaf and grass textures the renderer draws to SIZE x "
                        "SIZE PNG images (a power of two, e.g. 512) that the file references "
                        "(glTF/GLB, OBJ, USD, POV-Ray; default: colours only)")  # fmt: skip
    p.add_argument("--view", metavar="V", default=None,
                   help="cpfg: the view file (.v) to read (default: the one beside FILE)")
    from ._lod import add_lod

    add_lod(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..geometry.build import build_mesh
    from ..geometry.exchange import format_of, write
    from ..geometry.mesh import Scene
    from ..lsystem import render_word
    from ..turtle import interpret
    from ._lod import lod_levels
    from .derive import load_program

    fmt = format_of(args.output)  # fail before deriving when OUT is unusable
    if args.textures is not None:
        from ..assets import textured_export

        textured_export(Scene(), fmt, args.textures)  # a bad size or format fails now
    n_lod = lod_levels(args, args.output)
    from ._lod import check_textures

    check_textures(args, args.output, n_lod)
    if args.up is not None and fmt in ("svg", "pov"):
        raise SylvaError(f"--up: {fmt.upper()} files have a fixed frame; leave --up out")
    from ..lsystem import DEFAULT_MODULE_LIMIT
    from .derive import derive_keeping

    program = load_program(args.file, view=args.view)
    limit = DEFAULT_MODULE_LIMIT if args.limit is None else args.limit
    word = derive_keeping(program, args.steps, seed=args.seed, limit=limit,
                          keep_last=args.keep_last)  # fmt: skip
    word = render_word(program, word)
    extra = {}
    if program.turtle == "engine" and "angle_var" not in program.settings:
        extra["angle_var"] = 0.2  # seed 004's executor default (±0.2 × the header angle)
    geometry = interpret(word, program, seed=args.seed, **extra)
    if n_lod is not None:
        from ..geometry.lod import plant_lods
        from ._lod import describe, finish_chain, write_chain

        chain = plant_lods(geometry, detail=args.detail, mode=args.mode,
                           taper=None if args.taper == "none" else args.taper,
                           levels=min(n_lod, 3))  # fmt: skip
        chain.name = program.name if getattr(program, "name", None) else "plant"
        chain = finish_chain(chain, n_lod, args)
        if args.textures is not None:
            from ._lod import bake_chain

            chain = bake_chain(chain, args.textures)
        write_chain(chain, args.output, args.up)
        what = describe(chain)
    elif fmt == "svg":
        write(geometry, args.output, format=fmt)
        what = f"{geometry.n_segments} segments"
    else:
        scene = build_mesh(
            geometry, detail=args.detail, mode=args.mode,
            taper=None if args.taper == "none" else args.taper,
        )  # fmt: skip
        if args.textures is not None:
            from ..assets import textured_export

            scene = textured_export(scene, fmt, args.textures)
        options = {} if args.up is None else {"up": args.up}
        write(scene, args.output, format=fmt, **options)
        what = f"{scene.n_triangles} triangles"
    if what.startswith("0 "):  # a valid, empty file: the word draws nothing
        what += "; nothing to draw, the file holds an empty scene"
    print(f"sylva: wrote {args.output} ({len(word)} modules, {what})", file=sys.stderr)
    return 0
