"""Renderer.update: an edited prepared scene renders as the edited scene prepared from scratch."""

import math

import numpy
import pytest

import penumbra

BOX = numpy.array([[x, y, z] for z in (-0.5, 0.5) for y in (-0.5, 0.5) for x in (-0.5, 0.5)], dtype=numpy.float32)
BOX_FACES = numpy.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                         [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]], dtype=numpy.uint32)
PLACES = [penumbra.Matrix3x4.translate((-1.2, 0.5, 0)), penumbra.Matrix3x4.translate((1.2, 0.5, 0))]
CAMERA = penumbra.Camera(eye=(0, 2.5, 5), look_at=(0, 0.4, 0), vfov_degrees=45)


def build(places=PLACES, red=(0.8, 0.1, 0.1), point=(6, 6, 6)):
    scene = penumbra.Scene()
    floor = scene.add_material(kd=0.6)
    paint = scene.add_material(kd=red, ks=0.2, exponent=20.0)
    scene.add_plane((0, 0, 0), (0, 1, 0), floor)
    scene.add_point_light((1, 4, 3), point)
    box = scene.add_prototype("box")
    scene.add_prototype_mesh(box, BOX, BOX_FACES, paint)
    indices = [scene.add_instance(box, m) for m in places]
    assert indices == list(range(len(places)))
    return scene


def render(renderer, prepared):
    return numpy.asarray(renderer.render(prepared, CAMERA, width=32, height=24, spp=2, seed=3))


@pytest.mark.parametrize("accelerator", ["embree", "naive"])
def test_edits_match_a_fresh_prepare(renderer, accelerator):
    moved = [PLACES[0], penumbra.Matrix3x4.translate((0.5, 1.0, 1.0)) @ penumbra.Matrix3x4.rotate(30, (0, 1, 0))]
    base = renderer.prepare(build(), accelerator=accelerator)
    before = render(renderer, base)
    edited = renderer.update(base, transforms={1: moved[1]},
                             materials={1: penumbra.Material(kd=(0.1, 0.2, 0.9), ks=0.2, exponent=20.0)},
                             point_lights={0: (3, 9, 3)})
    fresh = renderer.prepare(build(moved, red=(0.1, 0.2, 0.9), point=(3, 9, 3)), accelerator=accelerator)
    image = render(renderer, edited)
    assert not numpy.array_equal(image, before)
    assert numpy.array_equal(image, render(renderer, fresh))
    assert numpy.array_equal(render(renderer, base), before)  # the old one is unchanged


def test_bad_edits_are_errors(renderer):
    base = renderer.prepare(build())
    with pytest.raises(penumbra.Error, match="instance 5"):
        renderer.update(base, transforms={5: PLACES[0]})
    with pytest.raises(penumbra.Error, match="finite and invertible"):
        renderer.update(base, transforms={0: penumbra.Matrix3x4.scale(0.0)})
    with pytest.raises(penumbra.Error, match="point light 0"):
        renderer.update(base, point_lights={0: (math.nan, 1, 1)})
    with pytest.raises(penumbra.Error, match="no environment"):
        renderer.update(base, environment_rotation=30)
    assert render(renderer, base).any()
