"""The pictures of the documentation, rendered by sylva and cached by content.

A picture's file name is a hash of what it shows (the L-system text, the size and
:data:`VERSION`), so a second build renders nothing and a changed example is rendered
again.  Pictures that are missing are rendered in worker processes, one OpenGL context each.
"""

from __future__ import annotations

import hashlib
import os
import tempfile
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

#: Bump to render every picture again (after a change to how they are made).
VERSION = "1"

GALLERY_SIZE = (360, 360)
TURTLE_SIZE = (120, 120)
TEXTURE_SIZE = (192, 192)


@dataclass(frozen=True)
class Job:
    kind: str  # "example", "turtle", "texture" or "trees" (the species contact sheet)
    key: str  # the example's name, the program text, the texture preset, or "species"
    size: tuple[int, int]

    def filename(self) -> str:
        h = hashlib.sha256(f"{VERSION}\0{self.kind}\0{self.size}\0".encode())
        if self.kind == "example":
            from sylva.data import find

            h.update(find(self.key).path.read_bytes())
            stem = self.key
        elif self.kind == "texture":
            from sylva.texture import PRESETS

            h.update(repr(sorted(PRESETS[self.key].items())).encode())
            stem = f"texture-{self.key}"
        elif self.kind == "trees":
            import sylva.tree

            folder = Path(sylva.tree.__file__).parent
            for f in sorted([*folder.glob("species/*"), *folder.glob("*.py")]):
                h.update(f.name.encode() + b"\0" + f.read_bytes())
            stem = "tree-species"
        else:
            h.update(self.key.encode())
            stem = "turtle"
        return f"{stem}-{h.hexdigest()[:16]}.png"


def _render_turtle(text: str, out: Path, size: tuple[int, int]) -> None:
    from sylva.plant import grow
    from sylva.render import Camera, render, save_image

    plant = grow(text, 0)
    mode = "2d" if plant.is_2d else "perspective"
    if mode == "2d":
        plant = plant.with_min_radius(plant.line_radius(3.0, size))
    cam = Camera.auto(plant.scene.bounds(), mode, yaw=35.0 if mode != "2d" else None,
                      pitch=25.0 if mode != "2d" else None, margin=0.15)
    img = render(plant.scene, size=size, camera=cam, bg=(1.0, 1.0, 1.0), ground=False,
                 shadows=False)
    save_image(img, out)


def _render_example(name: str, out: Path, size: tuple[int, int]) -> dict:
    from sylva.cli.gallery import _render_example as render_one
    from sylva.data import find

    with tempfile.TemporaryDirectory(dir=out.parent) as tmp:
        info = render_one(find(name), Path(tmp), size)
        os.replace(Path(tmp) / info["file"], out)
    return info


def _render_texture(name: str, out: Path, size: tuple[int, int]) -> None:
    from PIL import Image

    from sylva.texture import PRESETS, render

    recipe = dict(PRESETS[name])
    recipe["size"] = list(size)
    Image.fromarray(render(recipe)).save(out)


def _render_trees(out: Path) -> None:
    from sylva.cli._tree_sheet import contact_sheet

    contact_sheet().save(out)


def _run(job: Job, folder: str) -> str:
    out = Path(folder) / job.filename()
    tmp = out.with_suffix(".part.png")
    if job.kind == "example":
        _render_example(job.key, tmp, job.size)
    elif job.kind == "texture":
        _render_texture(job.key, tmp, job.size)
    elif job.kind == "trees":
        _render_trees(tmp)
    else:
        _render_turtle(job.key, tmp, job.size)
    os.replace(tmp, out)
    return out.name


def render_missing(jobs: list[Job], folder: Path, workers: int | None = None) -> list[str]:
    """Render the pictures of ``jobs`` that ``folder`` lacks; return the new files' names."""
    folder.mkdir(parents=True, exist_ok=True)
    todo = [j for j in dict.fromkeys(jobs) if not (folder / j.filename()).exists()]
    if not todo:
        return []
    workers = workers or min(len(todo), os.cpu_count() or 1, 4)
    if workers == 1:
        return [_run(j, str(folder)) for j in todo]
    import multiprocessing

    # the species sheet and the examples first: they take longest
    todo.sort(key=lambda j: (j.kind != "trees", j.kind != "example"))
    ctx = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(workers, mp_context=ctx) as pool:
        return list(pool.map(_run, todo, [str(folder)] * len(todo), chunksize=1))
