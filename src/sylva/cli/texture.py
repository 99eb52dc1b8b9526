"""``sylva texture``: render procedural textures, animations and presets.

Examples::

    sylva texture marble -o marble.png --size 1024x1024 --seed 3 --tileable
    sylva texture simplex -o clouds.gif --frames 48 --octaves 6 --colormap clouds
    sylva texture fern -o fern.png
    sylva texture --list
    sylva texture bark -o bark.png --save-preset bark.toml
    sylva texture --preset bark.toml -o again.png
    sylva texture marble -o m.png --turbulence 4 --colors "0:#223344,0.6:#88aa55,1:white"
    sylva texture worley -o f5.png --cell f5 --density 3 --colors sunset.gpl
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from .._atomic import save_buffered
from ..errors import SylvaError

_OPTIONS = (
    ("size", "--size", str, "WxH", "image size, e.g. 1024x768 (default 512x512)"),
    ("seed", "--seed", int, "S", "random seed (default: the reference permutation)"),
    ("scale", "--scale", float, "F", "noise cells across the width"),
    ("octaves", "--octaves", int, "N", "octaves of fBm"),
    ("persistence", "--persistence", float, "P", "amplitude ratio between octaves"),
    ("lacunarity", "--lacunarity", float, "L", "frequency ratio between octaves"),
    ("colormap", "--colormap", str, "NAME", "colour map (see --list)"),
    ("turbulence", "--turbulence", float, "A", "marble and wood: turbulence amplitude "
     "(0: pure stripes or rings)"),
    ("stripes", "--stripes", float, "N", "marble: stripe periods across the width"),
    ("rings", "--rings", float, "N", "wood: rings across the width"),
    ("density", "--density", float, "D", "Worley: mean feature points per cell (a Poisson "
     "process; default one jittered point per cell)"),
    ("fractal", "--fractal", str, "MODE", "noise octave sum: fbm, turbulence or ridged"),
    ("output", "--cell", str, "OUT", "Worley output: f1 .. fN (any order), f2-f1, f1+f2, "
     "f1*f2, cell, ..."),
    ("metric", "--metric", str, "M", "Worley metric: euclidean, manhattan, chebyshev"),
    ("interpolation", "--interpolation", str, "I", "linear, cosine, cubic or quintic"),
    ("warp", "--warp", float, "A", "domain-warp amount in noise cells"),
    ("iterations", "--iterations", int, "N", "L-system iterations"),
    ("maxiter", "--maxiter", int, "N", "fractal iteration limit"),
    ("speed", "--speed", float, "T", "animation: time step per frame (noise cells)"),
    ("normal_map", "--normal-map", float, "STRENGTH", "write a normal map of the height"),
)


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "texture",
        help="render a procedural texture (noise, patterns, fractals, L-systems)",
        description="Render a procedural texture to PNG, or an animation to GIF/MP4. KIND is a "
                    "texture kind or a preset name (see --list).",
    )
    p.add_argument("kind", nargs="?", metavar="KIND", help="texture kind or preset name")
    p.add_argument("-o", "--output", dest="out", metavar="OUT",
                   help="output file: .png (or .jpg, .tif, .bmp); .gif or .mp4 with --frames")
    for dest, flag, typ, meta, text in _OPTIONS:
        p.add_argument(flag, dest=dest, type=typ, metavar=meta, default=None, help=text)
    p.add_argument("--colors", metavar="LIST|FILE", default=None,
                   help="custom colour map: comma-separated colours (#rrggbb, #rgb or CSS "
                        "names) with optional stop positions, e.g. '0:#223344,0.7:#88aa55,"
                        "1:white', or a palette file (.gpl GIMP palette, .toml with colors "
                        "= [...] or stops = [[pos, colour], ...], or text: one '[pos] colour'"
                        " a line)")
    p.add_argument("--tileable", action="store_true", default=None,
                   help="seamless (periodic) output")
    p.add_argument("--frames", type=int, metavar="N", default=None,
                   help="render N frames of an animation (GIF or MP4)")
    p.add_argument("--fps", type=float, default=None, help="animation frame rate (default 24)")
    p.add_argument("--preset", metavar="FILE", help="load a TOML preset file")
    p.add_argument("--save-preset", metavar="FILE", help="write the parameter set as TOML")
    p.add_argument("--graph", metavar="FILE",
                   help="render a texture graph file (.toml or .json; see the texture-graph "
                        "reference); uses --size, --tileable, --frames/--fps/--speed (time), "
                        "--colormap/--colors")
    p.add_argument("--save-graph", metavar="FILE",
                   help="write the texture (KIND or --preset) as a graph file (.toml, .json)")
    p.add_argument("--list", action="store_true", help="list texture kinds, presets and maps")
    p.add_argument("--lsystem", metavar="SOURCE",
                   help="draw a sylva L-system (a file in any dialect, or an example name, e.g. "
                        "36-seed003-lstudio-tree) as a 2D line texture; uses --size, --seed, "
                        "--iterations (derivation steps) and --tileable")
    p.set_defaults(func=run)


def _listing() -> str:
    from ..texture import COLORMAPS, PRESETS, TEXTURE_KINDS

    lines = ["Texture kinds:"]
    lines += [f"  {k:<14} {v}" for k, v in TEXTURE_KINDS.items()]
    lines.append("")
    lines.append("Presets:")
    for name, r in PRESETS.items():
        desc = r.get("description", "")
        lines.append(f"  {name:<20} {r['kind']:<12} {desc}".rstrip())
    lines.append("")
    lines.append("Colour maps: " + ", ".join(sorted(COLORMAPS)))
    return "\n".join(lines)


def _custom_colors(value: str, kind: str) -> list:
    """``--colors``: a colour list or a palette file, as ``[position, "#rrggbb"]`` pairs."""
    from ..texture.colormap import load_palette, parse_colors
    from ..texture.presets import _DEFAULT_CMAP

    if kind not in _DEFAULT_CMAP:
        raise SylvaError(f"--colors: {kind} textures take no colour map")
    path = Path(value)
    if path.suffix.lower() in (".gpl", ".toml", ".txt", ".pal") or (
            "," not in value and path.is_file()):
        cmap = load_palette(path)
    else:
        cmap = parse_colors(value, option="--colors")
    return [[float(p), "#" + "".join(f"{round(float(v) * 255):02x}" for v in c)]
            for p, c in zip(cmap.positions, cmap.colors)]


def _save_image(path: Path, frames: list[np.ndarray], fps: float) -> None:
    suffix = path.suffix.lower()
    if len(frames) == 1 and suffix not in (".gif", ".mp4"):
        from PIL import Image

        try:
            fmt = Image.registered_extensions()[suffix]
        except KeyError:
            raise SylvaError(f"cannot write {path}: unknown image format {suffix!r}") from None
        image = Image.fromarray(frames[0])
        try:
            save_buffered(path, lambda fh: image.save(fh, format=fmt))
        except (KeyError, ValueError) as exc:
            raise SylvaError(f"cannot write {path}: unknown image format ({exc})") from None
        return
    if suffix not in (".gif", ".mp4"):
        raise SylvaError(f"an animation needs a .gif or .mp4 output, got {path.name}")
    from ..render.animate import write_animation

    if suffix == ".mp4":
        h, w = frames[0].shape[:2]
        frames = [f[: h - h % 2, : w - w % 2] for f in frames]  # yuv420p needs even sizes
    # one writer for every animation: atomic, and a full disk is an error, not a short file
    write_animation(frames, path, fps=fps, progress=False)


def run(args: argparse.Namespace) -> int:
    from ..texture import presets

    if args.list:
        print(_listing())
        return 0
    if args.lsystem:
        return _run_lsystem(args)
    if args.graph:
        return _run_graph(args)
    if args.preset:
        recipe = presets.load_preset(args.preset)
        if args.kind and args.kind != recipe["kind"]:
            raise SylvaError(f"KIND {args.kind!r} contradicts the preset's kind "
                             f"{recipe['kind']!r}; give one or the other")
    elif args.kind:
        recipe = presets.resolve(args.kind)
    else:
        raise SylvaError("give a texture KIND (or --preset FILE, or --list)")
    recipe = dict(recipe)
    for dest, *_ in _OPTIONS:
        v = getattr(args, dest)
        if v is not None:
            recipe[dest] = v
    if args.colors is not None:
        if args.colormap is not None:
            raise SylvaError("give --colors or --colormap, not both")
        recipe["colormap"] = _custom_colors(args.colors, recipe["kind"])
    if args.tileable:
        recipe["tileable"] = True
    if args.frames is not None:
        recipe["frames"] = args.frames
    if args.fps is not None:
        recipe["fps"] = args.fps
    recipe = presets.resolve(recipe)
    if args.save_preset:
        presets.save_preset(recipe, args.save_preset)
        print(f"wrote preset {args.save_preset}")
    if args.save_graph:
        from ..texture.graph import from_recipe

        from_recipe(recipe).save(args.save_graph)
        print(f"wrote graph {args.save_graph}")
    if not args.out:
        if args.save_preset or args.save_graph:
            return 0
        raise SylvaError("give an output file with -o OUT.png")
    out = Path(args.out)
    nframes = int(recipe.get("frames", 1))
    fps = float(recipe.get("fps", 24.0))
    if nframes < 1 or fps <= 0:
        raise SylvaError("--frames must be at least 1 and --fps positive")
    if nframes > 1 or out.suffix.lower() in (".gif", ".mp4"):
        frames = presets.render_frames(recipe, nframes)
    else:
        frames = [presets.render(recipe)]
    _save_image(out, frames, fps)
    print(f"wrote {out} ({recipe['size'][0]}x{recipe['size'][1]}, {len(frames)} frame"
          f"{'s' if len(frames) != 1 else ''})")
    return 0


def _run_lsystem(args: argparse.Namespace) -> int:
    from ..plant import plant_texture
    from ..texture.presets import parse_size

    if args.kind:
        raise SylvaError("--lsystem draws its own L-system: give it without a KIND")
    ignored = [flag for dest, flag, *_ in _OPTIONS if dest not in ("size", "seed", "iterations")
               and getattr(args, dest) is not None]
    ignored += [f for f, v in (("--frames", args.frames), ("--preset", args.preset),
                               ("--colors", args.colors),
                               ("--save-preset", args.save_preset)) if v is not None]
    if ignored:
        raise SylvaError(f"--lsystem takes --size, --seed, --iterations and --tileable; "
                         f"not {', '.join(ignored)}")
    if not args.out:
        raise SylvaError("give an output file with -o OUT.png")
    w, h = parse_size(args.size or "512x512")
    img = plant_texture(args.lsystem, (h, w), steps=args.iterations, seed=args.seed,
                        tileable=bool(args.tileable), count=4 if args.tileable else 1,
                        size=0.45 if args.tileable else 0.9)
    out = Path(args.out)
    _save_image(out, [img], 24.0)
    print(f"wrote {out} ({w}x{h}, L-system {args.lsystem})")
    return 0


def _run_graph(args: argparse.Namespace) -> int:
    from ..texture import graph as tg
    from ..texture.presets import parse_size

    if args.kind or args.preset:
        raise SylvaError("--graph renders its own graph: give it without a KIND or --preset")
    allowed = ("size", "speed", "colormap")
    ignored = [flag for dest, flag, *_ in _OPTIONS if dest not in allowed
               and getattr(args, dest) is not None]
    if args.save_preset:
        ignored.append("--save-preset")
    if ignored:
        raise SylvaError(f"--graph takes --size, --tileable, --frames, --fps, --speed, "
                         f"--colormap and --colors; not {', '.join(ignored)}")
    g = tg.load(args.graph)
    if args.size:
        g.size = list(parse_size(args.size))
    if args.tileable:
        g.tileable = True
    if args.colors is not None or args.colormap is not None:
        if args.colors is not None and args.colormap is not None:
            raise SylvaError("give --colors or --colormap, not both")
        if g.output.spec.output == "colour":
            raise SylvaError("--colors/--colormap: this graph's output is already a colour")
        g.colormap = (_custom_colors(args.colors, "value") if args.colors is not None
                      else args.colormap)
    if args.save_graph:
        g.save(args.save_graph)
        print(f"wrote graph {args.save_graph}")
    if not args.out:
        if args.save_graph:
            return 0
        raise SylvaError("give an output file with -o OUT.png")
    out = Path(args.out)
    nframes = int(args.frames or 1)
    fps = float(args.fps or 24.0)
    if nframes < 1 or fps <= 0:
        raise SylvaError("--frames must be at least 1 and --fps positive")
    if nframes > 1 or out.suffix.lower() in (".gif", ".mp4"):
        speed = 0.05 if args.speed is None else float(args.speed)
        t0 = float(g.time or 0.0)
        frames = []
        for k in range(nframes):
            g.time = t0 + k * speed
            frames.append(g.image())
    else:
        frames = [g.image()]
    _save_image(out, frames, fps)
    w, h = g.size or (512, 512)
    print(f"wrote {out} ({w}x{h}, {len(frames)} frame{'s' if len(frames) != 1 else ''}, "
          f"graph {args.graph})")
    return 0
