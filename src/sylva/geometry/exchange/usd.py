"""Universal Scene Description (``.usd``, ``.usda``, ``.usdc``), when ``usd-core`` is installed.

Each mesh becomes a ``UsdGeom.Mesh`` (points, normals, ``primvars:st``, ``displayColor``:
the colour each vertex is drawn with, its tint times its material colour) with a
``GeomSubset`` per material bound to a ``UsdPreviewSurface`` material; the subsets form a
``partition`` of the faces (every face in exactly one), the family type that
``UsdValidation`` asks of material subsets.  Baked material images (written beside a path
target) are ``UsdUVTexture`` shaders reading ``st`` (``u, 1 - v``: USD's ``t`` runs up the
image) and feeding the surface's colour, opacity (cut-outs), normal and roughness.
Double-sided materials make their meshes ``doubleSided``.  The stage has one metre per unit
and its ``upAxis`` is ``up``: ``"y"`` (the default, sylva's frame) or ``"z"`` (the points
rotated, ``(x, y, z) -> (x, -z, y)``).

Examples
--------
>>> available() in (True, False)
True
"""

from __future__ import annotations

import os
import shutil
import tempfile

import numpy as np

from ..._atomic import AtomicGroup, atomic_path, os_error_from_text
from ...errors import SylvaError
from ._common import (
    PathOrFile,
    as_scene,
    check_up,
    material_groups,
    material_of,
    oriented_scene,
    safe_name,
    shaded_colors,
    target_path,
)
from ._textures import scene_images, stem_of, usd_textures, v_up, write_companions

__all__ = ["available", "write_usd"]


def available() -> bool:
    """True when the ``pxr`` package of ``usd-core`` can be imported."""
    try:
        import pxr  # noqa: F401
    except ImportError:
        return False
    return True


def _ident(name: str) -> str:
    s = safe_name(name).replace("-", "_").replace(".", "_")
    return s if not s[0].isdigit() else "_" + s


def write_usd(scene, target: PathOrFile, *, suffix: str | None = None, up: str = "y") -> None:
    """Write a USD stage to a path (or a binary file object, via a temporary file).

    usd-core writes by file name: a path target gets a temporary file beside it (same
    suffix, so the same format) that replaces it only once the stage is saved.  ``up`` is
    the stage's ``upAxis`` (``"y"``, USD's default, or ``"z"``)."""
    if not available():
        raise SylvaError("USD export needs the usd-core package: pip install usd-core")
    from pxr import Gf, Sdf, Tf, Usd, UsdGeom, UsdShade, Vt

    up = check_up(up)
    scene = oriented_scene(as_scene(scene), up)
    pxr = (Gf, Sdf, Usd, UsdGeom, UsdShade, Vt)
    if isinstance(target, (str, os.PathLike)):
        images = scene_images(scene, stem_of(target_path(target)))
        if images:  # baked images beside the stage, all appearing together, the stage last
            with AtomicGroup() as group:
                write_companions(group, os.path.dirname(os.fspath(target)), images)
                tmp = group.path(target, main=True)
                try:
                    _write_stage(scene, tmp, up, pxr, images)
                except Tf.ErrorException as exc:
                    raise os_error_from_text(str(exc), tmp, "usd-core") from None
            return
        with atomic_path(target) as tmp:
            try:
                _write_stage(scene, tmp, up, pxr)
            except Tf.ErrorException as exc:  # a full disk, in usd-core's words
                raise os_error_from_text(str(exc), tmp, "usd-core") from None
        return
    tmpdir = tempfile.mkdtemp(prefix="sylva-usd-")
    try:
        path = os.path.join(tmpdir, "scene" + (suffix or ".usdc"))
        _write_stage(scene, path, up, pxr)
        with open(path, "rb") as fh:
            shutil.copyfileobj(fh, target)  # type: ignore[arg-type]
    finally:
        shutil.rmtree(tmpdir, ignore_errors=True)


def _write_stage(scene, path: str, up: str, pxr, images: dict | None = None) -> None:
    Gf, Sdf, Usd, UsdGeom, UsdShade, Vt = pxr
    stage = Usd.Stage.CreateNew(path)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z if up == "z" else UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    root = UsdGeom.Xform.Define(stage, "/" + _ident(scene.name))
    stage.SetDefaultPrim(root.GetPrim())
    looks: dict[str, UsdShade.Material] = {}
    base = root.GetPath()
    for k, mesh in enumerate(scene.meshes):
        if mesh.n_triangles == 0:
            continue
        gm = UsdGeom.Mesh.Define(stage, base.AppendChild(f"{_ident(mesh.name)}_{k}"))
        gm.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
        gm.CreateOrientationAttr(UsdGeom.Tokens.rightHanded)
        gm.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(mesh.vertices))
        gm.CreateFaceVertexCountsAttr(
            Vt.IntArray.FromNumpy(np.full(mesh.n_triangles, 3, np.int32))
        )
        gm.CreateFaceVertexIndicesAttr(
            Vt.IntArray.FromNumpy(mesh.indices.reshape(-1).astype(np.int32))
        )
        gm.CreateNormalsAttr(Vt.Vec3fArray.FromNumpy(mesh.normals))
        gm.SetNormalsInterpolation(UsdGeom.Tokens.vertex)
        lo, hi = mesh.bounds()
        gm.CreateExtentAttr(
            Vt.Vec3fArray([Gf.Vec3f(*map(float, lo)), Gf.Vec3f(*map(float, hi))])
        )
        pv = UsdGeom.PrimvarsAPI(gm)
        if mesh.uvs is not None:
            st = pv.CreatePrimvar(
                "st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.vertex
            )
            st.Set(Vt.Vec2fArray.FromNumpy(v_up(mesh.uvs)))  # USD's t runs up the image
        if mesh.colors is not None:
            dc = gm.CreateDisplayColorPrimvar(UsdGeom.Tokens.vertex)
            dc.Set(Vt.Vec3fArray.FromNumpy(np.ascontiguousarray(shaded_colors(mesh)[:, :3])))
        wind = (mesh.attributes or {}).get("WIND")
        if wind is not None:  # the wind vertex data of sylva.geometry.lod, as a primvar
            pw = pv.CreatePrimvar("wind", Sdf.ValueTypeNames.Float4Array, UsdGeom.Tokens.vertex)
            pw.Set(Vt.Vec4fArray.FromNumpy(np.ascontiguousarray(wind[:, :4], np.float32)))
        if any(m.double_sided for m in mesh.materials):
            gm.CreateDoubleSidedAttr(True)
        binding = UsdShade.MaterialBindingAPI.Apply(gm.GetPrim())
        groups = material_groups(mesh)
        mesh_looks = set()
        for mid, tris in groups:
            mat = material_of(mesh, mid)
            key = _ident(mat.name)
            if key not in looks:
                m = UsdShade.Material.Define(stage, base.AppendChild("Looks").AppendChild(key))
                sh = UsdShade.Shader.Define(stage, m.GetPath().AppendChild("Surface"))
                sh.CreateIdAttr("UsdPreviewSurface")
                sh.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).Set(
                    Gf.Vec3f(*map(float, mat.color[:3]))
                )
                sh.CreateInput("opacity", Sdf.ValueTypeNames.Float).Set(float(mat.color[3]))
                sh.CreateInput("roughness", Sdf.ValueTypeNames.Float).Set(float(mat.roughness))
                sh.CreateInput("metallic", Sdf.ValueTypeNames.Float).Set(float(mat.metallic))
                if images and mat.name in images:
                    usd_textures(stage, m, sh, images[mat.name], mat, pxr)
                m.CreateSurfaceOutput().ConnectToSource(sh.ConnectableAPI(), "surface")
                if getattr(mat, "billboard", False):  # USD has no billboard: say it
                    m.GetPrim().CreateAttribute("sylva:billboard",
                                                Sdf.ValueTypeNames.Bool).Set(True)
                looks[key] = m
            mesh_looks.add(key)
            if len(groups) == 1:
                continue
            subset = binding.CreateMaterialBindSubset(
                key, Vt.IntArray.FromNumpy(np.sort(tris).astype(np.int32)), UsdGeom.Tokens.face
            )
            UsdShade.MaterialBindingAPI.Apply(subset.GetPrim()).Bind(looks[key])
        if len(groups) == 1:
            binding.Bind(looks[next(iter(mesh_looks))])
        else:
            binding.SetMaterialBindSubsetsFamilyType(UsdGeom.Tokens.partition)
    stage.GetRootLayer().Save()
