#!/usr/bin/env python3
"""Penumbra from Python: load an OBJ scene, render it, look at the numbers, save an EXR.

    PYTHONPATH=build/python python3 apps/examples/python_example.py [out.exr]

CTest runs it (test Python.example). With matplotlib installed it also saves a preview
next to the EXR (out.preview.png) through matplotlib; without it, it says so and goes on.
"""

import pathlib
import sys

import numpy

import penumbra

HERE = pathlib.Path(__file__).resolve().parent
SCENE = HERE.parent.parent / "assets" / "cornell" / "cornell.obj"


def main(out):
    renderer = penumbra.Renderer()

    # 1. A scene file: the OBJ has no camera, so render() frames it as the CLI does.
    scene = renderer.prepare(renderer.load_scene(SCENE))
    print(f"{SCENE.name}: {scene.triangle_count} triangles, {scene.light_count} lights")
    image = renderer.render(scene, width=160, height=120, spp=8,
                            progress=lambda f: print(f"\r{f:4.0%}", end="", flush=True))
    print(f"\rrendered {image.shape} {image.dtype}; mean radiance {image.mean(axis=(0, 1))}")
    image.write(out)  # linear float EXR, like `penumbra ... -o out.exr`
    print(f"wrote {out}")

    # 2. A scene built in code, with a mesh from numpy arrays (no per-vertex Python loop).
    built = penumbra.Scene()
    red = built.add_material(kd=(0.7, 0.15, 0.1), ks=0.2, exponent=40.0)
    lamp = built.add_material(kd=0.0, ke=8.0)
    built.add_plane((0, 0, 0), (0, 1, 0))
    angles = numpy.linspace(0.0, 2.0 * numpy.pi, 33)[:-1]
    ring = numpy.stack([numpy.cos(angles), numpy.full_like(angles, 0.8), numpy.sin(angles)], axis=1)
    positions = numpy.vstack([ring * [0.6, 1.0, 0.6], [[0.0, 0.8, 0.0]]])   # a fan: disk top
    centre = len(ring)
    indices = numpy.stack([numpy.full(32, centre), (numpy.arange(32) + 1) % 32, numpy.arange(32)], axis=1)
    built.add_mesh(positions, indices, red)
    built.add_sphere((0, 0.4, 0), 0.4, red)
    built.add_rectangle((-0.5, 2.5, -0.5), (1, 0, 0), (0, 0, 1), lamp)    # faces down
    camera = penumbra.Camera(eye=(0, 1.6, 3.5), look_at=(0, 0.5, 0))
    preview = renderer.render(built, camera, width=160, height=120, spp=8)
    assert preview.shape == (120, 160, 3) and preview.max() > 0

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed; skipping the preview")
        return
    png = pathlib.Path(out).with_suffix(".preview.png")
    # matplotlib wants display values: clamp and gamma-encode the linear radiance.
    plt.imshow(numpy.clip(image, 0.0, 1.0) ** (1 / 2.2))
    plt.axis("off")
    plt.savefig(png, bbox_inches="tight")
    print(f"wrote {png}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "python_example.exr")
