"""The environment light and the default light of unlit scenes, from Python."""

import numpy
import pytest

import penumbra


def floor_scene():
    """A grey floor (kd 0.5), nothing else."""
    scene = penumbra.Scene()
    grey = scene.add_material(kd=0.5)
    scene.add_plane((0, 0, 0), (0, 1, 0), grey)
    return scene


TOP = penumbra.Camera(eye=(0, 2, 0), look_at=(0, 0, 0), up=(0, 0, -1), vfov_degrees=30.0)


def test_constant_environment_lights_a_floor_with_kd_times_l():
    renderer = penumbra.Renderer()
    scene = floor_scene()
    scene.set_environment((0.2, 0.4, 0.8), scale=2.0)
    assert scene.has_environment
    prepared = renderer.prepare(scene)
    assert not prepared.default_light_added and prepared.light_count == 1
    image = renderer.render(prepared, TOP, width=8, height=8, spp=16, light_samples=16)
    numpy.testing.assert_allclose(image.mean(axis=(0, 1)), [0.2, 0.4, 0.8], rtol=0.02)


def test_unlit_scene_gets_the_default_light_unless_turned_off():
    warnings = []
    renderer = penumbra.Renderer(log=lambda level, message: warnings.append(message))
    scene = floor_scene()
    assert scene.default_light
    prepared = renderer.prepare(scene)
    assert prepared.default_light_added
    assert sum("no light" in w for w in warnings) == 1
    image = renderer.render(prepared, TOP, width=8, height=8, spp=16, light_samples=16)
    assert image.mean() == pytest.approx(0.5, rel=0.02)
    scene.default_light = False
    dark = renderer.prepare(scene)
    assert not dark.default_light_added
    assert renderer.render(dark, TOP, width=8, height=8, spp=1).max() == 0.0


def test_missing_environment_image_names_the_file(tmp_path):
    scene = floor_scene()
    with pytest.raises(penumbra.Error) as e:
        scene.set_environment_image(str(tmp_path / "absent.exr"), rotate_degrees=30.0)
    assert "absent.exr" in str(e.value)
