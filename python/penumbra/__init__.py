"""Penumbra, an Embree-accelerated offline renderer, from Python.

    import penumbra
    renderer = penumbra.Renderer()
    scene = renderer.load_scene("assets/cornell/cornell.obj")
    image = renderer.render(scene, width=320, height=240, spp=16)   # float32 (240, 320, 3)
    image.framebuffer.write("cornell.exr")

See docs/python.md. Everything here binds the C++ API (<penumbra/penumbra.hpp>).
"""

import atexit
import sys
import weakref

try:
    from ._penumbra import (
        BuildQuality,
        Camera,
        DirectLightSampling,
        Error,
        ErrorCode,
        Framebuffer,
        IntegratorKind,
        JobStatus,
        LightSelection,
        LogLevel,
        Material,
        MaterialKind,
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
except ImportError as error:
    # Built for another interpreter (a pyenv or conda python3 beside Debian's,
    # a venv without numpy): say which one instead of failing deep inside.
    from ._built_for import INTERPRETER, PYTHON_VERSION

    raise ImportError(
        f"penumbra was built for {INTERPRETER} (Python {PYTHON_VERSION}) and cannot be imported by "
        f"{sys.executable} (Python {sys.version.split()[0]}): {error}. Run it with {INTERPRETER}, or build it "
        f"for this interpreter (cmake -DPython3_EXECUTABLE={sys.executable}, or pip install --no-build-isolation .)"
    ) from error

__version__ = version()

__all__ = [
    "BuildQuality", "Camera", "DirectLightSampling", "Error", "ErrorCode", "Framebuffer", "Image", "IntegratorKind",
    "JobStatus", "LightSelection",
    "LogLevel", "Material", "MaterialKind", "Matrix3x4", "PhongModel", "PreparedScene", "RenderJob", "Renderer",
    "RenderSettings", "RenderStats", "Scene", "png_bytes", "version",
]


def _framebuffer_to_png(self, exposure=0.0):
    """The image as PNG bytes, tone-mapped as the CLI writes PNGs (exposure in stops, sRGB, clamped)."""
    return png_bytes(self, exposure)


def _framebuffer_repr_png(self):
    return png_bytes(self, 0.0) if self.width > 0 and not self.incomplete else None


Framebuffer.to_png = _framebuffer_to_png
Framebuffer._repr_png_ = _framebuffer_repr_png


# Running jobs are cancelled and waited for when the interpreter exits, while
# their callbacks can still take the GIL (later, during finalization, a thread
# that asks for the GIL is stopped by Python itself).
_live_jobs = weakref.WeakSet()
_render_async = Renderer.render_async


def _tracked_render_async(self, *args, **kwargs):
    job = _render_async(self, *args, **kwargs)
    _live_jobs.add(job)
    return job


_tracked_render_async.__doc__ = _render_async.__doc__
Renderer.render_async = _tracked_render_async


@atexit.register
def _stop_jobs():
    jobs = list(_live_jobs)
    for job in jobs:
        job.cancel()
    for job in jobs:
        job.wait()
