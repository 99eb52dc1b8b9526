"""Run every cpfg model of a vlab checkout: derive, render, and print what happened.

vlab (Algorithmic Botany's Virtual Laboratory, GPL-3, not part of sylva) publishes its
manuals' and course's cpfg models under ``oofs/``.  This script finds every cpfg
L-system there (a ``.l`` file with an ``Lsystem:`` or ``lsystem:`` line), reads it with sylva's cpfg
reader together with the view file, colour map (``-m``) or material file (``-M``) named
on the object's ``cpfg`` command line, derives it to its ``derivation length``, builds
its meshes (with the view file's background scene and textures) and renders them with the
view file's camera, fitted to the plant.  Each model runs in its own child process with a
time limit.

Per model it prints one line: ``derived`` (with the modules of the word, the time, the
built-in environment its environment file maps to and the triangles drawn), ``error``
(sylva's message), ``timeout``, or ``needs environment program X`` (the object runs cpfg
with ``-e file.e`` and the environment program that file names is one sylva's built-in
environments do not serve: ``honda81`` and ``chiba`` are served by ``density`` and
``light``, :mod:`sylva.lsystem.dialects._cpfg_env`).  At the end: the counts, and a
contact sheet of the renders (``--sheet``, default ``cpfg_corpus.png`` in the current
folder).

Usage::

    PYTHONPATH=src .venv/bin/python benchmarks/cpfg_corpus.py PATH_TO_VLAB [--timeout 60]
        [--size 200] [--sheet out.png] [--only SUBSTRING] [--no-render]

The figure of issue 24: ``derived`` ≥ 85 of the 92 models with an ``Lsystem:`` line (88 on
2 December 2026: the 4 others need ``clover``, ``ecosystem`` or ``obcheck``); with the 6
whose line is ``lsystem:`` (cpfg reads either), 94 of 98.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import re
import sys
import time
import warnings
from pathlib import Path

_LSYSTEM = re.compile(r"^\s*[Ll]system\s*:", re.MULTILINE)  # cpfg's lexer: either case


def find_models(root: Path) -> list[Path]:
    """The cpfg L-system files under ``root/oofs`` (found by their ``Lsystem:`` line)."""
    out = []
    for path in sorted((root / "oofs").rglob("*.l")):
        if not path.is_file():
            continue
        try:
            text = path.read_text("latin-1")
        except OSError:
            continue
        if _LSYSTEM.search(text):
            out.append(path)
    return out


def cpfg_command(model: Path) -> dict:
    """What the object's ``specifications`` passes to cpfg for ``model``: the view file,
    colour map, material file, environment file (paths, or None)."""
    spec = model.parent / "specifications"
    found = {"view": None, "map": None, "mat": None, "env": None}
    if spec.is_file():
        for line in spec.read_text("latin-1").splitlines():
            words = line.strip().split()
            if not words or words[0] != "cpfg" or model.name not in words:
                continue
            k = 1
            while k < len(words):
                w = words[k]
                w = {"-m1": "-m", "-M1": "-M"}.get(w, w)  # cpfg: -m is -m1 (colour map 1)
                if w in ("-m", "-M", "-e") and k + 1 < len(words):
                    found[{"-m": "map", "-M": "mat", "-e": "env"}[w]] = words[k + 1]
                    k += 2
                    continue
                if w == "-w":
                    k += 3
                    continue
                if w.endswith(".v"):
                    found["view"] = w
                k += 1
            break
    if found["view"] is None and model.with_suffix(".v").is_file():
        found["view"] = model.with_suffix(".v").name
    return {k: (model.parent / v if v else None) for k, v in found.items()}


def _needs(env: Path | None) -> str | None:
    """The environment program a model needs that sylva does not serve (None: no
    environment file, or one a built-in environment answers)."""
    if env is None:
        return None
    from sylva.lsystem.dialects._cpfg_env import EnvironmentProgramError, environment_spec

    try:
        environment_spec(env)
    except EnvironmentProgramError as exc:
        return exc.program
    except Exception:  # noqa: BLE001 - a bad file: the model's run reports it
        return None
    return None


def camera_from_view(view, scene):
    """sylva's camera for a cpfg view file (:meth:`sylva.render.Camera.from_view`: the
    viewpoint, view reference point, twist, projection and scale factor), fitted to the
    plant as cpfg fits its view to the object's box."""
    from sylva.lsystem.dialects._cpfg_view import read_camera
    from sylva.render import Camera

    cam = read_camera(view or False)
    box = scene.bounds(skip=("background",))  # the plant, not its background scene
    return Camera.from_view(box, cam.get("viewpoint", (0.0, 0.0, 1.0)),
                            cam.get("view reference point", (0.0, 0.0, 0.0)),
                            twist=float(cam.get("twist", 0.0)),
                            projection=str(cam.get("projection", "parallel")),
                            scale=float(cam.get("scale", 1.0)),
                            fov=float(cam.get("viewing angle", 35.0)))  # fmt: skip


def line_pixels(view) -> float | None:
    """How many pixels wide cpfg draws the lines of a view file (its ``initial line
    width`` with ``line style: pixel``, cpfg's default style, else None: widths in units);
    the runner draws them so, as ``sylva render`` does."""
    from sylva.lsystem.dialects._cpfg_view import read_camera

    cam = read_camera(view or False)
    if cam.get("line style", "pixel") not in ("pixel", "pixels", "wireframe"):
        return None
    return float(cam.get("line width", 1.0))


def _run(model: str, files: dict, size: int, render: bool, queue) -> None:
    out: dict = {}
    try:
        warnings.simplefilter("ignore")
        import numpy as np

        import sylva
        from sylva.lsystem import Derivation
        from sylva.lsystem.dialects import cpfg
        from sylva.plant import environment_for, query_for

        t0 = time.perf_counter()
        text = Path(model).read_text("latin-1")
        program = cpfg.parse(text, model, view=files["view"] or False, colormap=files["map"],
                             materials=files["mat"], environment=files["env"])  # fmt: skip
        seed = program.seed if program.seed is not None else 1
        env, locate = environment_for(program, seed)
        out["environment"] = program.settings.get("environment")
        d = Derivation(program, seed=seed, limit=5_000_000, query=query_for(program, seed),
                       environment=env, locate=locate)  # fmt: skip
        d.advance(program.steps or 0)
        out["modules"] = len(d.word)
        out["derive_s"] = time.perf_counter() - t0
        out["status"] = "derived"
        if render:
            from sylva.geometry.build import build_mesh
            from sylva.turtle import interpret

            rw = d.render_word()
            pixels = line_pixels(files["view"])
            # cpfg's pixel lines: the initial width and those #(w) / !(w) set are pixels on
            # the screen; the turtle draws them as units, then every segment's radius
            # scales by the image's units per pixel (the plant fills the image)
            over = {"thick": pixels} if pixels is not None else {}
            geometry = interpret(rw, program, seed=seed, **over)
            if pixels is not None and geometry.n_segments:
                lo, hi = geometry.bounds()
                extent = float(np.max(np.asarray(hi) - np.asarray(lo)))
                geometry.seg_radius = (geometry.seg_radius * (extent / size)).astype(np.float32)
            scene = build_mesh(geometry, detail=4)
            out["triangles"] = sum(int(m.n_triangles) for m in scene.meshes)
            if out["triangles"]:
                cam = camera_from_view(files["view"], scene)
                bg = geometry.background if geometry.background is not None else (0, 0, 0)
                _plain(scene)  # cpfg's flat colours, its texture images kept
                image = sylva.render.render(scene, (size, size), cam, shadows=False, msaa=0,
                                            ground=False, bg=bg)  # fmt: skip
                out["image"] = np.asarray(image.convert("RGB")).tobytes()
            out["total_s"] = time.perf_counter() - t0
    except Exception as e:  # noqa: BLE001 - the runner reports every failure
        out["status"] = out.get("status", "error")
        msg = f"{type(e).__name__}: {e}".splitlines()
        out["message" if out["status"] == "error" else "render_error"] = " / ".join(msg)[:400]
    queue.put(out)


def _plain(scene) -> None:
    """Drop sylva's procedural textures (bark, leaf) from ``scene``'s materials, keeping the
    image textures of the view file's ``texture:`` lines."""
    import dataclasses

    from sylva.render.scene import TEXTURE_KINDS

    for mesh in scene.meshes:
        mesh.materials = [dataclasses.replace(m, texture=None)
                          if m.texture and m.texture.lower() in TEXTURE_KINDS else m
                          for m in mesh.materials]  # fmt: skip


def run_one(model: Path, files: dict, timeout: float, size: int, render: bool) -> dict:
    ctx = mp.get_context("fork")
    queue = ctx.Queue()
    p = ctx.Process(target=_run, args=(str(model), files, size, render, queue))
    t0 = time.perf_counter()
    p.start()
    try:
        out = queue.get(timeout=timeout)
    except Exception:  # noqa: BLE001 - queue.Empty: the child ran out of time
        out = {"status": "timeout"}
    p.join(1)
    if p.is_alive():
        p.kill()
        p.join()
    out["wall_s"] = time.perf_counter() - t0
    return out


def _icon(model: Path, size: int):
    """cpfg's own picture of the model: the object's ``icon`` (an SGI RGB image that vlab
    saves from cpfg's window), scaled to ``size``; None when the object has none."""
    from PIL import Image

    path = model.parent / "icon"
    if not path.is_file():
        return None
    try:
        with Image.open(path) as im:
            return im.convert("RGB").resize((size, size))
    except Exception:  # noqa: BLE001 - an unreadable icon: the sheet leaves the cell blank
        return None


def contact_sheet(results: list, size: int, path: Path, cols: int = 4) -> None:
    """Write the contact sheet to ``path``: per model, cpfg's icon (left) beside sylva's
    render (right), with the model's name and status under the pair."""
    from PIL import Image, ImageDraw

    rows = (len(results) + cols - 1) // cols
    cell_w, cell_h = 2 * size + 8, size + 28
    sheet = Image.new("RGB", (cols * cell_w, rows * cell_h), "white")
    draw = ImageDraw.Draw(sheet)
    for k, (name, model, out) in enumerate(results):
        x, y = (k % cols) * cell_w, (k // cols) * cell_h
        icon = _icon(model, size)
        if icon is not None:
            sheet.paste(icon, (x, y))
        else:
            draw.text((x + 6, y + 6), "no icon", fill="gray")
        if "image" in out:
            sheet.paste(Image.frombytes("RGB", (size, size), out["image"]), (x + size, y))
        else:
            draw.rectangle([x + size + 2, y + 2, x + 2 * size - 3, y + size - 3], outline="red")
            draw.text((x + size + 6, y + 6), out["status"][:28], fill="red")
        draw.text((x + 2, y + size + 1), name[-(2 * size // 6):], fill="black")
        status = out["status"]
        if status == "derived":
            status += f"  {out.get('triangles', 0)} triangles"
        draw.text((x + 2, y + size + 13), status[: 2 * size // 6], fill="black")
    from sylva._atomic import atomic_path

    with atomic_path(path) as tmp:
        sheet.save(tmp, format="PNG")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("vlab", type=Path)
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--size", type=int, default=200)
    ap.add_argument("--sheet", type=Path, default=Path("cpfg_corpus.png"),
                    help="where the contact sheet goes (cpfg's icon left, sylva right)")
    ap.add_argument("--only", default=None,
                    help="run only the models whose path contains SUBSTRING")
    ap.add_argument("--no-render", action="store_true")
    args = ap.parse_args(argv)
    import sylva.lsystem.dialects.cpfg  # noqa: F401 - loaded once, shared by the children
    import sylva.plant  # noqa: F401

    if not args.no_render:
        import sylva.geometry.build  # noqa: F401
        import sylva.render  # noqa: F401
    models = find_models(args.vlab)
    if args.only:
        # the path as printed (``10-manuals/11-CPFG/...``, vlab's ``ext/`` folders left
        # out) or as on disk
        models = [m for m in models if args.only in str(m)
                  or args.only in str(m.relative_to(args.vlab / "oofs")).replace("ext/", "")]
    counts: dict[str, int] = {}
    results = []
    for model in models:
        name = str(model.relative_to(args.vlab / "oofs")).replace("ext/", "")
        files = cpfg_command(model)
        needs = _needs(files["env"])
        if needs is not None:
            out = {"status": f"needs environment program {needs}", "wall_s": 0.0}
        else:
            out = run_one(model, files, args.timeout, args.size, not args.no_render)
        status = out["status"]
        key = status if not status.startswith("needs") else "needs environment program"
        counts[key] = counts.get(key, 0) + 1
        line = f"{status:9s} {name}"
        if status == "derived":
            line += f"  modules={out['modules']} derive={out['derive_s']:.2f}s"
            if out.get("environment"):
                line += f" environment={out['environment'].replace(' ', '')}"
            if "triangles" in out:
                line += f" triangles={out['triangles']} total={out['total_s']:.2f}s"
            if "render_error" in out:
                line += f"  (render: {out['render_error']})"
        elif status == "error":
            line += f"  {out['message']}"
        elif status == "timeout":
            line += f"  (over {args.timeout:g}s)"
        print(line, flush=True)
        results.append((name, model, out))
    print()
    print(f"{len(models)} models: " + ", ".join(f"{v} {k}" for k, v in sorted(counts.items())))
    if not args.no_render and results:
        contact_sheet(results, args.size, args.sheet)
        print(f"contact sheet: {args.sheet}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
