"""Offscreen rendering: cameras, lights, shadows, procedural textures, images and animations.

The public API::

    from sylva.render import Camera, render, save_image
    img = render(scene, size=(1280, 720), camera=Camera.auto(scene, yaw=40, aspect=16 / 9))
    save_image(img, "plant.png")

Every OpenGL context comes from :mod:`sylva.render.context` (headless EGL: the GPU where there
is one, Mesa llvmpipe otherwise).
"""

from sylva.render.animate import (
    Frames,
    growth_frames,
    render_frames,
    turntable_frames,
    tween,
    write_animation,
)
from sylva.render.camera import MODES, Camera
from sylva.render.context import RenderError, context_info, create_context, get_context
from sylva.render.lights import ATTENUATION, PointLight, Sun, attenuation, default_lights
from sylva.render.offscreen import Renderer, parse_color, render, render_array, save_image
from sylva.render.scene import GpuScene, Ground, Sky

__all__ = [
    "ATTENUATION",
    "Camera",
    "Frames",
    "GpuScene",
    "Ground",
    "MODES",
    "PointLight",
    "RenderError",
    "Renderer",
    "Sky",
    "Sun",
    "attenuation",
    "context_info",
    "create_context",
    "default_lights",
    "get_context",
    "growth_frames",
    "parse_color",
    "render",
    "render_array",
    "render_frames",
    "save_image",
    "turntable_frames",
    "tween",
    "write_animation",
]
