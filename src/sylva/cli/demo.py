"""``sylva demo``: the main job on the built-in examples.

Grows every built-in example; when the renderer is available it renders the gallery
(``sylva gallery``) into ``gallery/`` as well.
"""

from __future__ import annotations

import sys
import time

__all__ = ["register"]


def register(sub) -> None:
    p = sub.add_parser(
        "demo",
        help="grow every built-in example and render the gallery",
        description="Grow every built-in example (all three dialects) and print what each "
        "grew; then render the gallery into OUT (default gallery/).",
    )
    p.add_argument("-o", "--out", default="gallery", help="gallery folder (default gallery/)")
    p.add_argument("--no-gallery", action="store_true", help="only derive, render nothing")
    p.set_defaults(func=run)


def grow_all(out=sys.stdout) -> list[tuple[str, int, float]]:
    from ..data import examples
    from ..lsystem import Derivation, load
    from ..plant import environment_for, query_for

    rows = []
    print(f"{'example':40s} {'dialect':8s} {'steps':>5s} {'modules':>10s} {'time':>8s}", file=out)
    for ex in examples():
        p = load(ex.path)
        t = time.perf_counter()
        seed = p.seed if p.seed is not None else 1
        env, locate = environment_for(p, seed)
        d = Derivation(p, seed=seed, query=query_for(p, seed), environment=env, locate=locate)
        d.advance(p.steps or 0)
        r = d.render_word()
        dt = time.perf_counter() - t
        counts = r.counts()
        top = ", ".join(f"{k}×{v}" for k, v in counts.most_common(3))
        print(f"{ex.name:40s} {p.dialect:8s} {d.step:5d} {len(d.word):10,d} {dt * 1e3:6.1f}ms"
              f"  {top}", file=out)
        rows.append((ex.name, len(d.word), dt))
    return rows


def run(args) -> int:
    grow_all()
    if args.no_gallery:
        return 0
    try:
        from . import gallery
    except ImportError:
        return 0
    return gallery.make(args.out)
