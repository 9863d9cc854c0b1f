"""penumbra.Image: what Renderer.render returns, a float32 numpy array that shows itself in Jupyter."""

import os
import tempfile

import numpy


def png_bytes(framebuffer, exposure=0.0):
    """PNG bytes of a Framebuffer, written by the library itself (exposure, sRGB, clamp: as the CLI's PNGs)."""
    with tempfile.TemporaryDirectory(prefix="penumbra-") as folder:
        path = os.path.join(folder, "image.png")
        framebuffer.write(path, exposure=exposure)
        with open(path, "rb") as f:
            return f.read()


class Image(numpy.ndarray):
    """A rendered image: float32 (H, W, 3) linear radiance, or (H, W, 10) with AOVs
    (R G B, albedo R G B, normal X Y Z, depth), row 0 on top.

    It is a plain numpy array besides three attributes: `framebuffer` (the Framebuffer it was
    read from: write it with image.framebuffer.write("out.exr")), `stats` (RenderStats) and
    `exposure` (stops, for the Jupyter preview). Arrays computed from it are plain numbers
    again: they forget the framebuffer, and Jupyter shows them as arrays.
    """

    def __array_finalize__(self, obj):
        self.framebuffer = None
        self.stats = None
        self.exposure = 0.0

    @classmethod
    def _wrap(cls, array, framebuffer, stats):
        image = array.view(cls)
        image.framebuffer = framebuffer
        image.stats = stats
        return image

    def write(self, path, exposure=None, aovs=False):
        """Writes the framebuffer this image came from (see Framebuffer.write)."""
        if self.framebuffer is None:
            raise ValueError("this array was not read from a framebuffer; nothing to write")
        self.framebuffer.write(path, exposure=self.exposure if exposure is None else exposure, aovs=aovs)

    def to_png(self, exposure=None):
        """PNG bytes of the framebuffer, tone-mapped like the CLI's PNG output."""
        if self.framebuffer is None:
            raise ValueError("this array was not read from a framebuffer")
        return png_bytes(self.framebuffer, self.exposure if exposure is None else exposure)

    def _repr_png_(self):
        if self.framebuffer is None or self.framebuffer.incomplete:
            return None
        return self.to_png()
