// The preview's render loop: the view the page asks for, rendered in
// progressive passes through the public API (Renderer::renderPass), the first
// of one sample per pixel and the later ones sized to about a quarter of a
// second, growing to two seconds as the view converges (each pass costs a
// little: a framebuffer copy and a PNG while a page watches); a camera move
// cancels the pass in flight and starts again from it.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>

#include <penumbra/penumbra.hpp>

#include "preview_state.h"

namespace penumbra::preview {

/// What to render: the prepared scene and its settings (the camera is the state's).
struct PreviewJob {
    const pnb::Renderer& renderer;
    const pnb::PreparedScene& scene;
    pnb::RenderSettings settings;
};

/// Called with each view rendered to the end: its image, camera and stats.
using OnViewComplete = std::function<void(const pnb::Framebuffer& image, const pnb::Camera& camera,
                                          const pnb::RenderStats& stats)>;

enum class PreviewEnd {
    Interrupted,  ///< `interrupted` became true
    Completed,    ///< a view completed and `exitWhenComplete` asked to stop there
};

/// Renders the views `state` asks for until `interrupted` becomes true (it is
/// polled between passes, within each pass after every tile, and at least
/// every 100 ms while waiting for a new view), or, with exitWhenComplete,
/// until a view completes. Errors other than cancellation propagate.
PreviewEnd renderPreview(const PreviewJob& job, PreviewState& state, const std::atomic<bool>& interrupted,
                         bool exitWhenComplete, const OnViewComplete& onComplete);

/// How long a pass should take `elapsed` seconds into a view: a quarter of a
/// second at first, an eighth of the time so far later, at most two seconds.
double passSeconds(double elapsed);

/// Samples in the next pass: 1 first, then as many as take about
/// `targetSeconds` at the last pass's rate, at most twice the last pass,
/// never beyond `spp`.
std::uint32_t nextPassSamples(std::uint32_t done, std::uint32_t spp, std::uint32_t lastSamples, double lastSeconds,
                              double targetSeconds);

}  // namespace penumbra::preview
