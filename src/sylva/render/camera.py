"""Cameras: perspective, orthographic and 2D, framed automatically to a scene.

The world is right-handed with Y up.  A camera orbits a *target* (LSysVis's focus point,
seed 001 §5.4): ``yaw`` turns it about +Y, ``pitch`` raises it, ``distance`` is the distance to
the target.  ``yaw = pitch = 0`` puts the eye on +Z looking down -Z, which is also the 2D camera
(an orthographic view of the XY plane with rotation locked).

Matrices are ``float64[4, 4]`` acting on column vectors (``clip = P @ V @ [x, y, z, 1]``).

Examples
--------
>>> import numpy as np
>>> cam = Camera.auto(np.array([[-1, 0, -1], [1, 4, 1]]), mode="orthographic", yaw=0, pitch=0)
>>> cam.target.tolist()
[0.0, 2.0, 0.0]
>>> corners = project(cam, np.array([[-1, 0, 0], [1, 4, 0]]), aspect=1.0)
>>> bool(np.all(np.abs(corners[:, :2]) <= 1.0))
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

__all__ = ["MODES", "Camera", "look_at", "project", "tile_matrix"]

#: The camera modes of seed 001 §5.4.
MODES = ("perspective", "orthographic", "2d")


def _bounds_of(obj) -> np.ndarray:
    """``float64[2, 3]`` bounds of a Scene, Mesh, GpuScene, (N, 3) points or a (2, 3) box."""
    bounds = getattr(obj, "bounds", None)
    if bounds is not None:  # a Scene or Mesh method, or a GpuScene's array
        b = np.asarray(bounds() if callable(bounds) else bounds, dtype=np.float64)
    else:
        pts = np.asarray(obj, dtype=np.float64).reshape(-1, 3)
        if pts.shape[0] == 0:
            return np.zeros((2, 3))
        b = np.stack([pts.min(axis=0), pts.max(axis=0)])
    return b


def box_corners(bounds: np.ndarray) -> np.ndarray:
    """The 8 corners ``float64[8, 3]`` of an axis-aligned box ``[[min], [max]]``."""
    b = np.asarray(bounds, dtype=np.float64)
    idx = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    return np.stack([b[idx[:, 0], 0], b[idx[:, 1], 1], b[idx[:, 2], 2]], axis=1)


def look_at(eye, target, up) -> np.ndarray:
    """A view matrix ``float64[4, 4]`` with the eye at the origin looking down -Z."""
    eye = np.asarray(eye, np.float64)
    f = np.asarray(target, np.float64) - eye
    f /= np.linalg.norm(f)
    r = np.cross(f, np.asarray(up, np.float64))
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = r, u, -f
    m[:3, 3] = -m[:3, :3] @ eye
    return m


def tile_matrix(x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    """Clip-space matrix that maps the NDC window ``[x0, x1] × [y0, y1]`` onto ``[-1, 1]²``.

    Multiplying a projection by it on the left gives the off-centre (shifted) frustum of one
    tile, for perspective and orthographic projections alike.
    """
    sx, sy = 2.0 / (x1 - x0), 2.0 / (y1 - y0)
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    m = np.eye(4)
    m[0, 0], m[0, 3] = sx, -sx * cx
    m[1, 1], m[1, 3] = sy, -sy * cy
    return m


@dataclass
class Camera:
    """An orbit camera.

    Parameters
    ----------
    mode : {"perspective", "orthographic", "2d"}
        ``"2d"`` is orthographic looking down -Z at the XY plane; its yaw and pitch are locked
        at 0.
    target : array_like of 3 float
        The focus point the camera looks at.
    yaw, pitch : float
        Degrees about +Y and above the horizon.
    distance : float
        Eye-to-target distance (> 0).  For orthographic modes it only places the eye.
    fov : float
        Vertical field of view in degrees (perspective).
    height : float
        Visible world height at the target (orthographic modes).
    near, far : float or None
        Clip planes; ``None`` lets the renderer fit them to what it draws.
    roll : float
        Degrees the camera turns about its view axis, counter-clockwise as seen from the
        eye (so the picture turns clockwise); cpfg's ``twist`` is ``-twist / 10``.
    """

    mode: str = "perspective"
    target: np.ndarray = field(default_factory=lambda: np.zeros(3))
    yaw: float = 0.0
    pitch: float = 0.0
    distance: float = 10.0
    fov: float = 35.0
    height: float = 10.0
    near: float | None = None
    far: float | None = None
    roll: float = 0.0

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ValueError(f"camera mode must be one of {MODES}, got {self.mode!r}")
        self.target = np.asarray(self.target, dtype=np.float64).reshape(3)
        if self.mode == "2d":
            self.yaw = 0.0
            self.pitch = 0.0
        if not self.distance > 0:
            raise ValueError(f"camera distance must be > 0, got {self.distance}")
        if not 0 < self.fov < 180:
            raise ValueError(f"field of view must be in (0, 180) degrees, got {self.fov}")
        if not self.height > 0:
            raise ValueError(f"orthographic height must be > 0, got {self.height}")

    # ---------------------------------------------------------------- construction
    @classmethod
    def auto(
        cls,
        scene,
        mode: str = "perspective",
        *,
        yaw: float | None = None,
        pitch: float | None = None,
        distance: float | None = None,
        target=None,
        fov: float = 35.0,
        aspect: float = 1.0,
        margin: float = 0.05,
        roll: float = 0.0,
    ) -> Camera:
        """A camera that frames ``scene`` for the given view direction.

        Parameters
        ----------
        scene : Scene, Mesh or array_like
            Anything with ``bounds()``, or points ``(N, 3)`` (a ``(2, 3)`` box works).
        mode : {"perspective", "orthographic", "2d"}
        yaw, pitch : float, optional
            Degrees; default 30 and 20 for 3D modes (0 and 0, locked, in 2D).
        distance : float, optional
            Override the fitted distance (perspective; orthographic modes scale ``height``
            by it relative to the fitted distance, like a zoom).
        target : array_like of 3 float, optional
            Override the focus point (default: the centre of the bounding box).
        fov : float
            Vertical field of view in degrees.
        aspect : float
            Width / height of the image the camera is for.
        margin : float
            Fraction of the image left empty on the tightest side.
        roll : float
            Degrees about the view axis (:attr:`roll`).

        Returns
        -------
        Camera
            All eight corners of the bounding box lie inside the view.
        """
        if mode == "2d":
            yaw = pitch = 0.0
        yaw = 30.0 if yaw is None else float(yaw)
        pitch = 20.0 if pitch is None else float(pitch)
        b = _bounds_of(scene)
        center = 0.5 * (b[0] + b[1])
        tgt = center if target is None else np.asarray(target, np.float64).reshape(3)
        probe = cls(mode=mode, target=tgt, yaw=yaw, pitch=pitch, fov=fov, roll=roll)
        r, u, back = probe.basis()
        rel = box_corners(b) - tgt
        x, y, z = rel @ r, rel @ u, rel @ back  # z > 0 is towards the eye
        extent = float(np.linalg.norm(b[1] - b[0]))
        tiny = max(extent, 1e-6) * 1e-3
        scale = 1.0 - margin
        if mode == "perspective":
            ty = math.tan(math.radians(fov) / 2) * scale
            tx = ty * aspect
            fit = float(np.max(np.maximum(z + np.abs(x) / tx, z + np.abs(y) / ty)))
            fit = max(fit, tiny)
            height = 2.0 * fit * math.tan(math.radians(fov) / 2)
            dist = fit if distance is None else float(distance)
        else:
            half = float(max(np.max(np.abs(y)), np.max(np.abs(x)) / aspect)) / scale
            height = 2.0 * max(half, tiny)
            fit = float(np.max(z)) + max(extent, 1e-6)
            dist = fit
            if distance is not None:
                height *= float(distance) / fit
                dist = float(distance)
        return cls(
            mode=mode, target=tgt, yaw=yaw, pitch=pitch, distance=dist, fov=fov, height=height,
            roll=roll,
        )

    @classmethod
    def from_view(
        cls,
        scene,
        viewpoint=(0.0, 0.0, 1.0),
        reference=(0.0, 0.0, 0.0),
        *,
        twist: float = 0.0,
        projection: str = "parallel",
        scale: float = 1.0,
        aspect: float = 1.0,
        fov: float = 35.0,
    ) -> Camera:
        """The camera of a cpfg view file, framing ``scene``.

        cpfg looks from ``viewpoint`` towards the ``view reference point``, with world
        ``+Y`` up turned by ``twist`` (tenths of a degree, as cpfg reads it) about the view
        axis, ``parallel`` (orthographic) or ``perspective``, and fits the object's box to
        its window, times the ``scale factor``.

        Examples
        --------
        >>> box = np.array([[-1.0, 0, -1], [1, 4, 1]])
        >>> cam = Camera.from_view(box, (0, 0, 5), (0, 0, 0), twist=900)
        >>> cam.mode, round(cam.roll, 6), np.round(cam.basis()[1], 6).tolist()
        ('orthographic', -90.0, [1.0, 0.0, 0.0])
        """
        d = np.asarray(viewpoint, np.float64).reshape(3) - np.asarray(reference, np.float64)
        n = float(np.linalg.norm(d))
        d = d / n if n > 0 else np.array([0.0, 0.0, -1.0])  # cpfg's default view normal
        pitch = math.degrees(math.asin(max(-1.0, min(1.0, float(d[1])))))
        yaw = math.degrees(math.atan2(float(d[0]), float(d[2])))
        if abs(d[0]) < 1e-12 and abs(d[2]) < 1e-12:
            yaw = 0.0
        mode = "perspective" if str(projection).strip().lower() == "perspective" else (
            "orthographic")
        s = float(scale) if math.isfinite(scale) and scale > 0 else 1.0
        return cls.auto(scene, mode, yaw=yaw, pitch=float(np.clip(pitch, -89.9, 89.9)),
                        fov=fov, aspect=aspect, margin=1.0 - 0.95 * s,
                        roll=-0.1 * float(twist))  # fmt: skip

    def orbit(self, yaw: float = 0.0, pitch: float = 0.0) -> Camera:
        """A copy turned by ``yaw`` and ``pitch`` degrees (a no-op in 2D: rotation is locked)."""
        if self.mode == "2d":
            return replace(self)
        p = float(np.clip(self.pitch + pitch, -89.9, 89.9))
        return replace(self, yaw=self.yaw + yaw, pitch=p)

    # ---------------------------------------------------------------- geometry
    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Right, up and backward unit vectors (``backward`` points from target to eye)."""
        y, p = math.radians(self.yaw), math.radians(self.pitch)
        back = np.array([math.cos(p) * math.sin(y), math.sin(p), math.cos(p) * math.cos(y)])
        right = np.array([math.cos(y), 0.0, -math.sin(y)])
        up = np.cross(back, right)
        if self.roll:
            c, s = math.cos(math.radians(self.roll)), math.sin(math.radians(self.roll))
            right, up = c * right + s * up, c * up - s * right
        return right, up, back

    @property
    def eye(self) -> np.ndarray:
        """The eye position ``float64[3]``."""
        return self.target + self.distance * self.basis()[2]

    @property
    def orthographic(self) -> bool:
        return self.mode != "perspective"

    def view_matrix(self) -> np.ndarray:
        """World → eye ``float64[4, 4]``."""
        r, u, back = self.basis()
        m = np.eye(4)
        m[0, :3], m[1, :3], m[2, :3] = r, u, back
        m[:3, 3] = -m[:3, :3] @ self.eye
        return m

    def projection_matrix(
        self, aspect: float, near: float | None = None, far: float | None = None
    ) -> np.ndarray:
        """Eye → clip ``float64[4, 4]`` (OpenGL conventions, depth in ``[-1, 1]``)."""
        n = near if near is not None else (self.near or self.distance * 1e-3)
        f = far if far is not None else (self.far or self.distance * 1e3)
        if not 0 < n < f:
            raise ValueError(f"need 0 < near < far, got near={n}, far={f}")
        m = np.zeros((4, 4))
        if self.mode == "perspective":
            t = 1.0 / math.tan(math.radians(self.fov) / 2)
            m[0, 0], m[1, 1] = t / aspect, t
            m[2, 2], m[2, 3] = (f + n) / (n - f), 2 * f * n / (n - f)
            m[3, 2] = -1.0
        else:
            h = self.height / 2
            m[0, 0], m[1, 1] = 1.0 / (h * aspect), 1.0 / h
            m[2, 2], m[2, 3] = 2.0 / (n - f), (f + n) / (n - f)
            m[3, 3] = 1.0
        return m

    def clip_planes(self, bounds) -> tuple[float, float]:
        """Near and far planes that enclose ``bounds`` (explicit ``near``/``far`` win)."""
        rel = box_corners(_bounds_of(bounds)) - self.eye
        depth = rel @ -self.basis()[2]  # distance along the view direction
        dmax = float(np.max(depth))
        dmin = float(np.min(depth))
        far = self.far or max(dmax * 1.05, 1e-3)
        if self.orthographic:
            pad = 0.05 * (dmax - dmin) + 1e-3 * abs(dmax)
            near = self.near or max(dmin - pad, far * 1e-6)
        else:
            near = self.near or max(dmin * 0.95, far * 1e-4)
        if near >= far:
            near = far * 1e-4
        return float(near), float(far)


def project(camera: Camera, points, aspect: float, near=None, far=None) -> np.ndarray:
    """Normalised device coordinates ``float64[N, 3]`` of world ``points`` ``(N, 3)``."""
    pts = np.asarray(points, np.float64).reshape(-1, 3)
    if near is None or far is None:
        near, far = camera.clip_planes(pts) if len(pts) else (None, None)
    m = camera.projection_matrix(aspect, near, far) @ camera.view_matrix()
    h = np.concatenate([pts, np.ones((len(pts), 1))], axis=1) @ m.T
    return h[:, :3] / h[:, 3:4]
