"""Shapes and dtypes of what the module returns, its value types, and errors on bad input."""

import copy
import json

import numpy
import pytest

import penumbra
from conftest import small_scene


def test_render_returns_float32_image(renderer):
    image = renderer.render(small_scene(), width=40, height=30, spp=2)
    assert isinstance(image, numpy.ndarray) and isinstance(image, penumbra.Image)
    assert image.dtype == numpy.float32 and image.shape == (30, 40, 3)
    assert image.flags.c_contiguous
    assert isinstance(image.framebuffer, penumbra.Framebuffer) and image.framebuffer.sample_count == 2
    assert image.stats.samples_per_pixel == 2 and image.stats.camera_rays == 40 * 30 * 2
    assert numpy.all(numpy.isfinite(image)) and image.max() > 0
    # Arithmetic gives plain numbers that forget the framebuffer.
    assert (image * 2).framebuffer is None


def test_aovs_add_seven_channels(renderer):
    image = renderer.render(small_scene(), width=16, height=12, spp=1, aovs=True)
    assert image.shape == (12, 16, 10) and image.dtype == numpy.float32
    fb = image.framebuffer
    assert fb.has_aovs and fb.shape == (12, 16, 10)
    numpy.testing.assert_array_equal(image[..., 3:6], fb.albedo())
    numpy.testing.assert_array_equal(image[..., 6:9], fb.normals())
    numpy.testing.assert_array_equal(image[..., 9], fb.depth())
    assert fb.depth().shape == (12, 16) and fb.rgba().shape == (12, 16, 4)
    numpy.testing.assert_array_equal(fb.rgba()[..., 3], 1.0)
    # Unit normals where something was hit, depth positive there.
    hit = fb.depth() > 0
    assert hit.any()
    numpy.testing.assert_allclose(numpy.linalg.norm(fb.normals()[hit], axis=-1), 1.0, rtol=1e-4)


def test_framebuffer_readouts_agree(renderer):
    image = renderer.render(small_scene(), width=8, height=6, spp=1)
    fb = image.framebuffer
    assert (fb.width, fb.height, fb.full_width, fb.full_height, fb.window) == (8, 6, 8, 6, (0, 0, 8, 6))
    numpy.testing.assert_array_equal(numpy.asarray(fb), image)
    numpy.testing.assert_array_equal(fb.rgb(), image)
    assert fb.pixel(3, 2) == tuple(float(v) for v in image[2, 3])
    copied = fb.copy()
    fb.clear()
    assert fb.sample_count == 0 and copied.sample_count == 1
    numpy.testing.assert_array_equal(copied.array(), image)


def test_crop_window_is_a_slice_of_the_full_frame(renderer, cornell):
    full = renderer.render(cornell, width=48, height=32, spp=2)
    crop = renderer.render(cornell, width=48, height=32, spp=2, crop=(8, 4, 40, 20))
    assert crop.shape == (16, 32, 3)
    numpy.testing.assert_array_equal(crop, full[4:20, 8:40])


def test_settings_and_camera_values():
    s = penumbra.RenderSettings(width=64, spp=3, light_selection="power", crop=(0, 0, 8, 8), seed=2**64 - 1)
    assert (s.width, s.height, s.spp, s.seed, s.crop) == (64, 512, 3, 2**64 - 1, (0, 0, 8, 8))
    assert s.light_selection == penumbra.LightSelection.Power
    assert s.direct_light == penumbra.DirectLightSampling.Mis
    assert s.replace(direct_light="light").direct_light == penumbra.DirectLightSampling.Light
    t = s.replace(height=10, crop=None)
    assert t.height == 10 and t.crop == (0, 0, 8, 8) and s.height == 512
    c = penumbra.Camera(eye=numpy.array([1, 2, 3]), look_at=[0, 0, 0])
    assert c.eye == (1.0, 2.0, 3.0) and c.up == (0.0, 1.0, 0.0)
    m = penumbra.Material(kd=0.5, ke=(1, 2, 3))
    assert m.kd == (0.5, 0.5, 0.5) and m.ke == (1.0, 2.0, 3.0) and m.model == penumbra.PhongModel.Normalized
    r = penumbra.Matrix3x4.translate((1, 2, 3)) @ penumbra.Matrix3x4.scale(2)
    numpy.testing.assert_array_equal(numpy.asarray(r), [[2, 0, 0, 1], [0, 2, 0, 2], [0, 0, 2, 3]])
    numpy.testing.assert_array_equal(penumbra.Matrix3x4(numpy.eye(4)).m, numpy.eye(4)[:3])


def test_scene_building_counts():
    scene = small_scene()
    box = scene.add_material(penumbra.Material(kd=(0.1, 0.6, 0.1)))
    scene.add_box((-0.3, 0, -0.3), (0.3, 0.6, 0.3), box, transform=penumbra.Matrix3x4.rotate(30, (0, 1, 0)))
    scene.add_rectangle((-0.5, 2.5, -0.5), (1, 0, 0), (0, 0, 1), box)
    scene.add_disk((0, 3, 0), (0, -1, 0), 0.2, box)
    positions = numpy.random.default_rng(1).random((100, 3), dtype=numpy.float32)
    scene.add_mesh(positions.ravel(), numpy.arange(99, dtype=numpy.uint32), box)  # flat arrays: 33 triangles
    assert scene.material_count == 3 and scene.triangle_count == 33
    other = copy.copy(scene)
    other.add_sphere((0, 0, 0), 1.0)
    assert other.primitive_count == scene.primitive_count + 1


def error_of(call):
    with pytest.raises(penumbra.Error) as info:
        call()
    assert isinstance(info.value, RuntimeError)
    return info.value


def test_missing_file_is_file_not_found(renderer, tmp_path):
    path = tmp_path / "missing.obj"
    e = error_of(lambda: renderer.load_scene(path))
    assert e.code == penumbra.ErrorCode.FileNotFound and str(path) in str(e)


def test_bad_scene_file_names_the_json_path(renderer, tmp_path):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": -1}]}))
    e = error_of(lambda: renderer.load_scene(path))
    assert e.code in (penumbra.ErrorCode.ParseError, penumbra.ErrorCode.InvalidScene)
    assert "bad.json" in str(e) and "/shapes/0/radius" in str(e)


def test_bad_settings_are_invalid_argument(renderer, cornell):
    e = error_of(lambda: renderer.render(cornell, width=16, height=16, spp=0))
    assert e.code == penumbra.ErrorCode.InvalidArgument and "spp" in str(e)
    e = error_of(lambda: renderer.render(cornell, width=-4, height=16))
    assert e.code == penumbra.ErrorCode.InvalidArgument and "width" in str(e)
    e = error_of(lambda: penumbra.RenderSettings(seed=-1))
    assert "seed" in str(e)
    with pytest.raises(TypeError, match="spp_per_pixel"):
        renderer.render(cornell, spp_per_pixel=4)
    with pytest.raises(TypeError):
        renderer.render(cornell, width="wide")


def test_bad_scene_content(renderer, tmp_path):
    scene = penumbra.Scene()
    e = error_of(lambda: scene.add_sphere((0, 0, 0), 1.0, 7))
    assert e.code == penumbra.ErrorCode.InvalidArgument
    e = error_of(lambda: scene.add_mesh(numpy.zeros((3, 3)), [[0, 1, 3]]))
    assert e.code == penumbra.ErrorCode.InvalidArgument
    e = error_of(lambda: scene.add_mesh(numpy.zeros((3, 3)), [[0, 1, -1]]))
    assert "indices" in str(e)
    e = error_of(lambda: scene.add_mesh(numpy.zeros((4, 2)), [[0, 1, 2]]))
    assert "positions" in str(e)
    with pytest.raises(TypeError):
        scene.add_mesh(numpy.zeros((3, 3)), numpy.array([[0, 1, 2.5]]))
    with pytest.raises(TypeError):
        scene.add_sphere((0, 0), 1.0)
    e = error_of(lambda: renderer.render(small_scene(), width=8, height=8, spp=1, camera=None,
                                         settings=None, threads=1, seed=1, tile_size=0))
    assert "tile" in str(e).lower()


def test_write_errors(renderer, tmp_path):
    fb = renderer.render(small_scene(), width=8, height=8, spp=1).framebuffer
    e = error_of(lambda: fb.write(tmp_path / "image.bmpx"))
    assert "image.bmpx" in str(e)
    e = error_of(lambda: fb.write(tmp_path / "no" / "such" / "folder" / "a.exr"))
    assert e.code in (penumbra.ErrorCode.IoError, penumbra.ErrorCode.InvalidArgument)
    fb.write(tmp_path / "ok.exr")
    assert (tmp_path / "ok.exr").stat().st_size > 0


def test_log_callback_receives_warnings(tmp_path):
    messages = []
    renderer = penumbra.Renderer(log=lambda level, text: messages.append((level, text)))
    path = tmp_path / "faces.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n")
    scene = renderer.load_scene(path)
    assert scene.triangle_count == 1
    assert messages and messages[0][0] == penumbra.LogLevel.Warning and "faces.obj" in messages[0][1]
    with pytest.raises(penumbra.Error):
        renderer.load_scene(path, strict=True)


def test_instances_render_like_copies_and_refuse_bad_input(renderer):
    quad = numpy.array([[-0.5, 0, -0.5], [0.5, 0, -0.5], [0.5, 0, 0.5], [-0.5, 0, 0.5]], dtype=numpy.float32)
    tris = numpy.array([[0, 2, 1], [0, 3, 2]], dtype=numpy.uint32)  # facing +y
    moves = [(-0.9, 0.3, 0.0), (0.9, 0.5, 0.2), (0.0, 1.3, -0.4)]
    copied = small_scene()
    green = copied.add_material(kd=(0.1, 0.6, 0.1))
    for m in moves:
        copied.add_mesh(quad + numpy.array(m, dtype=numpy.float32), tris, green)
    instanced = small_scene()
    green = instanced.add_material(kd=(0.1, 0.6, 0.1))
    proto = instanced.add_prototype("quad")
    instanced.add_prototype_mesh(proto, quad, tris, green)
    for m in moves:
        instanced.add_instance(proto, penumbra.Matrix3x4.translate(m))
    assert instanced.prototype_count == 1 and instanced.instance_count == 3
    assert instanced.triangle_count == copied.triangle_count
    a = renderer.render(copied, width=40, height=30, spp=2)
    b = renderer.render(instanced, width=40, height=30, spp=2)
    # Translations only: object-space and world-space tests round alike here but for the last bits.
    numpy.testing.assert_allclose(a, b, rtol=1e-3, atol=1e-4)
    assert numpy.abs(a - renderer.render(small_scene(), width=40, height=30, spp=2)).max() > 0.05  # quads show

    e = error_of(lambda: instanced.add_instance(5))
    assert e.code == penumbra.ErrorCode.InvalidArgument and "prototype id 5" in str(e)
    e = error_of(lambda: instanced.add_instance(proto, penumbra.Matrix3x4.scale((1, 0, 1))))
    assert "singular" in str(e)
    e = error_of(lambda: instanced.add_instance(proto, material=42))
    assert "material id 42" in str(e)
    e = error_of(lambda: instanced.add_prototype_mesh(proto, numpy.zeros((3, 3)), [[0, 1, 3]]))
    assert e.code == penumbra.ErrorCode.InvalidArgument
    e = error_of(lambda: instanced.add_prototype_mesh(proto, numpy.zeros((4, 2)), [[0, 1, 2]]))
    assert "add_prototype_mesh: positions" in str(e)


def test_load_scene_reads_models_with_a_model_and_smoothing(tmp_path):
    # An ASCII PLY quad without normals: read through Assimp, smoothed (flat: its face normal), and
    # its materials take the Phong model asked for.
    path = tmp_path / "quad.ply"
    path.write_text("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                    "-1 -1 0\n1 -1 0\n1 1 0\n-1 1 0\n4 0 1 2 3\n")
    renderer = penumbra.Renderer()
    scene = renderer.load_scene(path, model=penumbra.PhongModel.Classic, smooth_angle=0)
    assert scene.triangle_count == 2

    # Both options take effect: a pyramid without normals, lit by a point light, shades
    # differently with each model, and has other normals (AOV channels 6-8) smoothed than faceted.
    pyramid = tmp_path / "pyramid.ply"
    pyramid.write_text("ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
                       "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n"
                       "-1 -1 0\n1 -1 0\n1 1 0\n-1 1 0\n0 0 1.2\n3 0 1 4\n3 1 2 4\n3 2 3 4\n3 3 0 4\n")

    def image(**options):
        s = renderer.load_scene(pyramid, **options)
        s.add_point_light((1, 2, 4), (20, 20, 20))
        camera = penumbra.Camera(eye=(0, 0, 4), look_at=(0, 0, 0))
        return renderer.render(s, camera, width=24, height=24, spp=2, aovs=True)

    classic = image(model=penumbra.PhongModel.Classic, smooth_angle=0)
    normalized = image(model=penumbra.PhongModel.Normalized, smooth_angle=0)
    smoothed = image(model=penumbra.PhongModel.Classic, smooth_angle=90)
    assert not numpy.array_equal(classic[..., :3], normalized[..., :3])
    assert numpy.array_equal(classic[..., 6:9], normalized[..., 6:9])
    assert not numpy.array_equal(classic[..., 6:9], smoothed[..., 6:9])
    with pytest.raises(penumbra.Error, match="smooth angle"):
        renderer.load_scene(pyramid, smooth_angle=200)
    with pytest.raises(penumbra.Error, match="quad.xyz"):
        renderer.load_scene(tmp_path / "quad.xyz")
