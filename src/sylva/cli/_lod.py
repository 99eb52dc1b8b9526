"""``--lod N``: the levels of detail of ``sylva export`` and ``sylva tree``."""

from __future__ import annotations

import os

from ..errors import SylvaError

LOD_FORMATS = ("glb", "gltf", "usd", "usda", "usdc")
LOD_HELP = ("write N levels of detail (1-4: LOD0, LOD1 <= 25%% and LOD2 <= 5%% of LOD0's "
            "triangles, and an impostor) to .glb/.gltf (MSFT_lod + NAME_LODn nodes) or "
            ".usd* (a variant set 'lod')")


def add_lod(p) -> None:
    p.add_argument("--lod", default=None, metavar="N", help=LOD_HELP)
    p.add_argument("--impostor-size", default="256", metavar="PX",
                   help="with --lod 4: the height of each impostor view in pixels (default 256)")


def lod_levels(args, out) -> int | None:
    """The ``--lod`` setting (None without it), checked against the output's format."""
    from ..geometry.lod import check_lods

    if args.lod is None:
        return None
    n = check_lods(args.lod, "--lod")
    ext = os.path.splitext(os.fspath(out))[1].lower().lstrip(".")
    if ext not in LOD_FORMATS:
        raise SylvaError(f"--lod: levels of detail are written to .glb, .gltf or .usd*, "
                         f"not {('.' + ext) if ext else os.fspath(out)!r}")
    return n


def finish_chain(chain, n: int, args):
    """Add the impostor when ``n`` is 4."""
    if n < 4:
        return chain
    from .._impostor import add_impostor

    try:
        size = int(args.impostor_size)
    except ValueError:
        raise SylvaError(f"--impostor-size: expected a whole number of pixels, got "
                         f"{args.impostor_size!r}") from None
    try:
        return add_impostor(chain, size=size)
    except SylvaError as exc:
        raise SylvaError(f"--impostor-size: {exc}") from None


def check_textures(args, out, n: int | None) -> None:
    """``--lod`` with ``--textures``: baked images travel in a GLB's levels only."""
    if n is None or getattr(args, "textures", None) is None:
        return
    ext = os.path.splitext(os.fspath(out))[1].lower()
    if ext != ".glb":
        raise SylvaError(f"--lod with --textures: baked levels of detail are written to "
                         f".glb (it embeds the images), not {ext or os.fspath(out)!r}; "
                         "leave out one of the two for .gltf or .usd*")


def bake_chain(chain, size):
    """Every mesh level of ``chain`` with its materials baked (the impostor keeps its own
    atlas): each level is baked from its own meshes, so a level's leaf cards get the
    outline of their own blades."""
    from ..assets import bake_scene

    for level in chain.levels:
        if level.kind == "mesh":
            level.scene = bake_scene(level.scene, size)
    return chain


def write_chain(chain, out, up: str | None = None) -> None:
    from ..geometry.exchange.gltf_lod import write_lod_glb, write_lod_gltf
    from ..geometry.exchange.usd_lod import write_usd_lod

    ext = os.path.splitext(os.fspath(out))[1].lower()
    opts = {} if up is None else {"up": up}
    if ext == ".glb":
        write_lod_glb(chain, out, **opts)
    elif ext == ".gltf":
        write_lod_gltf(chain, out, **opts)
    else:
        write_usd_lod(chain, out, **opts)


def describe(chain) -> str:
    tris = [lv.n_triangles for lv in chain.levels]
    return "levels " + ", ".join(f"LOD{i} {t}" for i, t in enumerate(tris)) + " triangles"
