#include "preview_render.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace penumbra::preview {
namespace {

// Renders the view's passes into `image`; true when all its samples are in,
// false when the view changed or the render was interrupted.
bool renderView(const PreviewJob& job, PreviewState& state, const PreviewState::View& view,
                const std::atomic<bool>& interrupted, pnb::Framebuffer& image, pnb::RenderStats& stats) {
    const auto spp = std::uint32_t(job.settings.spp);
    const auto start = std::chrono::steady_clock::now();
    std::uint32_t last = 0;
    double lastSeconds = 0.0;
    while (image.sampleCount() < spp) {
        if (interrupted.load() || !state.beginPass(view.id)) return false;
        const std::uint32_t first = image.sampleCount();
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const std::uint32_t count = nextPassSamples(first, spp, last, lastSeconds, passSeconds(elapsed));
        pnb::RenderControl control;
        control.cancel = state.cancelFlag();
        control.progress = [&](double fraction) {
            if (interrupted.load()) state.cancelRender();
            state.progress(view.id, first + fraction * count);
        };
        pnb::RenderStats pass;
        try {
            pass = job.renderer.renderPass(job.scene, view.camera, job.settings, image, first, count, control);
        } catch (const pnb::Error& e) {
            if (e.code() != pnb::ErrorCode::Cancelled) throw;
            return false;
        }
        stats += pass;
        last = count;
        lastSeconds = pass.renderSeconds;
        state.publish(view.id, image, stats);
    }
    return true;
}

}  // namespace

double passSeconds(double elapsed) { return std::clamp(elapsed / 8.0, 0.25, 2.0); }

std::uint32_t nextPassSamples(std::uint32_t done, std::uint32_t spp, std::uint32_t lastSamples, double lastSeconds,
                              double targetSeconds) {
    std::uint32_t n = 1;
    if (lastSamples > 0) {
        const double rate = lastSeconds > 0 ? double(lastSamples) / lastSeconds : 2.0 * lastSamples / targetSeconds;
        n = std::uint32_t(std::clamp(std::floor(rate * targetSeconds), 1.0, 2.0 * lastSamples));
    }
    return std::min(n, spp - done);
}

PreviewEnd renderPreview(const PreviewJob& job, PreviewState& state, const std::atomic<bool>& interrupted,
                         bool exitWhenComplete, const OnViewComplete& onComplete) {
    pnb::Framebuffer image(job.settings);
    while (!interrupted.load()) {
        const PreviewState::View view = state.view();
        image.clear();  // also after a cancelled pass, which leaves it incomplete
        pnb::RenderStats stats;
        if (!renderView(job, state, view, interrupted, image, stats)) continue;
        state.complete(view.id);
        onComplete(image, view.camera, stats);
        if (exitWhenComplete) return PreviewEnd::Completed;
        while (!interrupted.load() && !state.waitForNewView(view.id, std::chrono::milliseconds(100))) {
        }
    }
    return PreviewEnd::Interrupted;
}

}  // namespace penumbra::preview
