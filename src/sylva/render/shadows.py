"""Shadow mapping for the sun.

The scene (the casters) is drawn depth-only from the sun through an orthographic projection
fitted to its bounding box; the main pass compares each fragment's depth in that projection
with the map (3 × 3 percentage-closer filtering on hardware-compared samples).  The ground
receives shadows but does not cast them, and points outside the map are lit.

Seed 004 §3.7 leaves the technique unwritten; this is standard directional shadow mapping.
"""

from __future__ import annotations

import moderngl
import numpy as np

from sylva.render.camera import box_corners, look_at

__all__ = ["ShadowMap", "light_view_projection"]


def light_view_projection(direction, casters, receivers=None) -> tuple[np.ndarray, float, float]:
    """Orthographic sun matrix that covers the caster box.

    Parameters
    ----------
    direction : array_like of 3 float
        Where the sun's rays travel.
    casters : float[2, 3]
        Bounding box of what casts shadows.
    receivers : float[2, 3], optional
        Bounding box of what receives them (widens the depth range only).

    Returns
    -------
    matrix : float64[4, 4]
        World → light clip space.
    texel_world : float
        World size of one map texel per unit of map resolution (divide by the resolution).
    depth_range : float
        World length the map's depth range spans.
    """
    d = np.asarray(direction, np.float64)
    d = d / np.linalg.norm(d)
    b = np.asarray(casters, np.float64)
    center = 0.5 * (b[0] + b[1])
    radius = max(0.5 * float(np.linalg.norm(b[1] - b[0])), 1e-6)
    up = np.array([0.0, 1.0, 0.0]) if abs(d[1]) < 0.99 else np.array([0.0, 0.0, 1.0])
    view = look_at(center - d * 2.0 * radius, center, up)
    pts = box_corners(b)
    if receivers is not None:
        pts = np.concatenate([pts, box_corners(receivers)])
    eye_pts = np.c_[box_corners(b), np.ones(8)] @ view.T
    all_pts = np.c_[pts, np.ones(len(pts))] @ view.T
    pad = 0.02 * radius
    x0, x1 = eye_pts[:, 0].min() - pad, eye_pts[:, 0].max() + pad
    y0, y1 = eye_pts[:, 1].min() - pad, eye_pts[:, 1].max() + pad
    near = -all_pts[:, 2].max() - pad
    far = -all_pts[:, 2].min() + pad
    proj = np.zeros((4, 4))
    proj[0, 0], proj[0, 3] = 2 / (x1 - x0), -(x1 + x0) / (x1 - x0)
    proj[1, 1], proj[1, 3] = 2 / (y1 - y0), -(y1 + y0) / (y1 - y0)
    proj[2, 2], proj[2, 3] = -2 / (far - near), -(far + near) / (far - near)
    proj[3, 3] = 1.0
    return proj @ view, float(max(x1 - x0, y1 - y0)), float(far - near)


class ShadowMap:
    """A depth texture rendered from the sun, reusable while the sun and the scene stay put.

    Parameters
    ----------
    ctx : moderngl.Context
    size : int
        Resolution of the square map.
    """

    def __init__(self, ctx: moderngl.Context, size: int) -> None:
        self.ctx = ctx
        self.size = int(size)
        self.texture = ctx.depth_texture((self.size, self.size))
        self.texture.compare_func = "<="
        self.texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
        self.texture.repeat_x = self.texture.repeat_y = False
        self.fbo = ctx.framebuffer(depth_attachment=self.texture)
        self.matrix = np.eye(4)
        self.texel = 1.0 / self.size
        self.bias = 0.0
        self.key: object = None  # what the map was drawn for (set by the renderer's cache)

    def update(self, gpu_scene, direction, receivers, depth_program: moderngl.Program) -> None:
        """Draw ``gpu_scene`` into the map for a sun travelling along ``direction``."""
        matrix, width, depth_range = light_view_projection(direction, gpu_scene.bounds, receivers)
        self.matrix = matrix
        # 1.5 texels of world size, expressed in [0, 1] depth units.
        self.bias = 1.5 * width / self.size / max(depth_range, 1e-12)
        ctx = self.ctx
        self.fbo.use()
        self.fbo.clear(depth=1.0)
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.disable(moderngl.CULL_FACE)
        depth_program["u_light_view_proj"].write(matrix.T.astype("f4").tobytes())
        if gpu_scene.depth_vao is not None:
            gpu_scene.depth_vao.render(moderngl.TRIANGLES)

    def release(self) -> None:
        self.fbo.release()
        self.texture.release()
