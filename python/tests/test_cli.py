"""The module's images equal the CLI's, bit for bit, for the same scene and settings."""

import subprocess

import numpy
import pytest

import penumbra
from conftest import SOURCE_DIR, read_pfm

CASES = [
    # scene, CLI options, the same as keywords
    ("assets/cornell/cornell.obj", ["--width", "40", "--height", "30", "--spp", "4", "--seed", "7"],
     dict(width=40, height=30, spp=4, seed=7)),
    ("assets/scenes/lecture_area_light.json", ["--width", "36", "--height", "24", "--spp", "2", "--light-samples", "2"],
     dict(width=36, height=24, spp=2, light_samples=2)),
    ("assets/scenes/lecture_whitted.json", ["--width", "30", "--height", "20", "--spp", "2", "--max-depth", "3",
                                            "--light-selection", "power"],
     dict(width=30, height=20, spp=2, max_depth=3, light_selection="power")),
]


def run_cli(cli, scene, out, options):
    subprocess.run([cli, str(SOURCE_DIR / scene), "-o", str(out), "-q", *options], check=True)


def read_exr(path):
    oiio = pytest.importorskip("OpenImageIO")
    image = oiio.ImageInput.open(str(path))
    try:
        pixels = image.read_image(oiio.FLOAT)
        names = list(image.spec().channelnames)
    finally:
        image.close()
    return pixels, names


@pytest.mark.parametrize("scene,options,keywords", [CASES[0], CASES[2]], ids=["obj", "whitted"])
def test_equals_cli_pfm(renderer, cli, tmp_path, scene, options, keywords):
    run_cli(cli, scene, tmp_path / "cli.pfm", options)
    image = renderer.render(renderer.load_scene(SOURCE_DIR / scene), **keywords)
    numpy.testing.assert_array_equal(image, read_pfm(tmp_path / "cli.pfm"))


def test_equals_cli_exr_with_aovs(renderer, cli, tmp_path):
    scene, options, keywords = CASES[0]
    run_cli(cli, scene, tmp_path / "cli.exr", options + ["--aovs"])
    pixels, names = read_exr(tmp_path / "cli.exr")
    image = renderer.render(renderer.load_scene(SOURCE_DIR / scene), aovs=True, **keywords)
    # The module's channel order: R G B, albedo, normal, depth (the EXR stores them by name).
    order = ["R", "G", "B", "albedo.R", "albedo.G", "albedo.B", "N.X", "N.Y", "N.Z", "Z"]
    numpy.testing.assert_array_equal(image, pixels[..., [names.index(n) for n in order]])


def test_written_exr_equals_cli(renderer, cli, tmp_path):
    scene, options, keywords = CASES[1]
    run_cli(cli, scene, tmp_path / "cli.exr", options)
    image = renderer.render(renderer.load_scene(SOURCE_DIR / scene), **keywords)
    image.write(tmp_path / "module.exr")
    numpy.testing.assert_array_equal(read_exr(tmp_path / "module.exr")[0], read_exr(tmp_path / "cli.exr")[0])
    numpy.testing.assert_array_equal(image, read_exr(tmp_path / "cli.exr")[0])


def test_png_preview_is_the_cli_png(renderer, cli, tmp_path):
    oiio = pytest.importorskip("OpenImageIO")
    scene, options, keywords = CASES[0]
    run_cli(cli, scene, tmp_path / "cli.png", options + ["--exposure", "1.5"])
    image = renderer.render(renderer.load_scene(SOURCE_DIR / scene), **keywords)
    image.exposure = 1.5
    png = image._repr_png_()
    assert png.startswith(b"\x89PNG\r\n\x1a\n")
    (tmp_path / "preview.png").write_bytes(png)
    a = oiio.ImageBuf(str(tmp_path / "preview.png")).get_pixels(oiio.UINT8)
    b = oiio.ImageBuf(str(tmp_path / "cli.png")).get_pixels(oiio.UINT8)
    assert a.shape == (30, 40, 3)
    numpy.testing.assert_array_equal(a, b)
    assert image.framebuffer._repr_png_().startswith(b"\x89PNG")
    assert (image + 0)._repr_png_() is None  # a computed array has no framebuffer to show
