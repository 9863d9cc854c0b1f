"""Progressive passes, progress callbacks and asynchronous jobs."""

import threading

import numpy
import pytest

import penumbra

SETTINGS = penumbra.RenderSettings(width=32, height=24, spp=8, seed=3)


def test_passes_give_the_one_shot_image(renderer, cornell):
    once = renderer.render(cornell, settings=SETTINGS)
    fb = penumbra.Framebuffer(SETTINGS)
    for first in range(0, 8, 3):
        stats = renderer.render_pass(cornell, fb, first, min(3, 8 - first), settings=SETTINGS)
        assert fb.sample_count == stats.samples_per_pixel == min(first + 3, 8)
    numpy.testing.assert_array_equal(fb.array(), once)
    # The framebuffer's own size is the default; render(framebuffer=) adds what it lacks.
    fb2 = penumbra.Framebuffer(SETTINGS)
    renderer.render_pass(cornell, fb2, 0, 2, spp=8, seed=3)
    finished = renderer.render(cornell, framebuffer=fb2, spp=8, seed=3)
    numpy.testing.assert_array_equal(finished, once)


def test_pass_must_start_at_the_framebuffer_sample_count(renderer, cornell):
    fb = penumbra.Framebuffer(SETTINGS)
    with pytest.raises(penumbra.Error) as info:
        renderer.render_pass(cornell, fb, 2, 2, settings=SETTINGS)
    assert info.value.code == penumbra.ErrorCode.InvalidArgument


def test_progress_on_the_calling_thread(renderer, cornell):
    seen = []
    renderer.render(cornell, width=64, height=48, spp=4,
                    progress=lambda f: seen.append((f, threading.get_ident())))
    fractions = [f for f, _ in seen]
    assert fractions[-1] == 1.0 and all(0.0 <= f <= 1.0 for f in fractions)
    assert fractions == sorted(fractions)
    assert {t for _, t in seen} == {threading.get_ident()}


def test_progress_exception_stops_the_render(renderer, cornell):
    def fail(fraction):
        raise ValueError("stop here")

    with pytest.raises(ValueError, match="stop here"):
        renderer.render(cornell, width=256, height=256, spp=256, progress=fail)


def test_async_job_equals_render_and_calls_back(renderer, cornell):
    once = renderer.render(cornell, settings=SETTINGS)
    passes, completions, progress = [], [], []
    job = renderer.render_async(
        cornell, settings=SETTINGS, pass_samples=3,
        progress=progress.append,
        on_pass=lambda fb, done: passes.append((done, fb.sample_count, fb.array().shape)),
        on_complete=completions.append)
    image = job.result()
    assert job.done and job.status == penumbra.JobStatus.Finished and job.error is None
    numpy.testing.assert_array_equal(image, once)
    assert isinstance(image, penumbra.Image) and image.framebuffer.sample_count == 8
    assert passes == [(3, 3, (24, 32, 3)), (6, 6, (24, 32, 3)), (8, 8, (24, 32, 3))]
    assert len(completions) == 1 and completions[0].status == penumbra.JobStatus.Finished
    numpy.testing.assert_array_equal(completions[0].image, once)
    assert progress and max(progress) == pytest.approx(1.0) and job.progress == 1.0
    assert job.stats.samples_per_pixel == 8


def test_async_callback_exception_fails_the_job(renderer, cornell):
    def fail(fb, done):
        raise KeyError("on_pass broke")

    job = renderer.render_async(cornell, settings=SETTINGS, pass_samples=2, on_pass=fail)
    job.wait()
    assert job.status == penumbra.JobStatus.Failed
    assert job.error.code == penumbra.ErrorCode.Internal and "on_pass broke" in str(job.error)
    with pytest.raises(penumbra.Error, match="on_pass broke"):
        job.result()


def test_async_bad_arguments_raise_at_once(renderer, cornell):
    with pytest.raises(penumbra.Error) as info:
        renderer.render_async(cornell, width=0)
    assert info.value.code == penumbra.ErrorCode.InvalidArgument
