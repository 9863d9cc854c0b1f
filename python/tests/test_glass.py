"""Glass and the path integrator from Python: a clear slab at normal incidence in front of an
emitter passes (1 - R)^2 / (1 - R^2) of its radiance, R = ((n - 1) / (n + 1))^2, with both
integrators; settings and statistics name the integrator and the new ray kinds."""

import numpy
import pytest

import penumbra

CAMERA = penumbra.Camera(eye=(0, 0, 5), look_at=(0, 0, 0), up=(0, 1, 0), vfov_degrees=2)


def slab_scene():
    scene = penumbra.Scene()
    glass = scene.add_material(penumbra.Material(kd=0, kt=1, ior=1.5))
    lamp = scene.add_material(penumbra.Material(kd=0, ke=1))
    scene.add_box((-2, -2, -0.1), (2, 2, 0.1), glass)
    scene.add_rectangle((-5, -5, -3), (10, 0, 0), (0, 10, 0), lamp)
    return scene


@pytest.mark.parametrize("integrator", ["whitted", "path"])
def test_glass_slab_transmission(renderer, integrator):
    n = 1.5
    r = ((n - 1) / (n + 1)) ** 2
    expected = (1 - r) ** 2 / (1 - r * r)
    image = renderer.render(slab_scene(), CAMERA, width=8, height=8, spp=64 if integrator == "path" else 1,
                            max_depth=12, integrator=integrator)
    tolerance = 2e-4 if integrator == "whitted" else 0.02
    assert abs(float(numpy.mean(image)) - expected) < tolerance * expected
    assert image.stats.transmission_rays > 0
    assert image.stats.path_length_max >= 3  # into the slab, out, to the lamp


def test_material_and_settings_values():
    m = penumbra.Material(kt=(0.9, 0.8, 0.7), ior=1.33)
    assert m.ior == pytest.approx(1.33)
    assert tuple(m.kt) == pytest.approx((0.9, 0.8, 0.7))
    s = penumbra.RenderSettings(integrator="path")
    assert s.integrator == penumbra.IntegratorKind.Path
    assert "integrator='path'" in repr(s)
    assert penumbra.RenderSettings().integrator == penumbra.IntegratorKind.Whitted
    with pytest.raises(penumbra.Error):
        penumbra.RenderSettings(integrator="bidirectional")
