"""Penumbra, an Embree-accelerated offline renderer, from Python.

    import penumbra
    renderer = penumbra.Renderer()
    scene = renderer.load_scene("assets/cornell/cornell.obj")
    image = renderer.render(scene, width=320, height=240, spp=16)   # float32 (240, 320, 3)
    image.framebuffer.write("cornell.exr")

See docs/python.md. Everything here binds the C++ API (<penumbra/penumbra.hpp>).
"""

from ._penumbra import (
    BuildQuality,
    Camera,
    Error,
    ErrorCode,
    Framebuffer,
    JobStatus,
    LightSelection,
    LogLevel,
    Material,
    Matrix3x4,
    PhongModel,
    PreparedScene,
    RenderJob,
    Renderer,
    RenderSettings,
    RenderStats,
    Scene,
    version,
)
from ._image import Image, png_bytes

__version__ = version()

__all__ = [
    "BuildQuality", "Camera", "Error", "ErrorCode", "Framebuffer", "Image", "JobStatus", "LightSelection",
    "LogLevel", "Material", "Matrix3x4", "PhongModel", "PreparedScene", "RenderJob", "Renderer",
    "RenderSettings", "RenderStats", "Scene", "png_bytes", "version",
]


def _framebuffer_to_png(self, exposure=0.0):
    """The image as PNG bytes, tone-mapped as the CLI writes PNGs (exposure in stops, sRGB, clamped)."""
    return png_bytes(self, exposure)


def _framebuffer_repr_png(self):
    return png_bytes(self, 0.0) if self.width > 0 and not self.incomplete else None


Framebuffer.to_png = _framebuffer_to_png
Framebuffer._repr_png_ = _framebuffer_repr_png
