"""``sylva gallery``: render every built-in example, a turntable and a growth, with a page.

``make demo`` runs this: it is the main job the README promises.
"""

from __future__ import annotations

import html
import sys
import time
from pathlib import Path

from .._atomic import atomic_write, make_folder, save_buffered
from ._common import parse_size

__all__ = ["make", "register"]


def register(sub) -> None:
    p = sub.add_parser(
        "gallery",
        help="render every built-in example into a folder with an index.html",
        description="Render every built-in example (all three dialects), a turntable, a "
        "growth animation and some procedural textures, and write DIR/index.html.",
    )
    p.add_argument("-o", "--out", default="gallery", metavar="DIR", help="folder (default gallery)")
    p.add_argument("--size", type=parse_size, default=parse_size("800x800"),
                   help="image size (default 800x800)")
    p.add_argument("--only", default=None, help="render only examples whose name contains this")
    p.add_argument("--no-animations", action="store_true", help="skip the GIFs")
    p.set_defaults(func=lambda a: make(a.out, a.size, a.only, not a.no_animations))


def _render_example(ex, out: Path, size: tuple[int, int]) -> dict:
    from ..lsystem import load
    from ..plant import grow
    from ..render import Camera, render, save_image

    t0 = time.perf_counter()
    program = load(ex.path)
    # files that name no step count (seed 001's Source code 1, seed 004's acacia) are shown
    # after 4 steps, as their theses show them
    plant = grow(program, None if program.steps is not None else 4)
    mode = "2d" if plant.is_2d else "perspective"
    if mode == "2d":
        plant = plant.with_min_radius(plant.line_radius(2.0, size))
    t1 = time.perf_counter()
    # 3D plants stand under a sky unless their file sets a background colour of its own;
    # the camera is then lowered a little (pitch 12 instead of 20) to show some of the sky
    sky = mode != "2d" and plant.program.settings.get("bg") is None
    pitch = 12.0 if sky else None
    cam = Camera.auto(plant.scene.bounds(), mode, pitch=pitch, aspect=size[0] / size[1])
    img = render(plant.scene, size=size, camera=cam, bg=plant.background, sky=sky)
    png = out / f"{ex.name}.png"
    save_image(img, png)
    t2 = time.perf_counter()
    return dict(
        name=ex.name, title=ex.title, file=png.name, dialect=plant.program.dialect,
        steps=plant.steps, modules=len(plant.word), triangles=plant.scene.n_triangles,
        grow=t1 - t0, render=t2 - t1, source=ex.path.read_text(encoding="utf-8"),
    )


def _animations(out: Path) -> list[dict]:
    from ..plant import grow, growth_scenes
    from ..render import growth_frames, turntable_frames, write_animation

    made = []
    t = time.perf_counter()
    bush = grow("abop-1.25-bush", 5)
    frames = turntable_frames(bush.scene, 24, (400, 400), "perspective", pitch=20, sky=True)
    write_animation(frames, out / "turntable-bush.gif", fps=12, progress=True)
    made.append(dict(file="turntable-bush.gif", title="ABOP Fig. 1.25 bush, turntable",
                     seconds=time.perf_counter() - t))
    t = time.perf_counter()
    scenes = list(growth_scenes("abop-2.8-ternary-tree", 6, substeps=4))
    frames = growth_frames(scenes, (400, 400), "perspective", pitch=10, sky=True)
    write_animation(frames, out / "growth-ternary-tree.gif", fps=12, progress=True)
    made.append(dict(file="growth-ternary-tree.gif",
                     title="ABOP Fig. 2.8 ternary tree growing (smooth: 4 frames a step)",
                     seconds=time.perf_counter() - t))
    return made


def _tree_sheet(out: Path) -> list[dict]:
    """The contact sheet of every tree species at three ages (``sylva tree --sheet``)."""
    from ._tree_sheet import contact_sheet

    t = time.perf_counter()
    sheet = contact_sheet(log=lambda line: print(line, file=sys.stderr))
    save_buffered(out / "tree-species.png", lambda fh: sheet.save(fh, format="PNG"))
    return [dict(file="tree-species.png",
                 title="every tree species at 25 %, 50 % and 100 % of its age, one scale",
                 seconds=time.perf_counter() - t)]


GALLERY_TEXTURES = (
    "arabescato-marble", "beech-wood", "pink-granite", "oak-bark", "leaf-blade", "lawn",
    "worley-a", "ridged-terrain", "warped-marble", "seahorse-valley", "julia-dendrite",
    "burning-ship-armada", "lilac",
)


def _textures(out: Path, size: int = 256) -> list[dict]:
    """Some procedural textures (presets of :mod:`sylva.texture`) as PNGs."""
    from PIL import Image

    from ..texture import PRESETS
    from ..texture.graph import from_recipe
    from ..texture.graph.library import marble_graph

    made = []
    graphs = [(name, f"texture preset {name}", from_recipe(dict(PRESETS[name],
                                                                 size=[size, size])))
              for name in GALLERY_TEXTURES if name in PRESETS]
    graphs.append(("marble-graph", "marble as a graph of primitive nodes",
                   marble_graph(scale=3.0, stripes=3.0, turbulence=2.5, seed=11)))
    for name, title, g in graphs:
        t = time.perf_counter()
        g.size = [size, size]
        image = Image.fromarray(g.image())  # the preset's image, from its graph
        save_buffered(out / f"texture-{name}.png",
                      lambda fh, image=image: image.save(fh, format="PNG"))
        made.append(dict(file=f"texture-{name}.png", title=title,
                         seconds=time.perf_counter() - t, graph=g.dumps()))
    return made


def _page(rows: list[dict], anims: list[dict]) -> str:
    cards = []
    for r in rows:
        cards.append(
            f"""<figure><img src="{html.escape(r['file'])}" alt="{html.escape(r['name'])}"
loading="lazy"><figcaption><b>{html.escape(r['name'])}</b><br>{html.escape(r['title'])}<br>
<small>{r['dialect']} · {r['steps']} steps · {r['modules']:,} modules ·
{r['triangles']:,} triangles · grow {r['grow']:.2f} s · render {r['render']:.2f} s</small>
<details><summary>source</summary><pre>{html.escape(r['source'])}</pre></details>
</figcaption></figure>"""
        )
    for a in anims:
        graph = (f"<details><summary>graph</summary><pre>{html.escape(a['graph'])}</pre>"
                 "</details>" if a.get("graph") else "")
        cards.append(
            f"""<figure><img src="{html.escape(a['file'])}" alt="{html.escape(a['title'])}">
<figcaption><b>{html.escape(a['title'])}</b><br><small>{a['seconds']:.1f} s</small>
{graph}</figcaption></figure>"""
        )
    return """<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>sylva gallery</title>
<style>
body{font-family:system-ui,sans-serif;margin:2rem;background:#fafafa;color:#222}
main{display:grid;grid-template-columns:repeat(auto-fill,minmax(320px,1fr));gap:1.5rem}
figure{margin:0;background:#fff;border:1px solid #ddd;border-radius:6px;padding:.5rem}
img{width:100%;height:auto;display:block}
pre{font-size:.75rem;white-space:pre-wrap;background:#f3f3f3;padding:.5rem}
</style></head><body>
<h1>sylva gallery</h1>
<p>Every built-in example, grown and rendered offscreen by <code>sylva gallery</code>.</p>
<main>
""" + "\n".join(cards) + "\n</main></body></html>\n"


def make(out: str | Path, size=(800, 800), only: str | None = None,
         animations: bool = True) -> int:
    """Render the gallery into ``out``; print each example's time; return 0."""
    from ..data import examples

    out = Path(out)
    make_folder(out)
    rows = []
    chosen = [e for e in examples() if only is None or only in e.name]
    print(f"{'example':40s} {'modules':>9s} {'triangles':>10s} {'grow':>7s} {'render':>7s}",
          file=sys.stderr)
    for ex in chosen:
        r = _render_example(ex, out, size)
        rows.append(r)
        print(f"{r['name']:40s} {r['modules']:9,d} {r['triangles']:10,d} {r['grow']:6.2f}s "
              f"{r['render']:6.2f}s", file=sys.stderr)
    anims = _animations(out) if animations and only is None else []
    textures = _textures(out) if only is None else []
    if only is None and animations:  # the tree sheet is heavy too (about a minute)
        textures += _tree_sheet(out)
    with atomic_write(out / "index.html", "w") as fh:
        fh.write(_page(rows, anims + textures))
    print(f"sylva: wrote {out / 'index.html'} ({len(rows)} examples, {len(anims)} animations, "
          f"{len(textures)} textures)", file=sys.stderr)
    return 0
