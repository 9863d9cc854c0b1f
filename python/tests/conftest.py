"""Shared fixtures of the Python tests (run by ctest as `python3 -m pytest python/tests`)."""

import os
import pathlib
import shutil

import numpy
import pytest

import penumbra

SOURCE_DIR = pathlib.Path(os.environ.get("PENUMBRA_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture(scope="session")
def source_dir():
    return SOURCE_DIR


@pytest.fixture(scope="session")
def cli():
    """The penumbra command-line renderer of the same build."""
    path = os.environ.get("PENUMBRA_CLI") or shutil.which("penumbra")
    if not path:
        candidate = SOURCE_DIR / "build" / "bin" / "penumbra"
        path = str(candidate) if candidate.exists() else None
    if not path:
        pytest.skip("the penumbra CLI was not found (set PENUMBRA_CLI)")
    return path


@pytest.fixture(scope="session")
def renderer():
    return penumbra.Renderer()


@pytest.fixture(scope="session")
def cornell(renderer):
    return renderer.prepare(renderer.load_scene(SOURCE_DIR / "assets" / "cornell" / "cornell.obj"))


def small_scene():
    """A sphere on a plane under a point light: quick to prepare and render."""
    scene = penumbra.Scene()
    red = scene.add_material(kd=(0.7, 0.2, 0.1), ks=0.2, exponent=30.0)
    grey = scene.add_material(kd=0.6)
    scene.add_plane((0, 0, 0), (0, 1, 0), grey)
    scene.add_sphere((0, 0.6, 0), 0.6, red)
    scene.add_point_light((2, 3, 3), 15.0)
    scene.camera = penumbra.Camera(eye=(0, 1.4, 4.5), look_at=(0, 0.6, 0))
    return scene


def read_pfm(path):
    """A PFM file as a float32 (H, W, 3) array, row 0 on top (PFM stores the bottom row first)."""
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        width, height = (int(v) for v in f.readline().split())
        scale = float(f.readline())
        data = numpy.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(height, width, 3)[::-1].astype(numpy.float32)
