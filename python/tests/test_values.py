"""Radiance of scenes with a known answer: Lambertian surfaces (normalized Phong, ks = 0:
f = kd / pi) under directional, point and disk lights, and directly seen emitters."""

import math

import numpy
import pytest

import penumbra

ALBEDO = (0.5, 0.25, 0.8)
LOOK_DOWN = penumbra.Camera(eye=(0, 5, 0), look_at=(0, 0, 0), up=(0, 0, -1), vfov_degrees=30)


def floor_scene():
    scene = penumbra.Scene()
    floor = scene.add_material(kd=ALBEDO)
    scene.add_plane((0, 0, 0), (0, 1, 0), floor)
    return scene


@pytest.mark.parametrize("tilt", [0.0, 45.0])
def test_directional_light_on_lambertian_floor(renderer, tilt):
    scene = floor_scene()
    t = math.radians(tilt)
    scene.add_directional_light((math.sin(t), -math.cos(t), 0), (2.0, 1.0, 3.0))
    image = renderer.render(scene, LOOK_DOWN, width=24, height=16, spp=2)
    # L = kd / pi * E * cos(theta), the same for every pixel (a delta light, no noise).
    expected = numpy.array(ALBEDO) / math.pi * numpy.array([2.0, 1.0, 3.0]) * math.cos(t)
    numpy.testing.assert_allclose(image, numpy.broadcast_to(expected, image.shape), rtol=1e-5)


def test_point_light_falloff(renderer):
    height, intensity = 1.5, 10.0
    scene = floor_scene()
    scene.add_point_light((0, height, 0), intensity)
    size = 33
    image = renderer.render(scene, LOOK_DOWN, width=size, height=size, spp=16)
    # Pixel centres hit the floor at radius r from below the light: L = kd/pi * I cos(theta) / d^2,
    # cos(theta) = h / d. The pattern is radially symmetric, so image orientation does not matter.
    half = 5.0 * math.tan(math.radians(15.0))
    c = (numpy.arange(size) + 0.5) / size * 2.0 - 1.0
    x, z = numpy.meshgrid(c * half, c * half)
    d2 = x * x + z * z + height * height
    falloff = intensity * height / d2**1.5
    expected = falloff[..., None] * numpy.array(ALBEDO) / math.pi
    numpy.testing.assert_allclose(image, expected, rtol=0.01)


def test_disk_light_irradiance(renderer):
    # A one-sided disk of radiance Le and radius R, h above the floor, facing it: the irradiance
    # below its centre is E = pi Le R^2 / (h^2 + R^2), so L = kd Le R^2 / (h^2 + R^2).
    le, radius, h = 4.0, 0.5, 1.0
    scene = floor_scene()
    lamp = scene.add_material(kd=0.0, ke=le)
    scene.add_disk((0, h, 0), (0, -1, 0), radius, lamp)
    camera = penumbra.Camera(eye=(2, 1, 0), look_at=(0, 0, 0), up=(0, 1, 0), vfov_degrees=1.0)
    image = renderer.render(scene, camera, width=3, height=3, spp=64, light_samples=16)
    expected = numpy.array(ALBEDO) * le * radius**2 / (h * h + radius * radius)
    numpy.testing.assert_allclose(image[1, 1], expected, rtol=0.02)


def test_emitter_seen_directly(renderer):
    scene = penumbra.Scene()
    glow = scene.add_material(kd=0.0, ke=(1.5, 0.5, 0.25))
    scene.add_sphere((0, 0, 0), 1.0, glow)
    scene.set_background((0.1, 0.2, 0.3))
    camera = penumbra.Camera(eye=(0, 0, 5), look_at=(0, 0, 0))
    image = renderer.render(scene, camera, width=32, height=32, spp=1)
    numpy.testing.assert_array_equal(image[16, 16], numpy.float32([1.5, 0.5, 0.25]))
    numpy.testing.assert_array_equal(image[0, 0], numpy.float32([0.1, 0.2, 0.3]))


def test_mesh_from_numpy_matches_analytic_value(renderer):
    # A floor of two halves (x < 0 and x > 0), two triangles each, with per-face materials
    # and int64 indices: every pixel shows one of the two kd / pi * E.
    scene = penumbra.Scene()
    left = scene.add_material(kd=(0.2, 0.4, 0.6))
    right = scene.add_material(kd=(0.6, 0.4, 0.2))
    positions = numpy.array(
        [[-3, 0, -3], [0, 0, -3], [0, 0, 3], [-3, 0, 3], [3, 0, -3], [3, 0, 3]], dtype=numpy.float64)
    indices = numpy.array([[0, 3, 2], [0, 2, 1], [1, 2, 5], [1, 5, 4]], dtype=numpy.int64)
    scene.add_mesh(positions, indices, face_materials=numpy.array([left, left, right, right]))
    scene.add_directional_light((0, -1, 0), 1.0)
    assert scene.triangle_count == 4
    image = renderer.render(scene, LOOK_DOWN, width=20, height=10, spp=1)
    a = numpy.array([0.2, 0.4, 0.6]) / math.pi
    b = numpy.array([0.6, 0.4, 0.2]) / math.pi
    pixels = image.reshape(-1, 3)
    is_a = numpy.all(numpy.isclose(pixels, a, rtol=1e-5), axis=1)
    is_b = numpy.all(numpy.isclose(pixels, b, rtol=1e-5), axis=1)
    assert numpy.all(is_a | is_b)
    # Half of the columns each (the camera's x runs along the world's x).
    assert is_a.sum() == is_b.sum() == pixels.shape[0] // 2


def test_metal_roughness_material_from_keywords_renders_its_base_colour():
    mat = penumbra.Material(kind=penumbra.MaterialKind.MetalRoughness, base_color=(0.9, 0.1, 0.1), metallic=0.0,
                            roughness=0.6)
    assert mat.kind == penumbra.MaterialKind.MetalRoughness
    assert mat.metallic == 0.0 and mat.roughness == pytest.approx(0.6)
    assert mat.base_color_texture == "" and mat.normal_scale == 1.0
    renderer = penumbra.Renderer()
    scene = penumbra.Scene()
    scene.add_plane((0, 0, 0), (0, 1, 0), scene.add_material(mat))
    scene.set_environment((1, 1, 1))
    top = penumbra.Camera(eye=(0, 2, 0), look_at=(0, 0, 0), up=(0, 0, -1), vfov_degrees=30.0)
    image = renderer.render(renderer.prepare(scene), top, width=8, height=8, spp=16, light_samples=4)
    red, green = image[..., 0].mean(), image[..., 1].mean()
    # A red plastic under a white sky: the diffuse base's red, and the 4% specular in every channel.
    assert red > 0.6 and 0.02 < green < 0.2
