"""What every grown thing can do: render, save, show in a notebook (the one-line API).

:class:`Shown` is the base of :class:`sylva.plant.Plant`, :class:`sylva.grown.TreePlant` and
:class:`sylva.grown.WorldView`.  A subclass gives its :attr:`~Shown.scene`, its default
camera mode and render options, and its statistics; the rest is here, once:

* :meth:`~Shown.render` — an offscreen image (:func:`sylva.render.render`, headless EGL);
* :meth:`~Shown.save` — an image (``.png``, ``.jpg``) or any export format, by extension,
  through :func:`sylva.geometry.exchange.write` (written atomically);
* :meth:`~Shown.show` — the interactive three.js view of :mod:`sylva.widgets`;
* ``_repr_png_`` — the static image Jupyter, nbconvert and GitHub show inline.

Every import of the renderer, the exporters and the widgets happens inside the methods, so
``import sylva`` stays light.
"""

from __future__ import annotations

import os
from pathlib import Path

from .errors import SylvaError

__all__ = ["IMAGE_SUFFIXES", "Shown", "check_size", "register_ipython", "scene_png"]

#: Suffixes :meth:`Shown.save` renders an image for (the rest are export formats).
IMAGE_SUFFIXES = frozenset({".png", ".jpg", ".jpeg"})

#: The size of the inline image in a notebook.
REPR_SIZE = (480, 360)


def check_size(size, what: str = "size") -> tuple[int, int]:
    """``size`` as ``(width, height)``: an int (square) or a pair of positive ints."""
    if isinstance(size, bool):
        raise SylvaError(f"{what}: expected (width, height) in pixels, got {size!r}")
    if isinstance(size, int):
        size = (size, size)
    try:
        w, h = (int(v) for v in size)
        ok = all(float(v) == int(v) for v in size)
    except (TypeError, ValueError):
        raise SylvaError(f"{what}: expected (width, height) in pixels, got {size!r}") from None
    if not ok or w < 1 or h < 1 or w * h > 400_000_000:
        raise SylvaError(f"{what}: expected positive whole pixel counts, got {size!r}")
    return w, h


class Shown:
    """Render, save and show: the methods shared by plants, trees and worlds.

    A subclass has a ``scene`` (a :class:`sylva.geometry.mesh.Scene`) and ``stats``.
    """

    def _camera_mode(self) -> str:
        return "perspective"

    def _render_options(self, size: tuple[int, int]) -> dict:
        return {}

    def _render_scene(self, mode: str, size: tuple[int, int]):
        return self.scene

    # ------------------------------------------------------------------ images
    def render(self, size=(640, 480), camera=None, **options):
        """An image of it, rendered offscreen (no display needed).

        Parameters
        ----------
        size : int or (int, int)
            Width and height in pixels (an int is a square).
        camera : {"perspective", "orthographic", "2d"} or sylva.render.Camera, optional
            Default: ``"2d"`` for planar L-systems, else ``"perspective"``, framed on the
            whole scene.
        **options
            Passed to :func:`sylva.render.render` (``bg``, ``shadows``, ``ground``, ``sky``,
            ``transparent``, ``msaa`` …).

        Returns
        -------
        PIL.Image.Image
        """
        from .render import Camera, render

        size = check_size(size)
        if camera is None or isinstance(camera, str):
            mode = camera or self._camera_mode()
            mode = "orthographic" if mode == "ortho" else mode
            if mode not in ("perspective", "orthographic", "2d"):
                raise SylvaError(
                    f"camera: expected 'perspective', 'orthographic', '2d' or a Camera, "
                    f"got {camera!r}"
                )
            scene = self._render_scene(mode, size)
            cam = Camera.auto(scene.bounds(), mode, aspect=size[0] / size[1]) \
                if scene.meshes else mode
        elif isinstance(camera, Camera):
            scene, cam = self._render_scene(camera.mode, size), camera
        else:
            raise SylvaError(f"camera: expected a mode name or a Camera, got {camera!r}")
        opts = {**self._render_options(size), **options}
        return render(scene, size=size, camera=cam, **opts)

    def _repr_png_(self) -> bytes:
        import io

        buf = io.BytesIO()
        self.render(REPR_SIZE).save(buf, format="PNG")
        return buf.getvalue()

    # ------------------------------------------------------------------ files
    def save(self, path: str | os.PathLike, **options) -> Path:
        """Write it to ``path``; the extension picks the format.

        ``.png`` and ``.jpg`` render an image (``size=``, ``camera=`` and the options of
        :meth:`render`); every other extension is an export format of
        :mod:`sylva.geometry.exchange` (``.glb .gltf .obj .ply .stl .scad .pov .svg .usd``),
        its ``options`` going to the writer.  The file appears whole or not at all.
        ``textures=SIZE`` bakes the procedural materials into ``SIZE``-pixel images that the
        file references (glTF, OBJ, USD, POV-Ray; see :mod:`sylva.assets`).

        Returns
        -------
        pathlib.Path
            The path written.
        """
        path = Path(path)
        if path.suffix.lower() in IMAGE_SUFFIXES:
            from .render import save_image

            size = options.pop("size", (1280, 960))
            camera = options.pop("camera", None)
            img = self.render(size, camera, **options)
            bg = options.get("bg", self._render_options(check_size(size)).get("bg", "white"))
            save_image(img, path, bg=bg)
            return path
        from .geometry.exchange import format_of

        fmt = format_of(path)
        textures = options.pop("textures", None)
        if textures is not None:
            from .assets import textured_export
            from .geometry.exchange import write

            write(textured_export(self.scene, fmt, textures, "textures"), path, format=fmt,
                  **options)  # fmt: skip
            return path
        self._write(path, fmt, options)
        return path

    def _write(self, path: Path, fmt: str, options: dict) -> None:
        from .geometry.exchange import write

        write(self.scene, path, format=fmt, **options)

    # ------------------------------------------------------------------ notebook
    def show(self, **options):
        """The interactive three.js view of :mod:`sylva.widgets` (orbit, zoom, steps).

        Returns the widget; as the last expression of a notebook cell it is displayed.
        ``options`` go to :func:`sylva.widgets.view` (``height=``, ``camera=``).
        """
        from .widgets import view

        return view(self, **options)

    def __repr__(self) -> str:
        s = self.stats
        inner = ", ".join(f"{k}={v!r}" for k, v in s.items() if not isinstance(v, (list, dict)))
        return f"<{type(self).__name__} {inner}>"


def scene_png(scene) -> bytes:
    """A :class:`~sylva.geometry.mesh.Scene` or ``Mesh`` as PNG bytes (for notebooks)."""
    import io

    from .render import render

    buf = io.BytesIO()
    render(scene, size=REPR_SIZE).save(buf, format="PNG")
    return buf.getvalue()


def register_ipython(shell) -> None:
    """Show scenes and meshes as PNGs in IPython (registered by name: nothing is
    imported until one is displayed; :mod:`sylva.geometry` itself knows no renderer)."""
    png = shell.display_formatter.formatters["image/png"]
    for name in ("Scene", "Mesh"):
        png.for_type_by_name("sylva.geometry.mesh", name, scene_png)
