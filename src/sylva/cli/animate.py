"""``sylva animate``: a growth animation (one frame per step, or smooth) or a turntable."""

from __future__ import annotations

import sys

from ._common import add_camera, add_growth, camera_for, check_suffix, limit_type, render_options

__all__ = ["register"]


def register(sub) -> None:
    p = sub.add_parser(
        "animate",
        help="render a growth animation or a turntable to GIF/MP4",
        description="Render the plant growing step by step (--growth, the default; "
        "--substeps K makes it smooth: new segments extend out of the old ones) or the "
        "camera orbiting the grown plant (--turntable) to a GIF or MP4.",
    )
    add_growth(p)
    p.add_argument("--limit", type=limit_type, default=None, metavar="N",
                   help="stop before a word passes N modules (default 50,000,000)")
    add_camera(p, size="640x480")
    kind = p.add_mutually_exclusive_group()
    kind.add_argument("--growth", action="store_true", help="one frame per derivation step")
    kind.add_argument("--turntable", action="store_true", help="orbit the grown plant")
    p.add_argument("--substeps", type=int, default=1,
                   help="frames per derivation step for smooth growth (default 1)")
    p.add_argument("--frames", type=int, default=48, help="turntable frames (default 48)")
    p.add_argument("--fps", type=float, default=12.0, help="frames per second (default 12)")
    p.add_argument("-o", "--output", required=True, metavar="OUT", help="OUT.gif or OUT.mp4")
    p.set_defaults(func=run)


def run(args) -> int:
    from ..lsystem.engine import DEFAULT_MODULE_LIMIT, check_steps
    from ..plant import grow, growth_scenes, resolve
    from ..render import growth_frames, turntable_frames, write_animation

    check_suffix(args.output, (".gif", ".mp4"), "the animation file")
    program = resolve(args.file)
    limit = DEFAULT_MODULE_LIMIT if args.limit is None else args.limit
    check_steps(program, args.steps, limit=limit, option="-n")
    if args.turntable:
        plant = grow(program, args.steps, seed=args.seed, detail=args.detail, mode=args.mode,
                     limit=limit)
        mode = camera_for(args, plant)
        if mode == "2d":
            mode = "perspective"  # a 2D camera cannot turn
        frames = turntable_frames(plant.scene, args.frames, args.size, mode, pitch=args.pitch,
                                  **render_options(args, plant))
    else:
        if args.substeps < 1:
            from ..errors import SylvaError

            raise SylvaError("--substeps must be at least 1")
        scenes = list(growth_scenes(program, args.steps, seed=args.seed,
                                    substeps=args.substeps, detail=args.detail,
                                    mode=args.mode, limit=limit))
        plant = grow(program, args.steps, seed=args.seed, detail=args.detail, mode=args.mode,
                     limit=limit)
        frames = growth_frames(scenes, args.size, camera_for(args, plant), yaw=args.yaw,
                               pitch=args.pitch, **render_options(args, plant))
    write_animation(frames, args.output, fps=args.fps, progress=True)
    print(f"sylva: wrote {args.output} ({len(frames)} frames)", file=sys.stderr)
    return 0
