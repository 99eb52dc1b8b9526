"""Images inside formats: the baked images a :class:`~sylva.geometry.mesh.Material` carries
(:class:`~sylva.geometry.mesh.MaterialImages`), as the files and references each writer needs.

The images are laid over the mesh's uvs with ``v = 0`` on the first row of the file,
glTF's convention and the renderer's.  OBJ, USD and POV-Ray put ``v = 0`` on the last row,
so those writers write ``1 - v`` (:func:`v_up`), and every format shares the same files.

Writers that reference images:

* glTF / GLB — PBR metallic-roughness ``baseColorTexture``, ``normalTexture`` and
  ``metallicRoughnessTexture`` (roughness in green), a white ``baseColorFactor``; a
  cut-out (an image with transparent pixels: a leaf's outline) is ``alphaMode: MASK``
  and double-sided.  GLB embeds the PNGs in its buffer; ``.gltf`` writes them beside.
* OBJ / MTL — ``map_Kd``, ``map_d`` (cut-outs), ``norm`` (and ``map_Bump``, where Blender
  reads normal maps) and ``map_Pr``.
* USD — ``UsdUVTexture`` shaders reading ``st`` through a ``UsdPrimvarReader_float2``,
  connected to the ``UsdPreviewSurface``.
* POV-Ray — ``uv_mapping`` ``image_map`` pigments.

Examples
--------
>>> import numpy as np
>>> from sylva.geometry.mesh import Material, with_images
>>> rgba = np.full((8, 8, 4), 255, np.uint8)
>>> files = image_files(with_images(Material("bark"), rgba), "tree")
>>> sorted(files), files["color"][0]
(['color'], 'tree.bark.color.png')
>>> files["color"][1][:8] == b"\\x89PNG\\r\\n\\x1a\\n"
True
"""

from __future__ import annotations

import io
import os

import numpy as np

from ..mesh import Material
from ._common import safe_name

__all__ = ["GltfTextures", "image_files", "png_bytes", "scene_images", "tangents", "textured",
           "textured_materials", "v_up", "write_companions"]


def textured(mat: Material | None) -> bool:
    """Whether ``mat`` carries baked images."""
    return mat is not None and getattr(mat, "images", None) is not None


def textured_materials(meshes) -> dict[str, Material]:
    """The textured materials of ``meshes`` by name (first seen wins, as in the writers)."""
    out: dict[str, Material] = {}
    for mesh in meshes:
        for mat in mesh.materials:
            if textured(mat) and mat.name not in out:
                out[mat.name] = mat
    return out


def png_bytes(arr: np.ndarray) -> bytes:
    """PNG-encoded ``arr`` (uint8 ``[h, w]``, ``[h, w, 3]`` or ``[h, w, 4]``)."""
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(arr, dtype=np.uint8)).save(buf, format="PNG",
                                                                    optimize=False)
    return buf.getvalue()


def v_up(uvs: np.ndarray) -> np.ndarray:
    """``uvs`` with ``v`` measured up the image (``1 - v``): OBJ's, USD's and POV-Ray's
    convention, from sylva's (glTF's) ``v`` down the image."""
    out = np.array(uvs, np.float32, copy=True)
    out[:, 1] = 1.0 - out[:, 1]
    return out


def image_files(mat: Material, stem: str, *, gltf: bool = False) -> dict[str, tuple[str, bytes]]:
    """``{slot: (file name, PNG bytes)}`` of ``mat``'s images: ``color`` (RGBA) and
    ``normal`` always; with ``gltf``, ``metallic_roughness`` (roughness in green, metallic
    0 in blue); else ``roughness`` (grey) and, for a cut-out, ``alpha`` (its alpha as grey,
    for MTL's ``map_d``)."""
    imgs = mat.images
    if imgs is None:
        return {}
    base = f"{stem}.{safe_name(mat.name)}"
    out = {"color": (f"{base}.color.png", png_bytes(imgs.base_color))}
    if not gltf and imgs.has_alpha:
        out["alpha"] = (f"{base}.alpha.png", png_bytes(imgs.base_color[:, :, 3]))
    if imgs.normal is not None:
        out["normal"] = (f"{base}.normal.png", png_bytes(imgs.normal))
    if imgs.roughness is not None:
        r = imgs.roughness
        if gltf:
            mr = np.stack([np.full_like(r, 255), r, np.zeros_like(r)], axis=-1)
            out["roughness"] = (f"{base}.metallic_roughness.png", png_bytes(mr))
        else:
            out["roughness"] = (f"{base}.roughness.png", png_bytes(r))
    return out


def stem_of(path: str | os.PathLike | None, default: str = "scene") -> str:
    """The file stem companions are named after (``plant`` for ``out/plant.obj``)."""
    if path is None:
        return default
    return os.path.splitext(os.path.basename(os.fspath(path)))[0] or default


# --------------------------------------------------------------------------- glTF
class GltfTextures:
    """The ``images``, ``textures`` and ``samplers`` of a glTF document being built.

    ``embed``: images go into the binary buffer (GLB, or a ``.gltf`` written to a file
    object); else they are files beside the document, listed in :attr:`files`.
    """

    def __init__(self, stem: str, embed: bool = True) -> None:
        self.stem = stem
        self.embed = embed
        self.images: list[dict] = []
        self.textures: list[dict] = []
        self.files: list[tuple[str, bytes]] = []
        self._pending: list[tuple[int, bytes]] = []
        self._by_material: dict[str, dict[str, int]] = {}

    def scales(self, meshes, scales: dict[str, float]) -> dict[str, float]:
        """The tint scales with every textured material's at 1: the image carries its
        colour, so ``COLOR_0`` is the tint itself (clamped to [0, 1])."""
        out = dict(scales)
        for name in textured_materials(meshes):
            out[name] = 1.0
        return out

    def _texture(self, name: str, data: bytes) -> int:
        k = len(self.images)
        if self.embed:
            self.images.append({"mimeType": "image/png", "name": name})
            self._pending.append((k, data))
        else:
            self.images.append({"uri": name, "name": name})
            self.files.append((name, data))
        self.textures.append({"sampler": 0, "source": k})
        return len(self.textures) - 1

    def material(self, mat: Material, out: dict) -> dict:
        """``out`` (a material's JSON) referencing ``mat``'s images, if it has any."""
        if not textured(mat):
            return out
        slots = self._by_material.get(mat.name)
        if slots is None:
            files = image_files(mat, self.stem, gltf=True)
            slots = {slot: self._texture(name, data) for slot, (name, data) in files.items()}
            self._by_material[mat.name] = slots
        pbr = out["pbrMetallicRoughness"]
        pbr["baseColorFactor"] = [1.0, 1.0, 1.0, float(mat.color[3])]
        pbr["baseColorTexture"] = {"index": slots["color"]}
        if "roughness" in slots:
            pbr["metallicRoughnessTexture"] = {"index": slots["roughness"]}
            pbr["roughnessFactor"] = 1.0
        if "normal" in slots:
            out["normalTexture"] = {"index": slots["normal"]}
        if mat.images.has_alpha:
            out["alphaMode"] = "MASK"
            out["alphaCutoff"] = float(mat.alpha_cutoff if mat.alpha_cutoff is not None else 0.5)
            out["doubleSided"] = True
        return out

    def finish(self, doc: dict, builder) -> None:
        """Embed the pending images in ``builder``'s buffer (bufferViews without a target)
        and put the arrays into ``doc``; call before the buffer is joined."""
        for k, data in self._pending:
            self.images[k]["bufferView"] = builder.view(data, None)
        self._pending.clear()
        if self.images:
            doc["images"] = self.images
            doc["textures"] = self.textures
            # linear-mipmap-linear, repeat: the bark tiles along the stems
            doc["samplers"] = [{"magFilter": 9729, "minFilter": 9987,
                                "wrapS": 10497, "wrapT": 10497}]  # fmt: skip



def needs_tangents(mesh) -> bool:
    """Whether a mesh uses a material with a normal map (and has uvs to lay it with)."""
    return mesh.uvs is not None and any(
        textured(m) and m.images.normal is not None for m in mesh.materials
    )


def tangents(mesh) -> np.ndarray:
    """``float32[n, 4]`` glTF ``TANGENT`` of ``mesh`` (see :func:`tangents_numpy`), by the
    compiled loop :func:`sylva.geometry._kernels.vertex_tangents` (a 20 M-triangle plant's
    tangents took most of its GLB's writing time in NumPy)."""
    from .._kernels import vertex_tangents

    return vertex_tangents(
        np.ascontiguousarray(mesh.vertices), np.ascontiguousarray(mesh.normals),
        np.ascontiguousarray(mesh.uvs), np.ascontiguousarray(mesh.indices.astype(np.int64)),
    )  # fmt: skip


def tangents_numpy(mesh) -> np.ndarray:
    """``float32[n, 4]`` glTF ``TANGENT`` of ``mesh``: xyz the unit direction of ``+u`` on
    the surface, orthogonal to the normal, and w (±1) the handedness that makes
    ``cross(normal, xyz) * w`` point up the image (towards smaller ``v``), the normal maps'
    green (per-triangle uv gradients summed at the vertices, then Gram-Schmidt)."""
    p = mesh.vertices.astype(np.float64)
    uv = mesh.uvs.astype(np.float64)
    idx = mesh.indices.astype(np.int64)
    n = mesh.normals.astype(np.float64)
    nv = mesh.n_vertices
    e1 = p[idx[:, 1]] - p[idx[:, 0]]
    e2 = p[idx[:, 2]] - p[idx[:, 0]]
    d1 = uv[idx[:, 1]] - uv[idx[:, 0]]
    d2 = uv[idx[:, 2]] - uv[idx[:, 0]]
    det = d1[:, 0] * d2[:, 1] - d2[:, 0] * d1[:, 1]
    ok = np.abs(det) > 1e-14
    r = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)[:, None]
    t = (e1 * d2[:, 1:2] - e2 * d1[:, 1:2]) * r  # dP/du
    b = (e2 * d1[:, 0:1] - e1 * d2[:, 0:1]) * r  # dP/dv
    ts = np.zeros((nv, 3))
    bs = np.zeros((nv, 3))
    flat = idx.reshape(-1)
    for c in range(3):
        ts[:, c] = np.bincount(flat, weights=np.repeat(t[:, c], 3), minlength=nv)
        bs[:, c] = np.bincount(flat, weights=np.repeat(b[:, c], 3), minlength=nv)
    ts -= n * (n * ts).sum(axis=1, keepdims=True)
    length = np.linalg.norm(ts, axis=1)
    bad = length < 1e-12
    if bad.any():  # no uv gradient: any direction orthogonal to the normal
        alt = np.where(np.abs(n[bad, 0:1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
        alt -= n[bad] * (n[bad] * alt).sum(axis=1, keepdims=True)
        ts[bad] = alt
        length = np.linalg.norm(ts, axis=1)
    ts /= np.maximum(length, 1e-30)[:, None]
    w = np.where((np.cross(n, ts) * -bs).sum(axis=1) < 0.0, -1.0, 1.0)
    return np.concatenate([ts, w[:, None]], axis=1).astype(np.float32)


# --------------------------------------------------------------------------- files beside
def scene_images(scene, stem: str) -> dict[str, dict[str, tuple[str, bytes]]]:
    """``{material name: image_files(...)}`` of the textured materials of ``scene`` (the
    files OBJ, USD and POV-Ray write beside)."""
    return {name: image_files(mat, stem)
            for name, mat in textured_materials(scene.meshes).items()}  # fmt: skip


def write_companions(group, folder: str, images: dict) -> None:
    """Write every image of ``images`` (:func:`scene_images`) into ``folder`` as members
    of the :class:`~sylva._atomic.AtomicGroup` ``group``."""
    for files in images.values():
        for name, data in files.values():
            with group.open(os.path.join(folder, name), "wb") as fh:
                fh.write(data)


def mtl_maps(files: dict[str, tuple[str, bytes]]) -> list[str]:
    """The MTL lines referencing one material's image files."""
    out = [f"map_Kd {files['color'][0]}"]
    if "alpha" in files:
        out.append(f"map_d {files['alpha'][0]}")
    if "normal" in files:  # norm: the PBR extension; map_Bump: as Blender reads (and writes) it
        out.append(f"norm {files['normal'][0]}")
        out.append(f"map_Bump -bm 1 {files['normal'][0]}")
    if "roughness" in files:
        out.append(f"map_Pr {files['roughness'][0]}")
    return out


# --------------------------------------------------------------------------- USD
def usd_textures(stage, material, surface, files: dict, mat: Material, pxr) -> None:
    """Connect ``files`` (one material's :func:`image_files`, written beside the stage) to
    the ``UsdPreviewSurface`` ``surface`` of ``material``: ``UsdUVTexture`` shaders reading
    the ``st`` primvar through one ``UsdPrimvarReader_float2``."""
    Gf, Sdf, _Usd, _UsdGeom, UsdShade, _Vt = pxr
    path = material.GetPath()
    reader = UsdShade.Shader.Define(stage, path.AppendChild("STReader"))
    reader.CreateIdAttr("UsdPrimvarReader_float2")
    st_name = material.CreateInput("frame:stPrimvarName", Sdf.ValueTypeNames.String)
    st_name.Set("st")
    reader.CreateInput("varname", Sdf.ValueTypeNames.String).ConnectToSource(st_name)
    st_out = reader.CreateOutput("result", Sdf.ValueTypeNames.Float2)

    def texture(slot: str, name: str, colour_space: str):
        tex = UsdShade.Shader.Define(stage, path.AppendChild(name))
        tex.CreateIdAttr("UsdUVTexture")
        tex.CreateInput("file", Sdf.ValueTypeNames.Asset).Set("./" + files[slot][0])
        tex.CreateInput("st", Sdf.ValueTypeNames.Float2).ConnectToSource(st_out)
        tex.CreateInput("wrapS", Sdf.ValueTypeNames.Token).Set("repeat")
        tex.CreateInput("wrapT", Sdf.ValueTypeNames.Token).Set("repeat")
        tex.CreateInput("sourceColorSpace", Sdf.ValueTypeNames.Token).Set(colour_space)
        return tex

    colour = texture("color", "ColorTexture", "sRGB")
    rgb = colour.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
    surface.GetInput("diffuseColor").ConnectToSource(rgb)
    if mat.images.has_alpha:
        a = colour.CreateOutput("a", Sdf.ValueTypeNames.Float)
        surface.GetInput("opacity").ConnectToSource(a)
        cut = mat.alpha_cutoff if mat.alpha_cutoff is not None else 0.5
        surface.CreateInput("opacityThreshold", Sdf.ValueTypeNames.Float).Set(float(cut))
    if "normal" in files:
        nt = texture("normal", "NormalTexture", "raw")
        nt.CreateInput("scale", Sdf.ValueTypeNames.Float4).Set(Gf.Vec4f(2, 2, 2, 1))
        nt.CreateInput("bias", Sdf.ValueTypeNames.Float4).Set(Gf.Vec4f(-1, -1, -1, 0))
        out = nt.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
        surface.CreateInput("normal", Sdf.ValueTypeNames.Normal3f).ConnectToSource(out)
    if "roughness" in files:
        rt = texture("roughness", "RoughnessTexture", "raw")
        out = rt.CreateOutput("r", Sdf.ValueTypeNames.Float)
        surface.GetInput("roughness").ConnectToSource(out)
