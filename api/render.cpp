// Rendering through the API: whole images, progressive passes, and
// asynchronous jobs (pnb::RenderJob).
#include "api/api_internal.h"

#include <algorithm>

namespace pnb {

namespace {

std::string windowText(int width, int height, const CropWindow& w) {
    return std::to_string(width) + "x" + std::to_string(height) + ", window " + std::to_string(w.x0) + "," +
           std::to_string(w.y0) + "," + std::to_string(w.x1) + "," + std::to_string(w.y1);
}

// The one gate of a render call: the scene handle, camera and settings.
const PreparedImpl& checkRender(const PreparedScene& scene, const Camera& camera, const RenderSettings& s) {
    const PreparedImpl& p = requirePrepared(scene);
    pn::validateSettings(s);
    pn::validateCamera(camera);
    return p;
}

// The pass [first, first + count) against the framebuffer it adds to, checked
// before anything is written, so a rejected call leaves the framebuffer
// untouched. The settings are valid (checkRender); nothing below checks again.
void checkPass(const RenderSettings& s, const FramebufferImpl& fb, uint32_t first, uint32_t count) {
    const pn::Film& f = fb.film;
    require(f.fullWidth() > 0, "the framebuffer is empty (create it from the render settings)");
    require(!fb.incomplete, "the framebuffer holds a cancelled or failed pass; clear() it first");
    const CropWindow w = renderWindow(s);
    require(f.fullWidth() == s.width && f.fullHeight() == s.height && f.window() == w,
            "the framebuffer (" + windowText(f.fullWidth(), f.fullHeight(), f.window()) +
                ") does not match the render settings (" + windowText(s.width, s.height, w) + ")");
    require(uint64_t(first) + count <= uint64_t(s.spp), "samples [" + std::to_string(first) + ", " +
                                                            std::to_string(uint64_t(first) + count) +
                                                            ") exceed spp = " + std::to_string(s.spp));
    require(f.sampleCount() == first, "the framebuffer holds " + std::to_string(f.sampleCount()) +
                                          " samples per pixel; the pass must start there, not at " +
                                          std::to_string(first));
}

// One pass of checked arguments; `progress` receives the fraction of this pass, `tiles` the same in tiles.
RenderStats runPass(const PreparedImpl& p, const pn::CameraDesc& camera, const RenderSettings& s,
                    FramebufferImpl& fb, uint32_t first, uint32_t count, const std::function<void(double)>& progress,
                    const std::atomic<bool>* cancel, const std::function<void(size_t, size_t)>& tiles = {}) {
    pn::RenderControl control;
    control.cancel = cancel;
    if (progress || tiles)
        control.progress = [&](size_t done, size_t total) {
            if (tiles) tiles(done, total);
            if (progress) progress(double(done) / double(total));
        };
    fb.incomplete = true;  // until the pass completes
    const pn::PassResult pass = pn::renderPass(p.prepared, camera, s, fb.film, first, count, control);
    if (pass.cancelled)
        fail(ErrorCode::Cancelled, "render cancelled after " + std::to_string(fb.film.sampleCount()) +
                                       " complete samples per pixel; the framebuffer holds a partial pass");
    fb.incomplete = false;
    fb.seed = s.seed;
    fb.renderSeconds += pass.stats.renderSeconds;
    return pass.stats;
}

// The samples `fb` is missing, [its count, spp), for arguments checkRender passed.
RenderStats renderRest(const PreparedImpl& p, const Camera& camera, const RenderSettings& s, FramebufferImpl& fb,
                       const RenderControl& control) {
    const uint32_t have = fb.film.sampleCount(), spp = uint32_t(s.spp);
    require(have <= spp, "the framebuffer already holds " + std::to_string(have) + " samples per pixel, spp is " +
                             std::to_string(spp));
    checkPass(s, fb, have, spp - have);
    return runPass(p, camera, s, fb, have, spp - have, control.progress, control.cancel, control.tileProgress);
}

}  // namespace

// ---------------------------------------------------------------- RenderJob

RenderJob::RenderJob() = default;
RenderJob::~RenderJob() = default;
RenderJob::RenderJob(RenderJob&&) noexcept = default;
RenderJob& RenderJob::operator=(RenderJob&&) noexcept = default;

double RenderJob::progress() const noexcept { return impl_ ? impl_->state->progress.load() : 0.0; }
void RenderJob::cancel() noexcept {
    if (impl_) impl_->state->cancel.store(true);
}
bool RenderJob::done() const noexcept { return !impl_ || impl_->state->done.load(); }

void RenderJob::wait() const {
    if (!impl_) return;
    JobState& s = *impl_->state;
    std::unique_lock<std::mutex> lock(s.mutex);
    s.finished.wait(lock, [&] { return s.done.load(); });
}

bool RenderJob::waitFor(std::chrono::milliseconds timeout) const {
    if (!impl_) return true;
    JobState& s = *impl_->state;
    std::unique_lock<std::mutex> lock(s.mutex);
    return s.finished.wait_for(lock, timeout, [&] { return s.done.load(); });
}

JobStatus RenderJob::status() const noexcept { return impl_ ? impl_->state->status.load() : JobStatus::Failed; }

std::optional<Error> RenderJob::error() const {
    if (!impl_) return Error(ErrorCode::InvalidArgument, "empty render job");
    wait();
    return impl_->state->error;
}

RenderStats RenderJob::stats() const {
    if (!impl_) return {};
    wait();
    return impl_->state->stats;
}

const Framebuffer& RenderJob::framebuffer() const {
    require(impl_ != nullptr, "empty render job");
    wait();
    const JobState& s = *impl_->state;
    if (s.error) throw *s.error;
    return s.image;
}

Framebuffer RenderJob::takeFramebuffer() {
    framebuffer();  // waits, throws the job's error
    return std::move(impl_->state->image);
}

// ---------------------------------------------------------------- Renderer: rendering

Framebuffer Renderer::render(const PreparedScene& scene, const Camera& camera, const RenderSettings& settings,
                             const RenderControl& control) const {
    return guarded([&] {
        const PreparedImpl& p = checkRender(scene, camera, settings);
        Framebuffer image = newFramebuffer(settings);
        renderRest(p, camera, settings, Access::of(image), control);
        return image;
    });
}

RenderStats Renderer::render(const PreparedScene& scene, const Camera& camera, const RenderSettings& settings,
                             Framebuffer& image, const RenderControl& control) const {
    return guarded([&] {
        return renderRest(checkRender(scene, camera, settings), camera, settings, Access::of(image), control);
    });
}

RenderStats Renderer::render(const PreparedScene& scene, const Camera& camera, const RenderSettings& settings,
                             float* rgba, std::size_t floatCount, const RenderControl& control) const {
    return guarded([&] {
        const PreparedImpl& p = checkRender(scene, camera, settings);
        const CropWindow w = renderWindow(settings);
        const size_t needed = 4 * size_t(w.x1 - w.x0) * size_t(w.y1 - w.y0);
        require(rgba != nullptr, "render: destination is null");
        require(floatCount >= needed, "render: destination holds " + std::to_string(floatCount) +
                                          " floats, the image needs " + std::to_string(needed));
        Framebuffer image = newFramebuffer(settings);
        const RenderStats st = renderRest(p, camera, settings, Access::of(image), control);
        image.readRgba(rgba, floatCount);
        return st;
    });
}

RenderStats Renderer::renderPass(const PreparedScene& scene, const Camera& camera, const RenderSettings& settings,
                                 Framebuffer& image, std::uint32_t firstSample, std::uint32_t sampleCount,
                                 const RenderControl& control) const {
    return guarded([&] {
        const PreparedImpl& p = checkRender(scene, camera, settings);
        FramebufferImpl& fb = Access::of(image);
        checkPass(settings, fb, firstSample, sampleCount);
        return runPass(p, camera, settings, fb, firstSample, sampleCount, control.progress, control.cancel,
                       control.tileProgress);
    });
}

RenderJob Renderer::renderAsync(const PreparedScene& scene, const Camera& camera, const RenderSettings& settings,
                                AsyncOptions options) const {
    return guarded([&] {
        checkRender(scene, camera, settings);
        const RenderSettings& s = settings;
        auto state = std::make_shared<JobState>();
        state->image = newFramebuffer(settings);

        auto work = [state, prepared = PreparedScene(scene), cam = camera, s, opts = std::move(options)]() mutable {
            JobResult result;
            const uint32_t spp = uint32_t(s.spp);
            const uint32_t step = opts.passSamples > 0 ? std::min(opts.passSamples, spp) : spp;
            try {
                guarded([&] {
                    const PreparedImpl& p = *Access::of(prepared);
                    FramebufferImpl& fb = Access::of(state->image);
                    for (uint32_t first = 0; first < spp; first += step) {
                        if (state->cancel.load())
                            fail(ErrorCode::Cancelled, "render cancelled after " + std::to_string(first) +
                                                           " samples per pixel");
                        const uint32_t count = std::min(step, spp - first);
                        auto progress = [&](double f) {
                            const double done = (double(first) + f * double(count)) / double(spp);
                            state->progress.store(done);
                            if (opts.progress) opts.progress(done);
                        };
                        accumulate(result.stats, runPass(p, cam, s, fb, first, count, progress, &state->cancel));
                        if (opts.onPass) opts.onPass(state->image, first + count);
                    }
                });
                result.status = JobStatus::Finished;
                state->progress.store(1.0);
            } catch (const Error& e) {
                result.status = e.code() == ErrorCode::Cancelled ? JobStatus::Cancelled : JobStatus::Failed;
                result.error = e;
            }
            result.framebuffer = result.status == JobStatus::Finished ? &state->image : nullptr;
            if (opts.onComplete) {
                try {
                    opts.onComplete(result);
                } catch (...) {
                    // A throwing completion callback must not take the process down
                    // (std::terminate on this thread); the job's outcome stands.
                }
            }
            // The callbacks and the scene are released before the job says it
            // is done, not when this thread ends: whoever waited may then tear
            // down what they hold (a Python interpreter at exit, whose
            // finalisation stops a thread that asks for the GIL afterwards).
            opts = AsyncOptions{};
            prepared = PreparedScene{};
            std::lock_guard<std::mutex> lock(state->mutex);
            state->error = result.error;
            state->stats = result.stats;
            state->status.store(result.status);
            state->done.store(true);
            state->finished.notify_all();
        };

        auto impl = std::make_unique<JobImpl>();
        impl->state = state;
        impl->thread = std::thread(std::move(work));
        RenderJob job;
        Access::set(job, std::move(impl));
        return job;
    });
}

}  // namespace pnb
