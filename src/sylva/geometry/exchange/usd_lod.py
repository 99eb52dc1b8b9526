"""USD with levels of detail: a variant set ``lod`` over one layer per level.

:func:`write_usd_lod` writes each level of a :class:`~sylva.geometry.lod.LodChain` with
:func:`~.usd.write_usd` to its own layer beside the target (``STEM_LOD0.usda`` …, in the
target's format), and the target itself as a small stage whose root prim ``/NAME`` has the
variant set ``lod``: one variant per level (``LOD0`` selected), each referencing that
level's layer.  This is USD's usual asset layout: a tool that switches the variant loads
only that level.  An impostor's atlas is written beside the layers
(``STEM_MATERIAL_color.png``, ``_normal.png``) and read by ``UsdUVTexture`` shaders in its
material.
"""

from __future__ import annotations

import os

from ..._atomic import atomic_path, atomic_write, os_error_from_text
from ...errors import SylvaError
from ..mesh import Scene
from ._common import check_up, safe_name
from .usd import _ident, available, write_usd

__all__ = ["write_usd_lod"]


def write_usd_lod(chain, target, *, up: str = "y") -> None:
    """Write a LOD chain as a USD stage with the variant set ``lod`` (see the module
    docstring); ``target`` must be a path (the levels and images go beside it)."""
    if not available():
        raise SylvaError("USD export needs the usd-core package: pip install usd-core")
    if not isinstance(target, (str, os.PathLike)):
        raise SylvaError("USD levels of detail are written to a path (their layers and "
                         "images go beside it)")
    from pxr import Gf, Sdf, Tf, Usd, UsdGeom, UsdShade

    from .gltf_lod import png_bytes

    up = check_up(up)
    path = os.fspath(target)
    folder, base = os.path.split(path)
    stem, suffix = os.path.splitext(base)
    name = _ident(chain.name)
    layers = []
    for i, lv in enumerate(chain.levels):
        layer = f"{safe_name(stem)}_LOD{i}{suffix}"
        layers.append(layer)
        files = {}
        for mat_name, img in lv.images.items():
            for kind in ("color", "normal"):
                if kind in img:
                    png = f"{safe_name(stem)}_{safe_name(mat_name)}_{kind}.png"
                    with atomic_write(os.path.join(folder, png), "wb") as fh:
                        fh.write(png_bytes(img[kind], flip=_st_flipped()))
                    files.setdefault(mat_name, {})[kind] = "./" + png
        scene = Scene(lv.scene.meshes, name=chain.name)
        with atomic_path(os.path.join(folder, layer)) as tmp:
            write_usd(scene, tmp, up=up)
            if files:
                try:
                    stage = Usd.Stage.Open(tmp)
                    for mat_name, fl in files.items():
                        look = f"/{name}/Looks/{_ident(mat_name)}"
                        m = UsdShade.Material(stage.GetPrimAtPath(look))
                        sh = UsdShade.Shader(stage.GetPrimAtPath(look + "/Surface"))
                        if m and sh:
                            _textured(stage, m, sh, fl, lv.scene, mat_name,
                                      (Gf, Sdf, Usd, UsdGeom, UsdShade))
                    stage.GetRootLayer().Save()
                except Tf.ErrorException as exc:
                    raise os_error_from_text(str(exc), tmp, "usd-core") from None
    with atomic_path(path) as tmp:
        try:
            stage = Usd.Stage.CreateNew(tmp)
            UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z if up == "z" else UsdGeom.Tokens.y)
            UsdGeom.SetStageMetersPerUnit(stage, 1.0)
            root = UsdGeom.Xform.Define(stage, "/" + name)
            stage.SetDefaultPrim(root.GetPrim())
            vset = root.GetPrim().GetVariantSets().AddVariantSet("lod")
            for i, layer in enumerate(layers):
                vset.AddVariant(f"LOD{i}")
                vset.SetVariantSelection(f"LOD{i}")
                with vset.GetVariantEditContext():
                    root.GetPrim().GetReferences().AddReference("./" + layer)
            vset.SetVariantSelection("LOD0")
            stage.GetRootLayer().Save()
        except Tf.ErrorException as exc:
            raise os_error_from_text(str(exc), tmp, "usd-core") from None


def _st_flipped() -> bool:
    """Whether :func:`~.usd.write_usd` writes ``st`` as ``(u, 1 - v)`` (the texture work's
    convention: baked images have ``v`` running down).  The impostor's ``v`` runs up the
    image (the renderer's convention), so its atlas is then written upside down, to land
    the right way up under USD's ``t``."""
    from . import usd

    return hasattr(usd, "v_up")


def _cutoff(scene, mat_name):
    for m in scene.meshes:
        for mat in m.materials:
            if mat.name == mat_name:
                return mat.alpha_cutoff
    return None


def _textured(stage, m, sh, files: dict, scene, mat_name, pxr) -> None:
    """Connect image files (``{"color": path, "normal": path}``, relative to the layer) to a
    preview surface through ``UsdUVTexture`` readers of ``st``."""
    Gf, Sdf, Usd, UsdGeom, UsdShade = pxr
    cutoff = _cutoff(scene, mat_name)
    reader = UsdShade.Shader.Define(stage, m.GetPath().AppendChild("st"))
    reader.CreateIdAttr("UsdPrimvarReader_float2")
    reader.CreateInput("varname", Sdf.ValueTypeNames.String).Set("st")
    st = reader.CreateOutput("result", Sdf.ValueTypeNames.Float2)
    for kind, path in files.items():
        tex = UsdShade.Shader.Define(stage, m.GetPath().AppendChild(f"{kind}_texture"))
        tex.CreateIdAttr("UsdUVTexture")
        tex.CreateInput("file", Sdf.ValueTypeNames.Asset).Set(path)
        tex.CreateInput("st", Sdf.ValueTypeNames.Float2).ConnectToSource(st)
        if kind == "color":
            tex.CreateInput("sourceColorSpace", Sdf.ValueTypeNames.Token).Set("sRGB")
            rgb = tex.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
            a = tex.CreateOutput("a", Sdf.ValueTypeNames.Float)
            sh.GetInput("diffuseColor").ConnectToSource(rgb)
            sh.GetInput("opacity").ConnectToSource(a)
            if cutoff is not None:
                sh.CreateInput("opacityThreshold", Sdf.ValueTypeNames.Float).Set(float(cutoff))
        else:
            tex.CreateInput("sourceColorSpace", Sdf.ValueTypeNames.Token).Set("raw")
            tex.CreateInput("scale", Sdf.ValueTypeNames.Float4).Set(Gf.Vec4f(2, 2, 2, 1))
            tex.CreateInput("bias", Sdf.ValueTypeNames.Float4).Set(Gf.Vec4f(-1, -1, -1, 0))
            rgb = tex.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
            sh.CreateInput("normal", Sdf.ValueTypeNames.Normal3f).ConnectToSource(rgb)
