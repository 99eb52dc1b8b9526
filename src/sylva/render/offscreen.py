"""Offscreen rendering of scenes to images.

:func:`render` draws a :class:`~sylva.geometry.mesh.Scene` (or a single Mesh) headless with
Phong lighting, a shadow-casting sun, point lights, procedural plant textures, MSAA, a ground
plane and a plain, transparent or sky (:class:`~sylva.render.scene.Sky`) background, and
returns a :class:`PIL.Image.Image`.  Images
larger than the framebuffer limit (or than ``tile_size``) are rendered in tiles through
off-centre frustums and stitched, which gives the same pixels as one large render.

Examples
--------
>>> import numpy as np
>>> from sylva.geometry.mesh import Mesh, Scene
>>> tri = Mesh(np.array([[-1, 0, 0], [1, 0, 0], [0, 1.5, 0]]), np.array([[0, 1, 2]]))
>>> img = render(Scene([tri]), size=(64, 48), camera="2d", msaa=0)
>>> img.size, img.mode
((64, 48), 'RGB')
>>> img.getpixel((0, 0)), img.getpixel((32, 24)) != (255, 255, 255)
((255, 255, 255), True)
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass
from pathlib import Path

import moderngl
import numpy as np
from PIL import Image, ImageColor

from sylva._atomic import save_buffered
from sylva.geometry.mesh import Mesh, Scene
from sylva.render._programs import compile_program
from sylva.render.camera import Camera, tile_matrix
from sylva.render.context import RenderError, get_context, max_render_size
from sylva.render.lights import MAX_POINT_LIGHTS, PointLight, Sun, default_lights
from sylva.render.scene import (
    GROUND_SCALE,
    SKY_GROUND_SCALE,
    TEX_IMAGE,
    TEXTURE_KINDS,
    GpuScene,
    Ground,
    Sky,
    material_shading,
)
from sylva.render.shadows import ShadowMap

__all__ = ["DEFAULT_TILE", "DepthImage", "Renderer", "parse_color", "render", "render_array",
           "save_image"]

#: Where a sky's ground fade starts, as a fraction of the ground's half side (it ends at the
#: edge, which is then exactly the horizon colour).
FADE_START = 0.5

#: Default tile side: big enough for 1080p in one piece, small enough for 4× MSAA on a CPU.
DEFAULT_TILE = 2048


def parse_color(value) -> tuple[float, float, float]:
    """An sRGB colour in [0, 1]³ from a name (``"white"``, ``"#87ceeb"``) or a triple.

    Triples of numbers all ≤ 1 are read as fractions, otherwise as 0–255 values.

    >>> parse_color("#ff8000")
    (1.0, 0.5019607843137255, 0.0)
    >>> parse_color((0, 0, 255))
    (0.0, 0.0, 1.0)
    """
    if isinstance(value, str):
        try:
            rgb = ImageColor.getrgb(value)
        except ValueError as exc:
            raise ValueError(f"unknown colour {value!r}: use a name or #rrggbb") from exc
        return tuple(c / 255.0 for c in rgb[:3])
    a = np.asarray(value, dtype=np.float64).ravel()
    if a.size not in (3, 4) or not np.all(np.isfinite(a)) or np.any(a < 0):
        raise ValueError(f"a colour needs 3 non-negative numbers, got {value!r}")
    a = a[:3]
    if np.any(a > 1.0):
        if np.any(a > 255):
            raise ValueError(f"colour components must be ≤ 255, got {value!r}")
        a = a / 255.0
    return tuple(float(c) for c in a)


def _size(size) -> tuple[int, int]:
    try:
        w, h = (int(s) for s in size)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"size must be (width, height), got {size!r}") from exc
    if w < 1 or h < 1:
        raise ValueError(f"image size must be at least 1 × 1, got {w} × {h}")
    return w, h


def _mat(m: np.ndarray) -> bytes:
    return np.asarray(m, np.float64).T.astype("f4").tobytes()


def _set(prog: moderngl.Program, name: str, value) -> None:
    """Set a uniform if the compiler kept it."""
    member = prog.get(name, None)
    if member is None:
        return
    if isinstance(value, np.ndarray):
        member.write(value.astype("f4").tobytes())
    else:
        member.value = value


@dataclass
class _Frame:
    """Per-frame state shared by every tile."""

    view_proj: np.ndarray
    camera: Camera
    sun: Sun | None
    points: list
    shadow: ShadowMap | None
    lit: bool
    textures: bool
    noise_scale: float
    aspect: float = 1.0
    sky: Sky | None = None
    ground: GpuScene | None = None  # the ground plane, when the sky fades it
    fade: tuple[float, float, float, float] | None = None  # centre x, z; fade start, end
    clip: tuple[float, float] = (0.0, 1.0)  # near and far planes


@dataclass
class DepthImage:
    """The depth of each pixel of a render (``Renderer.render(..., depth=True)``).

    Attributes
    ----------
    values : float32[h, w]
        Distance from the eye along the view axis (the camera's backward axis reversed),
        in scene units (metres for worlds and for species sized in metres), row 0 at the
        top; 0 where nothing was drawn (the background).
    near, far : float
        The clip planes the image was drawn with (every drawn value lies between them).
    """

    values: np.ndarray
    near: float
    far: float


def _linear_depth(d: np.ndarray, near: float, far: float, orthographic: bool) -> np.ndarray:
    """View-axis distance of depth-buffer values ``d`` in [0, 1] (OpenGL's default range)."""
    d = d.astype(np.float64)
    if orthographic:
        z = near + d * (far - near)
    else:
        z = 2.0 * far * near / ((far + near) - (2.0 * d - 1.0) * (far - near))
    return np.where(d >= 1.0, 0.0, z).astype(np.float32)


class Renderer:
    """Programs, framebuffers and textures bound to one context.

    Parameters
    ----------
    ctx : moderngl.Context, optional
        Defaults to the shared context of :func:`sylva.render.context.get_context`.

    Examples
    --------
    >>> r = Renderer.default()
    >>> r is Renderer.default()
    True
    """

    _local = threading.local()

    def __init__(self, ctx: moderngl.Context | None = None) -> None:
        self.ctx = ctx or get_context()
        self._programs: dict[tuple[str, ...], moderngl.Program] = {}
        self.depth_program = compile_program(self.ctx, "depth.vert.glsl", "depth.frag.glsl")
        self.max_size = max_render_size(self.ctx)
        self.max_samples = int(self.ctx.max_samples)
        self._white = self.ctx.texture((1, 1), 4, bytes([255, 255, 255, 255]))
        self._images: dict[tuple, tuple[moderngl.Texture, moderngl.Texture]] = {}
        self._targets: dict[tuple[int, int, int], tuple] = {}
        self._sky_program: moderngl.Program | None = None
        self._sky_vao: moderngl.VertexArray | None = None

    def program_for(self, defines) -> moderngl.Program:
        """The Phong shader variant with these ``#define`` names (compiled once, then cached).

        See ``shaders/phong.frag.glsl`` for the names; ``"TEXTURE_KIND 2"`` style entries set
        a value.
        """
        key = tuple(sorted(defines))
        if key not in self._programs:
            prog = compile_program(self.ctx, "phong.vert.glsl", "phong.frag.glsl", key)
            _set(prog, "texture_diffuse1", 0)
            _set(prog, "texture_specular1", 1)
            _set(prog, "u_shadow_map", 2)
            self._programs[key] = prog
        return self._programs[key]

    @classmethod
    def default(cls) -> Renderer:
        """The renderer of this thread's shared context (made on first use)."""
        r = getattr(cls._local, "renderer", None)
        if r is None or r.ctx is not get_context():
            r = cls()
            cls._local.renderer = r
        return r

    # ----------------------------------------------------------------- resources
    def upload(self, scene: Scene | Mesh) -> GpuScene:
        """Upload ``scene`` once to draw it many times (free it with ``release()``)."""
        if isinstance(scene, GpuScene):
            return scene
        if not isinstance(scene, Scene | Mesh):
            raise TypeError(f"expected a Scene or a Mesh, got {type(scene).__name__}")
        return GpuScene(self.ctx, scene, self.depth_program)

    def _image_textures(self, path: Path) -> tuple[moderngl.Texture, moderngl.Texture]:
        """Diffuse and specular textures of an image file (cached while the file is unchanged)."""
        if not path.is_file():
            raise RenderError(f"texture image {str(path)!r} does not exist")
        spec_path = path.with_name(f"{path.stem}_specular{path.suffix}")
        stamp = [path.stat().st_mtime_ns]
        if spec_path.is_file():
            stamp.append(spec_path.stat().st_mtime_ns)
        key = (path.resolve(), tuple(stamp))
        if key not in self._images:
            tex = self._texture(Image.open(path).convert("RGBA"))
            spec = self._white
            if spec_path.is_file():
                spec = self._texture(Image.open(spec_path).convert("RGBA"))
            self._images[key] = (tex, spec)
        return self._images[key]

    def _texture(self, img: Image.Image) -> moderngl.Texture:
        img = img.transpose(Image.Transpose.FLIP_TOP_BOTTOM)  # v = 0 at the bottom
        tex = self.ctx.texture(img.size, 4, img.tobytes())
        tex.build_mipmaps()
        tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
        return tex

    def _target(self, w: int, h: int, samples: int):
        key = (w, h, samples)
        if key not in self._targets:
            if len(self._targets) > 4:
                self._release_targets()
            ctx = self.ctx
            color = ctx.renderbuffer((w, h), 4, samples=samples)
            depth = ctx.depth_renderbuffer((w, h), samples=samples)
            fbo = ctx.framebuffer(color_attachments=[color], depth_attachment=depth)
            resolve = None
            if samples:
                rb = ctx.renderbuffer((w, h), 4)
                resolve = (ctx.framebuffer(color_attachments=[rb]), rb)
            self._targets[key] = (fbo, color, depth, resolve)
        return self._targets[key]

    def _release_targets(self) -> None:
        for fbo, color, depth, resolve in self._targets.values():
            fbo.release()
            color.release()
            depth.release()
            if resolve is not None:
                resolve[0].release()
                resolve[1].release()
        self._targets.clear()

    def release(self) -> None:
        """Free programs, framebuffers and textures."""
        self._release_targets()
        for tex, spec in self._images.values():
            tex.release()
            if spec is not self._white:
                spec.release()
        self._images.clear()
        self._white.release()
        if self._sky_program is not None:
            self._sky_vao.release()
            self._sky_program.release()
            self._sky_program = self._sky_vao = None
        for prog in self._programs.values():
            prog.release()
        self._programs.clear()
        self.depth_program.release()

    # ----------------------------------------------------------------- rendering
    def render(
        self,
        scene: Scene | Mesh | GpuScene,
        size=(800, 600),
        camera: Camera | str | None = None,
        *,
        lights=None,
        bg="white",
        transparent: bool = False,
        ground: Ground | bool | None = None,
        shadows: bool = True,
        msaa: int = 4,
        textures: bool = True,
        lit: bool = True,
        tile_size: int | None = None,
        shadow_size: int = 2048,
        sky: Sky | bool | None = None,
        depth: bool = False,
    ) -> np.ndarray:
        """Render to a ``uint8[h, w, 3]`` array (``[h, w, 4]`` when ``transparent``).

        Parameters are those of :func:`render`; ``depth=True`` (which needs ``msaa`` 0 or
        1: a multisampled pixel has no one depth) returns ``(array, DepthImage)``.
        """
        w, h = _size(size)
        gpu = self.upload(scene)
        owned = gpu is not scene
        try:
            return self._render(
                gpu,
                w,
                h,
                camera,
                lights,
                bg,
                transparent,
                ground,
                shadows,
                msaa,
                textures,
                lit,
                tile_size,
                shadow_size,
                sky,
                depth,
            )
        finally:
            if owned:
                gpu.release()

    def _render(
        self,
        gpu,
        w,
        h,
        camera,
        lights,
        bg,
        transparent,
        ground,
        shadows,
        msaa,
        textures,
        lit,
        tile_size,
        shadow_size,
        sky=None,
        depth=False,
    ) -> np.ndarray:
        aspect = w / h
        if depth and msaa > 1:
            raise ValueError(f"depth=True needs msaa 0 or 1, got {msaa}")
        sky = _sky(sky)
        if camera is None or isinstance(camera, str):
            camera = Camera.auto(gpu.bounds, camera or "perspective", aspect=aspect)
        elif not isinstance(camera, Camera):
            raise TypeError(f"camera must be a Camera or a mode name, got {camera!r}")
        if ground is None:
            ground = camera.mode != "2d"
        if transparent or camera.mode == "2d":
            sky = None  # a transparent background wins; a 2D view has no horizon
        if ground is True:
            ground = Ground()
        ground_gpu = None
        draw_bounds = shadow_bounds = gpu.bounds
        fading = sky is not None and sky.ground_fade
        if isinstance(ground, Ground):
            scale = SKY_GROUND_SCALE if fading else GROUND_SCALE
            ground_mesh = ground.mesh(gpu.bounds, scale)
            ground_gpu = GpuScene(self.ctx, ground_mesh, self.depth_program)
            draw_bounds = np.stack(
                [
                    np.minimum(gpu.bounds[0], ground_gpu.bounds[0]),
                    np.maximum(gpu.bounds[1], ground_gpu.bounds[1]),
                ]
            )
            shadow_bounds = draw_bounds
            if sky is not None:
                shadow_bounds = _near_ground(gpu.bounds, ground_gpu.bounds)
        elif ground is not False:
            raise TypeError(f"ground must be a Ground or a bool, got {ground!r}")
        try:
            sun, points = self._lights(default_lights() if lights is None else lights)
            near, far = camera.clip_planes(draw_bounds)
            view_proj = camera.projection_matrix(aspect, near, far) @ camera.view_matrix()
            shadow = None
            if lit and shadows and sun is not None and sun.shadows and not gpu.empty:
                shadow = self._shadow(gpu, sun, shadow_bounds, shadow_size)
            extent = max(float(np.max(gpu.bounds[1] - gpu.bounds[0])), 1e-6)
            frame = _Frame(view_proj, camera, sun, points, shadow, lit, textures, 20.0 / extent)
            frame.aspect, frame.sky = aspect, sky
            frame.clip = (near, far)
            if fading and ground_gpu is not None:
                gb = ground_gpu.bounds
                half = 0.5 * float(max(gb[1, 0] - gb[0, 0], gb[1, 2] - gb[0, 2]))
                cx, cz = 0.5 * (gb[0, 0] + gb[1, 0]), 0.5 * (gb[0, 2] + gb[1, 2])
                frame.ground, frame.fade = ground_gpu, (cx, cz, FADE_START * half, half)
            clear = (0.0, 0.0, 0.0, 0.0) if transparent else (*parse_color(bg), 1.0)
            samples = 0 if msaa <= 1 else min(int(msaa), self.max_samples)
            if samples == 1:
                samples = 0
            limit = min(int(tile_size or DEFAULT_TILE), self.max_size)
            if limit < 1:
                raise ValueError(f"tile_size must be ≥ 1, got {tile_size}")
            return self._tiles(frame, [gpu, ground_gpu], w, h, limit, samples, clear, transparent,
                               depth)
        finally:
            if ground_gpu is not None:
                ground_gpu.release()

    @staticmethod
    def _lights(lights) -> tuple[Sun | None, list[PointLight]]:
        if isinstance(lights, Sun | PointLight):
            lights = [lights]
        suns = [light for light in lights if isinstance(light, Sun)]
        points = [light for light in lights if isinstance(light, PointLight)]
        if len(suns) + len(points) != len(list(lights)):
            raise TypeError("lights must be Sun and PointLight objects")
        if len(suns) > 1:
            raise ValueError(f"at most one Sun is supported, got {len(suns)}")
        if len(points) > MAX_POINT_LIGHTS:
            raise ValueError(f"at most {MAX_POINT_LIGHTS} point lights, got {len(points)}")
        return (suns[0] if suns else None), points

    def _shadow(self, gpu: GpuScene, sun: Sun, receivers, size: int) -> ShadowMap:
        size = int(min(max(size, 16), self.max_size))
        key = (tuple(np.round(sun.direction, 9)), size, tuple(np.round(receivers, 9).ravel()))
        cached = gpu._shadow_cache.get("sun")
        if cached is not None and cached.key == key:
            return cached  # the sun and the scene have not moved: reuse the map
        if cached is not None:
            cached.release()
        shadow = ShadowMap(self.ctx, size)
        shadow.update(gpu, sun.direction, receivers, self.depth_program)
        shadow.key = key
        gpu._shadow_cache["sun"] = shadow
        return shadow

    def _tiles(self, frame, gpus, w, h, limit, samples, clear, transparent,
               depth=False) -> np.ndarray:  # fmt: skip
        tw, th = min(w, limit), min(h, limit)
        fbo, _, _, resolve = self._target(tw, th, samples)
        comps = 4 if transparent else 3
        out = np.empty((h, w, comps), np.uint8)
        zbuf = np.empty((h, w), np.float32) if depth else None
        for y0 in range(0, h, th):
            for x0 in range(0, w, tw):
                cw, ch = min(tw, w - x0), min(th, h - y0)
                tile = _tile(x0, y0, cw, ch, w, h)
                fbo.use()
                fbo.viewport = (0, 0, cw, ch)
                fbo.clear(*clear, depth=1.0, viewport=(0, 0, cw, ch))
                if frame.sky is not None:
                    self._draw_sky(frame, tile)
                self._draw(frame, gpus, tile @ frame.view_proj)
                src = fbo
                if resolve is not None:
                    self.ctx.copy_framebuffer(resolve[0], fbo)
                    src = resolve[0]
                data = src.read(viewport=(0, 0, cw, ch), components=comps, alignment=1)
                pixels = np.frombuffer(data, np.uint8).reshape(ch, cw, comps)
                # GL rows run bottom-up: flip each tile into its place
                out[h - y0 - ch : h - y0, x0 : x0 + cw] = pixels[::-1]
                if zbuf is not None:  # the tile frustum shifts x and y only: depth is kept
                    z = fbo.read(viewport=(0, 0, cw, ch), components=1, attachment=-1, alignment=1,
                                 dtype="f4")  # fmt: skip
                    zbuf[h - y0 - ch : h - y0, x0 : x0 + cw] = np.frombuffer(
                        z, np.float32).reshape(ch, cw)[::-1]
        image = _unpremultiply(out) if transparent else out
        if zbuf is None:
            return image
        near, far = frame.clip
        return image, DepthImage(_linear_depth(zbuf, near, far, frame.camera.orthographic),
                                 float(near), float(far))

    def _draw_sky(self, frame: _Frame, tile: np.ndarray) -> None:
        """Fill the tile with the sky gradient (no depth: the scene is drawn over it)."""
        if self._sky_program is None:
            self._sky_program = compile_program(self.ctx, "sky.vert.glsl", "sky.frag.glsl")
            self._sky_vao = self.ctx.vertex_array(self._sky_program, [])
        prog, sky = self._sky_program, frame.sky
        prog["u_sky_rays"].write(_mat(_sky_rays(frame.camera, frame.aspect, tile)))
        prog["u_zenith"].value = sky.zenith
        prog["u_horizon"].value = sky.horizon
        prog["u_sky_exponent"].value = sky.exponent
        self.ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND | moderngl.CULL_FACE)
        self._sky_vao.render(moderngl.TRIANGLES, vertices=3)

    def _draw(self, frame: _Frame, gpus, view_proj: np.ndarray) -> None:
        self.ctx.enable(moderngl.DEPTH_TEST)
        ready: set[int] = set()
        for gpu in gpus:
            if gpu is None or gpu.empty:
                continue
            for rng in gpu.ranges:
                shade = material_shading(rng.material)
                if not frame.textures:
                    shade = {**shade, "kind": 0}
                prog = self.program_for(_variant(gpu, shade, frame))
                if id(prog) not in ready:
                    self._frame_uniforms(prog, frame, view_proj)
                    ready.add(id(prog))
                self._draw_range(gpu, prog, rng, shade)
        self.ctx.disable(moderngl.BLEND)
        self.ctx.disable(moderngl.CULL_FACE)

    @staticmethod
    def _frame_uniforms(prog: moderngl.Program, frame: _Frame, view_proj: np.ndarray) -> None:
        """Camera and light uniforms, the same for every draw of a tile."""
        prog["u_view_proj"].write(_mat(view_proj))
        cam = frame.camera
        _set(prog, "u_view_pos", cam.eye)
        _set(prog, "u_view_dir", cam.basis()[2])
        _set(prog, "u_ortho", cam.orthographic)
        _set(prog, "u_noise_scale", frame.noise_scale)
        if frame.fade is not None:
            _set(prog, "u_fade_center", frame.fade[:2])
            _set(prog, "u_fade_range", frame.fade[2:])
            _set(prog, "u_horizon", frame.sky.horizon)
        sun = frame.sun
        if sun is not None:
            _set(prog, "u_sun_dir", sun.direction)
            _set(prog, "u_sun_diffuse", sun.color)
            _set(prog, "u_sun_ambient", sun.ambient)
            _set(prog, "u_sun_specular", sun.specular)
        if frame.shadow is not None:
            frame.shadow.texture.use(2)
            prog["u_light_view_proj"].write(_mat(frame.shadow.matrix))
            _set(prog, "u_shadow_texel", 1.0 / frame.shadow.size)
            _set(prog, "u_shadow_bias", frame.shadow.bias)
        n = len(frame.points)
        _set(prog, "u_n_points", n)
        if n:
            pad = MAX_POINT_LIGHTS - n
            for name, attr in (
                ("u_point_pos", "position"),
                ("u_point_diffuse", "color"),
                ("u_point_ambient", "ambient"),
                ("u_point_specular", "specular"),
                ("u_point_atten", "attenuation"),
            ):
                rows = [np.asarray(getattr(p, attr), np.float64) for p in frame.points]
                _set(prog, name, np.concatenate([np.stack(rows), np.zeros((pad, 3))]))

    def _draw_range(self, gpu: GpuScene, prog: moderngl.Program, rng, shade: dict) -> None:
        ctx = self.ctx
        self._white.use(0)
        self._white.use(1)
        if shade["kind"] == TEX_IMAGE:
            tex, spec = self._image_textures(shade["image"])
            tex.use(0)
            spec.use(1)
        _set(prog, "u_color", shade["color"])
        _set(prog, "u_shininess", shade["shininess"])
        _set(prog, "u_specular", shade["specular"])
        _set(prog, "u_double_sided", shade["double_sided"])
        _set(prog, "u_alpha_cutoff", shade["alpha_cutoff"])
        if shade["double_sided"]:
            ctx.disable(moderngl.CULL_FACE)
        else:
            ctx.enable(moderngl.CULL_FACE)
            ctx.cull_face = "back"
            ctx.front_face = "ccw"
        if shade["blend"]:
            ctx.enable(moderngl.BLEND)
            ctx.blend_func = (
                moderngl.SRC_ALPHA,
                moderngl.ONE_MINUS_SRC_ALPHA,
                moderngl.ONE,
                moderngl.ONE_MINUS_SRC_ALPHA,
            )
        else:
            ctx.disable(moderngl.BLEND)
        gpu.vao_for(prog).render(moderngl.TRIANGLES, vertices=3 * rng.count, first=3 * rng.first)


_NEEDS_UV = (TEX_IMAGE, TEXTURE_KINDS["bark"], TEXTURE_KINDS["leaf"])


def _variant(gpu: GpuScene, shade: dict, frame: _Frame) -> tuple[str, ...]:
    """The shader ``#define`` names for one material of one scene in this frame."""
    names = [f"TEXTURE_KIND {shade['kind']}"]
    if gpu.has_uv and shade["kind"] in _NEEDS_UV:
        names.append("HAS_UV")
    if gpu.has_colors:
        names.append("HAS_COLORS")
    if getattr(gpu, "has_billboards", False):
        names.append("BILLBOARD")
    if frame.lit:
        names.append("LIT")
        if frame.sun is not None:
            names.append("SUN")
            if frame.shadow is not None:
                names.append("SHADOWS")
        if frame.points:
            names.append("POINTS")
    if frame.fade is not None and gpu is frame.ground:
        names.append("GROUND_FADE")
    return tuple(names)


def _sky(sky) -> Sky | None:
    """The ``sky`` argument as a :class:`Sky` or None (off)."""
    if sky is None or sky is False:
        return None
    if sky is True:
        return Sky()
    if isinstance(sky, Sky):
        return sky
    raise TypeError(f"sky must be a Sky, True or False/None, got {sky!r}")


def _near_ground(scene_bounds: np.ndarray, ground_bounds: np.ndarray) -> np.ndarray:
    """The scene plus the part of the ground that a ground of default size would cover.

    The shadow map is fitted to this, not to a large faded ground, so that the shadows keep
    the depth precision they have without a sky.
    """
    b = np.asarray(scene_bounds, np.float64)
    g = np.asarray(ground_bounds, np.float64).copy()
    half = 0.5 * GROUND_SCALE * max(float(np.max(b[1] - b[0])), 1e-3)
    mid = 0.5 * (b[0] + b[1])
    for axis in (0, 2):
        g[0, axis] = min(max(g[0, axis], mid[axis] - half), mid[axis] + half)
        g[1, axis] = max(min(g[1, axis], mid[axis] + half), mid[axis] - half)
    return np.stack([np.minimum(b[0], g[0]), np.maximum(b[1], g[1])])


def _sky_rays(camera: Camera, aspect: float, tile: np.ndarray | None = None) -> np.ndarray:
    """The ``float64[3, 3]`` matrix from a pixel's ``(x_ndc, y_ndc, 1)`` to its world ray.

    ``tile`` is the off-centre frustum matrix of :func:`~sylva.render.camera.tile_matrix`
    (its NDC are mapped back to the whole image's first).  It is the inverse of the camera's
    rotation and projection without the clip planes, so it stays precise whatever they are;
    orthographic cameras get the rays of a perspective camera with their ``fov``.
    """
    t = math.tan(math.radians(camera.fov) / 2)
    eye = np.diag([t * aspect, t, -1.0])
    untile = np.eye(3)
    if tile is not None:
        untile[0, 0], untile[0, 2] = 1.0 / tile[0, 0], -tile[0, 3] / tile[0, 0]
        untile[1, 1], untile[1, 2] = 1.0 / tile[1, 1], -tile[1, 3] / tile[1, 1]
    basis = np.stack(camera.basis(), axis=1)  # columns: right, up, backward
    return basis @ eye @ untile


def _tile(x0: int, y0: int, cw: int, ch: int, w: int, h: int) -> np.ndarray:
    """Off-centre frustum matrix for pixels ``[x0, x0+cw) × [y0, y0+ch)`` (GL rows, bottom-up)."""
    if (x0, y0, cw, ch) == (0, 0, w, h):
        return np.eye(4)
    return tile_matrix(2 * x0 / w - 1, 2 * y0 / h - 1, 2 * (x0 + cw) / w - 1, 2 * (y0 + ch) / h - 1)


def _unpremultiply(rgba: np.ndarray) -> np.ndarray:
    """Straight alpha from the premultiplied result of drawing over a (0, 0, 0, 0) clear."""
    a = rgba[..., 3:4].astype(np.float32)
    rgb = rgba[..., :3].astype(np.float32)
    safe = np.where(a > 0, a, 1.0)
    rgb = np.where(a > 0, np.clip(rgb * 255.0 / safe, 0, 255), 0)
    out = np.concatenate([np.rint(rgb), a], axis=-1).astype(np.uint8)
    return out


# --------------------------------------------------------------------- module API
def render_array(scene, size=(800, 600), camera=None, **options) -> np.ndarray:
    """Like :func:`render`, but return ``uint8[h, w, 3|4]`` (row 0 at the top)."""
    return Renderer.default().render(scene, size, camera, **options)


def render(
    scene,
    size=(800, 600),
    camera: Camera | str | None = None,
    *,
    lights=None,
    bg="white",
    transparent: bool = False,
    ground: Ground | bool | None = None,
    shadows: bool = True,
    msaa: int = 4,
    textures: bool = True,
    lit: bool = True,
    tile_size: int | None = None,
    shadow_size: int = 2048,
    sky: Sky | bool | None = None,
) -> Image.Image:
    """Render a scene offscreen.

    Parameters
    ----------
    scene : Scene, Mesh or GpuScene
        What to draw (upload it with ``Renderer.default().upload`` to draw it many times).
    size : (int, int)
        Width and height in pixels; any size (beyond the GL limit it is tiled).
    camera : Camera or {"perspective", "orthographic", "2d"}, optional
        A mode name (or ``None``, perspective) frames the scene automatically with
        :meth:`Camera.auto` for this image's aspect ratio.
    lights : list of Sun and PointLight, optional
        Default: :func:`~sylva.render.lights.default_lights` (one shadow-casting sun).
        An empty list renders black unless ``lit`` is false.
    bg : str or colour triple
        Background colour (sRGB), e.g. ``"white"``, ``"#87ceeb"``, ``(0.1, 0.1, 0.1)``.
        Unused behind a sky.
    transparent : bool
        Return RGBA with a transparent background instead of ``bg``.
    ground : Ground or bool, optional
        A ground plane under the plant; default on for 3D cameras and off for ``"2d"``.
    shadows : bool
        Let the sun cast shadows (shadow mapping).
    msaa : int
        Samples per pixel (0 or 1: none; capped at what the driver supports).
    textures : bool
        Use the materials' procedural and image textures.
    lit : bool
        False draws unlit colours (albedo), e.g. for masks and texture previews.
    tile_size : int, optional
        Largest tile side (default :data:`DEFAULT_TILE`, capped at the GL limit).
    shadow_size : int
        Shadow-map resolution.
    sky : Sky or bool, optional
        A sky gradient behind 3D views instead of ``bg`` (``True``: the default
        :class:`~sylva.render.scene.Sky`, whose ground fade also grows a default ground to
        10 × the scene so that it vanishes in the haze).  Off by default, in ``"2d"`` and
        when ``transparent``.

    Returns
    -------
    PIL.Image.Image
        ``"RGB"``, or ``"RGBA"`` when ``transparent``.
    """
    arr = render_array(
        scene,
        size,
        camera,
        lights=lights,
        bg=bg,
        transparent=transparent,
        ground=ground,
        shadows=shadows,
        msaa=msaa,
        textures=textures,
        lit=lit,
        tile_size=tile_size,
        shadow_size=shadow_size,
        sky=sky,
    )
    return Image.fromarray(arr, "RGBA" if transparent else "RGB")


def save_image(image, path, *, bg="white", quality: int = 95) -> Path:
    """Write an image as PNG or JPEG (chosen by the suffix).

    Parameters
    ----------
    image : PIL.Image.Image or uint8 ndarray ``(h, w, 3|4)``
    path : str or Path
        ``.png``, ``.jpg`` or ``.jpeg``.
    bg : str or colour triple
        JPEG has no alpha: transparent images are flattened onto this colour.
    quality : int
        JPEG quality (1–95).

    Returns
    -------
    Path
    """
    path = Path(path)
    if isinstance(image, np.ndarray):
        image = Image.fromarray(np.ascontiguousarray(image))
    suffix = path.suffix.lower()
    if suffix == ".png":
        save_buffered(path, lambda fh: image.save(fh, format="PNG"))
    elif suffix in (".jpg", ".jpeg"):
        if image.mode in ("RGBA", "LA"):
            rgb = tuple(round(c * 255) for c in parse_color(bg))
            flat = Image.new("RGB", image.size, rgb)
            flat.paste(image, mask=image.getchannel("A"))
            image = flat
        rgb_image = image.convert("RGB")
        save_buffered(path, lambda fh: rgb_image.save(fh, format="JPEG", quality=int(quality)))
    else:
        raise ValueError(f"cannot write {path.name!r}: use .png, .jpg or .jpeg")
    return path
