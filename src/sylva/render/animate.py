"""Animations: growth (one frame per scene) and turntables, written as GIF or MP4.

Frames are produced lazily and written as they come, so long animations do not sit in memory.
Progress goes to standard error through :mod:`tqdm`.

Examples
--------
>>> import numpy as np, tempfile, pathlib
>>> from sylva.geometry.mesh import Mesh, Scene
>>> tri = Mesh(np.array([[-1, 0, 0], [1, 0, 0], [0, 2, 0]]), np.array([[0, 1, 2]]))
>>> frames = turntable_frames(Scene([tri]), n_frames=3, size=(32, 32), msaa=0, ground=False)
>>> out = pathlib.Path(tempfile.mkdtemp()) / "spin.gif"
>>> write_animation(frames, out, fps=10, progress=False).stat().st_size > 0
True
"""

from __future__ import annotations

import contextlib
import errno
import io
import os
import signal
import sys
from collections.abc import Callable, Iterable, Iterator, Sequence
from pathlib import Path

import numpy as np
from PIL import Image
from tqdm import tqdm

from sylva._atomic import AtomicGroup, os_error_from_text
from sylva.geometry.mesh import Mesh, Scene
from sylva.render.camera import Camera
from sylva.render.offscreen import Renderer, parse_color
from sylva.render.scene import GROUND_SCALE, SKY_GROUND_SCALE, GpuScene, Ground, Sky

__all__ = [
    "Frames",
    "growth_frames",
    "render_frames",
    "turntable_frames",
    "tween",
    "write_animation",
]

_FORMATS = {".gif": "gif", ".mp4": "mp4", ".m4v": "mp4", ".mov": "mp4"}


def _union_bounds(scenes: Sequence) -> np.ndarray:
    boxes = [np.asarray(s.bounds(), np.float64) for s in scenes]
    b = np.stack(boxes)
    return np.stack([b[:, 0].min(axis=0), b[:, 1].max(axis=0)])


def _fixed_ground(ground, bounds, scale: float = GROUND_SCALE) -> Ground | bool:
    """A ground plane that does not move from frame to frame (default side: ``scale`` × extent)."""
    if ground is False:
        return False
    g = Ground() if ground in (None, True) else ground
    mesh_bounds = np.asarray(bounds, np.float64)
    ext = mesh_bounds[1] - mesh_bounds[0]
    return Ground(
        height=float(mesh_bounds[0, 1]) if g.height is None else g.height,
        size=scale * max(float(ext.max()), 1e-3) if g.size is None else g.size,
        center=(
            (
                0.5 * (mesh_bounds[0, 0] + mesh_bounds[1, 0]),
                0.5 * (mesh_bounds[0, 2] + mesh_bounds[1, 2]),
            )
            if g.center is None
            else g.center
        ),
        material=g.material,
    )


class Frames:
    """Frames rendered lazily on each iteration, with a known count (for progress bars).

    Parameters
    ----------
    make : callable
        Returns a fresh iterator of PIL images.
    count : int
        How many it yields.
    """

    def __init__(self, make: Callable[[], Iterator[Image.Image]], count: int) -> None:
        self._make = make
        self._count = int(count)

    def __len__(self) -> int:
        return self._count

    def __iter__(self) -> Iterator[Image.Image]:
        return iter(self._make())


def render_frames(
    scenes: Iterable[Scene | Mesh],
    size=(640, 480),
    camera: Camera | str | None = None,
    **options,
) -> Iterator[Image.Image]:
    """Render each scene with the same settings (a generator of PIL images).

    Parameters
    ----------
    scenes : iterable of Scene or Mesh
    size : (int, int)
    camera : Camera or mode name, optional
        A mode name frames each scene on its own; pass a :class:`Camera` to keep it fixed.
    **options
        Passed to :func:`sylva.render.render`.
    """
    renderer = Renderer.default()
    mode = "RGBA" if options.get("transparent") else "RGB"
    for scene in scenes:
        yield Image.fromarray(renderer.render(scene, size, camera, **options), mode)


def growth_frames(
    scenes: Sequence[Scene | Mesh],
    size=(640, 480),
    camera: Camera | str | None = None,
    *,
    yaw: float | None = None,
    pitch: float | None = None,
    substeps: int = 1,
    **options,
) -> Frames:
    """Frames of a growing plant: one per scene, with a fixed camera and ground.

    Give one scene per derivation step for stepwise growth, or scenes at finely spaced times
    of a parametric (timed) system for smooth growth.  The camera is framed on the union of
    all scenes (the grown plant), so the plant grows inside a still frame.  With
    ``substeps > 1`` each step is followed by in-between frames: interpolated (see
    :func:`tween`) where consecutive scenes have the same triangles, which is the case when a
    parametric system only changes lengths and angles, and held otherwise.

    Parameters
    ----------
    scenes : sequence of Scene or Mesh
    size : (int, int)
    camera : Camera or mode name, optional
        A :class:`Camera` is used as is; a mode name (default perspective) is framed.
    yaw, pitch : float, optional
        View direction for the automatic framing.
    substeps : int
        Frames per step (1: one frame per scene).
    **options
        Passed to :func:`sylva.render.render`.
    """
    if substeps < 1:
        raise ValueError(f"substeps must be ≥ 1, got {substeps}")
    scenes = list(scenes)
    if not scenes:
        return Frames(lambda: iter(()), 0)
    bounds = _union_bounds(scenes)
    w, h = size
    if not isinstance(camera, Camera):
        camera = Camera.auto(bounds, camera or "perspective", yaw=yaw, pitch=pitch, aspect=w / h)
    ground = options.pop("ground", None)
    if ground is None:
        ground = camera.mode != "2d"
    sky = options.get("sky")
    fades = sky is True or isinstance(sky, Sky) and sky.ground_fade
    fades = fades and camera.mode != "2d" and not options.get("transparent")
    options["ground"] = _fixed_ground(ground, bounds, SKY_GROUND_SCALE if fades else GROUND_SCALE)
    count = (len(scenes) - 1) * substeps + 1
    return Frames(
        lambda: render_frames(_in_between(scenes, substeps), size, camera, **options), count
    )


def _in_between(scenes: list, substeps: int) -> Iterator:
    for a, b in zip(scenes, scenes[1:]):
        yield a
        if substeps > 1:
            ma = a if isinstance(a, Mesh) else a.merged()
            mb = b if isinstance(b, Mesh) else b.merged()
            for k in range(1, substeps):
                yield tween(ma, mb, k / substeps) or a
    yield scenes[-1]


def tween(a: Mesh, b: Mesh, t: float) -> Mesh | None:
    """Linear blend of two meshes with the same triangles, or None when they differ.

    Parameters
    ----------
    a, b : Mesh
        Two states of one plant (same vertex count, indices and material ids).
    t : float
        0 gives ``a``, 1 gives ``b``.

    Returns
    -------
    Mesh or None
        Positions, uvs and colours blended linearly, normals blended and renormalised; None
        when the topology differs (a new module appeared), so no blend is meaningful.

    Examples
    --------
    >>> import numpy as np
    >>> a = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]))
    >>> b = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 3, 0]]), np.array([[0, 1, 2]]))
    >>> tween(a, b, 0.5).vertices[2].tolist()
    [0.0, 2.0, 0.0]
    """
    if (
        a.n_vertices != b.n_vertices
        or not np.array_equal(a.indices, b.indices)
        or not np.array_equal(a.triangle_materials(), b.triangle_materials())
        or (a.uvs is None) != (b.uvs is None)
        or (a.colors is None) != (b.colors is None)
    ):
        return None

    def lerp(x, y):
        return None if x is None else (1 - t) * x + t * y

    n = lerp(a.normals, b.normals)
    length = np.linalg.norm(n, axis=1, keepdims=True)
    n = np.where(length > 1e-12, n / np.where(length > 1e-12, length, 1.0), a.normals)
    return Mesh(
        lerp(a.vertices, b.vertices),
        a.indices,
        normals=n,
        uvs=lerp(a.uvs, b.uvs),
        colors=lerp(a.colors, b.colors),
        material_ids=a.material_ids,
        materials=b.materials,
        name=b.name,
    )


def turntable_frames(
    scene: Scene | Mesh,
    n_frames: int = 36,
    size=(640, 480),
    camera: Camera | str | None = None,
    *,
    degrees: float = 360.0,
    pitch: float | None = None,
    **options,
) -> Frames:
    """Frames of the camera orbiting the plant about the vertical axis.

    The scene is uploaded once and the shadow map reused, so each frame costs one draw.  The
    automatic framing keeps one distance for every yaw (the plant does not pulse in size).

    Parameters
    ----------
    scene : Scene or Mesh
    n_frames : int
        Number of frames; the last one stops one step short of ``degrees`` so that a loop of
        a full turn does not repeat a frame.
    size : (int, int)
    camera : Camera or mode name, optional
        The starting camera (its yaw is the first frame's).  In ``"2d"`` the view cannot turn:
        all frames are the same.
    degrees : float
        Total turn.
    pitch : float, optional
        Elevation for the automatic framing.
    **options
        Passed to :func:`sylva.render.render`.
    """
    if n_frames < 1:
        raise ValueError(f"n_frames must be ≥ 1, got {n_frames}")
    renderer = Renderer.default()
    bounds = scene.bounds if isinstance(scene, GpuScene) else np.asarray(scene.bounds())
    w, h = size
    if not isinstance(camera, Camera):
        mode = camera or "perspective"
        fits = [
            Camera.auto(bounds, mode, yaw=k * 360.0 / 12, pitch=pitch, aspect=w / h)
            for k in range(12)
        ]
        widest = max(fits, key=lambda c: c.distance if c.mode == "perspective" else c.height)
        camera = Camera.auto(bounds, mode, yaw=0.0, pitch=pitch, aspect=w / h)
        camera.distance, camera.height = widest.distance, widest.height
    mode = "RGBA" if options.get("transparent") else "RGB"

    def frames() -> Iterator[Image.Image]:
        gpu = renderer.upload(scene)  # once for all frames (the shadow map is reused too)
        try:
            for k in range(n_frames):
                cam = camera.orbit(yaw=degrees * k / n_frames)
                yield Image.fromarray(renderer.render(gpu, size, cam, **options), mode)
        finally:
            if gpu is not scene:
                gpu.release()

    return Frames(frames, n_frames)


def _to_rgb(frame, bg) -> np.ndarray:
    img = frame if isinstance(frame, Image.Image) else Image.fromarray(np.asarray(frame))
    if img.mode in ("RGBA", "LA"):
        flat = Image.new("RGB", img.size, tuple(round(c * 255) for c in parse_color(bg)))
        flat.paste(img, mask=img.getchannel("A"))
        img = flat
    return np.asarray(img.convert("RGB"))


def write_animation(
    frames: Iterable,
    path,
    fps: float = 12.0,
    *,
    loop: int = 0,
    progress: bool = True,
    total: int | None = None,
    bg="white",
    quality: float = 8.0,
    desc: str | None = None,
) -> Path:
    """Write frames to a GIF or an MP4 (H.264) file, with a progress bar on stderr.

    Parameters
    ----------
    frames : iterable of PIL.Image.Image or uint8 ndarray ``(h, w, 3|4)``
        All the same size; consumed lazily.  Transparent frames are flattened onto ``bg``.
    path : str or Path
        ``.gif``, or ``.mp4``/``.m4v``/``.mov``.
    fps : float
        Frames per second.
    loop : int
        GIF repeat count (0: for ever).
    progress : bool
        Show a tqdm progress bar on standard error.
    total : int, optional
        Number of frames, for the progress bar (taken from ``len(frames)`` when it has one).
    bg : str or colour triple
        Background for transparent frames.
    quality : float
        MP4 quality, 0–10 (imageio-ffmpeg's scale).
    desc : str, optional
        Progress bar label (default: the file name).

    Returns
    -------
    Path
        The written file.

    Raises
    ------
    ValueError
        For an unknown suffix, a non-positive ``fps``, no frames, or frames of varying size.
    """
    path = Path(path)
    fmt = _FORMATS.get(path.suffix.lower())
    if fmt is None:
        raise ValueError(f"cannot write {path.name!r}: use .gif or .mp4")
    if not fps > 0:
        raise ValueError(f"fps must be > 0, got {fps}")
    if total is None and hasattr(frames, "__len__"):
        total = len(frames)
    shape = None
    count = 0
    # frames stream into a temporary file beside ``path`` that replaces it only once the
    # animation is complete: a failure (or Ctrl-C) leaves the previous file as it was
    with AtomicGroup() as group:
        writer = _Writer(fmt, group.path(path, main=True), fps, loop, quality)
        bar = tqdm(  # after the temporary file: a missing folder fails before any output
            frames,
            total=total,
            desc=desc or path.name,
            unit="frame",
            file=sys.stderr,
            disable=not progress,
            leave=True,
        )
        try:
            for frame in bar:
                rgb = _to_rgb(frame, bg)
                if shape is None:
                    shape = rgb.shape
                elif rgb.shape != shape:
                    raise ValueError(
                        f"frame {count} is {rgb.shape[:2]}, the first was {shape[:2]}")
                writer.send(rgb)
                count += 1
            if count == 0:
                raise ValueError("no frames to write")
        except BaseException:
            writer.abort()
            raise
        finally:
            bar.close()
        writer.close()
    return path


class _Writer:
    """Streams frames to a GIF (Pillow) or to ffmpeg (H.264); :meth:`close` finishes the
    file and raises ``OSError`` when it could not be written whole.

    imageio's writers hide failures: its ffmpeg writer never reads ffmpeg's exit status (a
    full disk gives a truncated MP4 and no error) and its GIF writer repeats a failed flush
    from ``__del__``.  So the GIF is assembled by Pillow in memory and written with Python's
    checked writes, and ffmpeg runs here, its exit status checked and
    its complaint turned into the ``OSError`` it met.
    """

    def __init__(self, fmt, path, fps, loop, quality):
        self.fmt, self.path, self.fps, self.loop, self.quality = fmt, path, fps, loop, quality
        self._frames: list[Image.Image] = []
        self._proc = None
        self._log: list[bytes] = []
        self._reader = None

    def send(self, rgb: np.ndarray) -> None:
        if self.fmt == "gif":
            self._frames.append(Image.fromarray(rgb))
            return
        pad_h, pad_w = rgb.shape[0] % 2, rgb.shape[1] % 2  # yuv420p needs even sides
        if pad_h or pad_w:
            rgb = np.pad(rgb, ((0, pad_h), (0, pad_w), (0, 0)), mode="edge")
        if self._proc is None:
            self._start(rgb.shape[1], rgb.shape[0])
        try:
            self._proc.stdin.write(np.ascontiguousarray(rgb).tobytes())
        except (BrokenPipeError, OSError):
            self._finish()  # ffmpeg stopped: raise what it met
            raise

    def _start(self, w: int, h: int) -> None:
        import subprocess
        import threading
        from fractions import Fraction

        import imageio_ffmpeg

        crf = int((1 - self.quality / 10.0) * 51)  # imageio-ffmpeg's quality scale
        cmd = [imageio_ffmpeg.get_ffmpeg_exe(), "-y", "-loglevel", "error", "-nostdin",
               "-f", "rawvideo", "-vcodec", "rawvideo", "-s", f"{w}x{h}", "-pix_fmt", "rgb24",
               "-r", str(Fraction(self.fps).limit_denominator()), "-i", "-", "-an",
               "-vcodec", "libx264", "-pix_fmt", "yuv420p", "-crf", str(crf), self.path]
        self._proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL,
                                      stderr=subprocess.PIPE)
        # drain ffmpeg's log as it comes, so a chatty failure cannot fill the pipe
        self._reader = threading.Thread(target=lambda: self._log.extend(self._proc.stderr),
                                        daemon=True)
        self._reader.start()

    def _finish(self) -> None:
        proc, self._proc = self._proc, None
        if proc is None:
            return
        with contextlib.suppress(OSError):
            proc.stdin.close()
        code = proc.wait()
        self._reader.join()
        proc.stderr.close()
        if code == -signal.SIGXFSZ:  # killed for passing the file size limit
            raise OSError(errno.EFBIG, os.strerror(errno.EFBIG), self.path)
        if code != 0:
            text = b"".join(self._log).decode("utf-8", "replace")
            raise os_error_from_text(text or f"exit status {code}", self.path, "ffmpeg")

    def close(self) -> None:
        if self.fmt != "gif":
            self._finish()
            return
        frames, self._frames = self._frames, []
        if not frames:
            return
        args = dict(format="GIF", duration=1000.0 / self.fps, loop=self.loop)
        if len(frames) > 1:
            args.update(save_all=True, append_images=frames[1:])
        buf = io.BytesIO()  # Pillow writes to a descriptor unchecked; Python's writes check
        frames[0].save(buf, **args)
        with open(self.path, "wb") as fh:
            fh.write(buf.getbuffer())

    def abort(self) -> None:
        """Stop without finishing (the temporary file is discarded by the caller)."""
        self._frames = []
        proc, self._proc = self._proc, None
        if proc is not None:
            with contextlib.suppress(OSError):
                proc.stdin.close()
            proc.kill()
            proc.wait()
            self._reader.join()
            proc.stderr.close()
