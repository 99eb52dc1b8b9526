"""``sylva render``: grow a plant and render it offscreen to an image."""

from __future__ import annotations

import sys
import time

from ._common import (
    add_camera,
    add_growth,
    camera_for,
    check_suffix,
    limit_type,
    render_options,
    view_camera,
    view_line_pixels,
)

__all__ = ["register"]


def register(sub) -> None:
    p = sub.add_parser(
        "render",
        help="grow an L-system and render it to PNG/JPG",
        description="Grow an L-system and render it offscreen (EGL: the GPU, or Mesa's "
        "llvmpipe on the CPU) to a PNG or JPG of any size.",
    )
    add_growth(p)
    p.add_argument("--limit", type=limit_type, default=None, metavar="N",
                   help="stop before a word passes N modules (default 50,000,000)")
    add_camera(p)
    p.add_argument("-o", "--output", required=True, metavar="OUT", help="OUT.png or OUT.jpg")
    p.add_argument("--view", metavar="V", default=None,
                   help="cpfg: the view file (.v) to read (default: the one beside FILE)")
    p.add_argument("--environment", metavar="ENV", default=None,
                   help="an open L-system's environment for its ?E modules: light, "
                        "obstacle, world, with options as in the .lsys directive, e.g. "
                        "'obstacle(shape = box, sy = 2)' (default: the file's environment = …)")
    p.add_argument("--line-width", type=float, default=2.0,
                   help="in 2D, draw branches at least this many pixels wide (default 2)")
    p.set_defaults(func=run)


def run(args) -> int:
    from ..lsystem.engine import DEFAULT_MODULE_LIMIT, check_steps
    from ..plant import grow, resolve
    from ..render import Camera, render, save_image

    check_suffix(args.output, (".png", ".jpg", ".jpeg"), "the image file")
    t0 = time.perf_counter()
    source = args.file
    if args.view is not None:
        from .derive import load_program

        source = load_program(args.file, view=args.view)
    source = resolve(source)
    limit = DEFAULT_MODULE_LIMIT if args.limit is None else args.limit
    check_steps(source, args.steps, limit=limit, option="-n")
    plant = grow(source, args.steps, seed=args.seed, detail=args.detail, mode=args.mode,
                 limit=limit, environment=args.environment)
    t1 = time.perf_counter()
    w, h = args.size
    mode = camera_for(args, plant)
    pixels = view_line_pixels(args, plant)  # cpfg's pixel lines, in any camera
    if pixels is None and mode == "2d":
        pixels = args.line_width
    if pixels is not None and pixels > 0:
        plant = plant.with_min_radius(plant.line_radius(pixels, (w, h)))
    cam = view_camera(args, plant, w / h)  # a cpfg view file's camera, if it has one
    if cam is None:
        cam = Camera.auto(plant.scene.bounds(), mode, yaw=args.yaw, pitch=args.pitch,
                          aspect=w / h)  # fmt: skip
    img = render(plant.scene, size=(w, h), camera=cam, **render_options(args, plant))
    save_image(img, args.output, bg=args.bg or "white")
    t2 = time.perf_counter()
    print(
        f"sylva: wrote {args.output} ({w}x{h}, {len(plant.word):,} modules, "
        f"{plant.scene.n_triangles:,} triangles; grow {t1 - t0:.2f} s, render {t2 - t1:.2f} s)",
        file=sys.stderr,
    )
    return 0
