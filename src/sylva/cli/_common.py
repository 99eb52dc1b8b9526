"""Arguments and helpers shared by the commands that grow and draw a plant."""

from __future__ import annotations

import argparse
import math

from ..errors import SylvaError

__all__ = ["add_camera", "add_growth", "camera_for", "parse_size", "steps_type", "view_camera",
           "view_line_pixels"]


def parse_size(text: str) -> tuple[int, int]:
    """``"1920x1080"`` -> ``(1920, 1080)``."""
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"size {text!r}: expected WIDTHxHEIGHT such as 1920x1080"
        ) from None
    if w <= 0 or h <= 0 or w * h > 400_000_000:
        raise argparse.ArgumentTypeError(f"size {text!r}: expected positive sizes")
    return w, h


def steps_type(text: str) -> int:
    """``-n``: a whole number of steps from 0 to :data:`~sylva.lsystem.ast.MAX_STEPS`."""
    from ..lsystem.ast import MAX_STEPS

    try:
        n = int(text)
    except ValueError:
        try:
            x = float(text)  # 1e23 is a whole number too, and refused for its size below
        except ValueError:
            x = math.nan
        if not x.is_integer():
            raise argparse.ArgumentTypeError(
                f"{text!r}: expected a whole number of steps such as 5"
            ) from None
        n = int(x)
    if not 0 <= n <= MAX_STEPS:
        raise argparse.ArgumentTypeError(
            f"{text}: expected 0 to {MAX_STEPS:,} derivation steps"
        )
    return n


def limit_type(text: str) -> int:
    """``--limit``: the module limit, a whole number of modules, at least 1."""
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r}: expected a whole number of modules such as 1000000"
        ) from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"{text}: expected at least 1 module")
    return n


def add_growth(p: argparse.ArgumentParser) -> None:
    p.add_argument("file", metavar="FILE",
                   help="an L-system file (any dialect) or a built-in example name")
    p.add_argument("-n", "--steps", type=steps_type, default=None,
                   help="derivation steps (default: the file's own count)")
    p.add_argument("-r", "--seed", type=int, default=None,
                   help="seed of the random choices (-r as in seed 000)")
    p.add_argument("--detail", type=int, default=None,
                   help="sides around each branch (default: the file's detail, else 8)")
    p.add_argument("--mode", choices=("tube", "prism", "cone"), default="tube",
                   help="branch construction (default: tube)")


def add_camera(p: argparse.ArgumentParser, size: str = "1280x960") -> None:
    p.add_argument("--size", type=parse_size, default=parse_size(size),
                   help=f"image size WIDTHxHEIGHT (default {size})")
    p.add_argument("--camera", choices=("auto", "perspective", "ortho", "orthographic", "2d"),
                   default="auto",
                   help="camera mode; auto picks 2d for planar systems (seed 001 §5.3)")
    p.add_argument("--yaw", type=float, default=None, help="view direction, degrees")
    p.add_argument("--pitch", type=float, default=None, help="view elevation, degrees")
    p.add_argument("--bg", default=None,
                   help="background colour (name, #rrggbb); default the file's bg or white")
    p.add_argument("--transparent", action="store_true", help="transparent background (PNG)")
    p.add_argument("--sky", action="store_true",
                   help="a sky gradient behind 3D views, the ground fading into its haze")
    p.add_argument("--no-shadows", action="store_true", help="no shadow mapping")
    p.add_argument("--no-ground", action="store_true", help="no ground plane")
    p.add_argument("--msaa", type=int, default=4, help="samples per pixel (default 4)")


def camera_for(args, plant) -> str:
    """The camera mode to use for ``plant`` given ``--camera``."""
    mode = args.camera
    if mode == "auto":
        return "2d" if plant.is_2d else "perspective"
    return "orthographic" if mode == "ortho" else mode


def view_camera(args, plant, aspect: float):
    """The camera of a cpfg plant's view file (``viewpoint``, ``view reference point``,
    ``twist``, ``projection``, ``scale factor``), or None: not a cpfg program, no camera
    lines, or the command line chose the view (``--camera``, ``--yaw``, ``--pitch``)."""
    program = plant.program
    if (program.dialect != "cpfg" or getattr(args, "camera", "auto") != "auto"
            or getattr(args, "yaw", None) is not None
            or getattr(args, "pitch", None) is not None):  # fmt: skip
        return None
    from ..lsystem.dialects._cpfg_view import read_camera
    from ..render import Camera

    view = getattr(args, "view", None)
    cam = read_camera(view if view is not None else None, program.filename)
    if not cam:
        return None
    box = plant.scene.bounds(skip=("background",))  # cpfg fits its view to the plant alone
    return Camera.from_view(box, cam.get("viewpoint", (0.0, 0.0, 1.0)),
                            cam.get("view reference point", (0.0, 0.0, 0.0)),
                            twist=float(cam.get("twist", 0.0)),
                            projection=str(cam.get("projection", "parallel")),
                            scale=float(cam.get("scale", 1.0)), aspect=aspect,
                            fov=float(cam.get("viewing angle", 35.0)))  # fmt: skip


def view_line_pixels(args, plant) -> float | None:
    """How many pixels wide a cpfg plant's lines are drawn: its view file's ``initial line
    width`` with ``line style: pixel`` (cpfg's default style), at least ``--line-width``;
    None for other programs and styles (their widths are in units)."""
    program = plant.program
    if program.dialect != "cpfg":
        return None
    from ..lsystem.dialects._cpfg_view import read_camera

    view = getattr(args, "view", None)
    cam = read_camera(view if view is not None else None, program.filename)
    if cam.get("line style", "pixel") not in ("pixel", "pixels", "wireframe"):
        return None
    return max(float(cam.get("line width", 1.0)), float(getattr(args, "line_width", 0.0)))


def render_options(args, plant) -> dict:
    bg = args.bg if args.bg is not None else plant.background
    opts = dict(bg=bg, transparent=args.transparent, shadows=not args.no_shadows,
                msaa=args.msaa)
    if getattr(args, "sky", False):
        opts["sky"] = True
    if args.no_ground:
        opts["ground"] = False
    return opts


def check_suffix(path: str, allowed: tuple[str, ...], what: str) -> None:
    if not path.lower().endswith(allowed):
        raise SylvaError(f"{path}: {what} must end in " + ", ".join(allowed))
