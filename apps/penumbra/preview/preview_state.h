// What the preview's render loop and its server share: the view the page asks
// for, the render's progress, and the latest image. One mutex guards it. The
// render loop never waits for the server; the server never reads the
// framebuffer being rendered (it encodes a copy taken after each pass).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <penumbra/penumbra.hpp>

namespace penumbra::preview {

class PreviewState {
public:
    using Clock = std::chrono::steady_clock;
    using Bytes = std::vector<std::uint8_t>;

    /// A view to render: the camera and a number that changes with every move.
    struct View {
        pnb::Camera camera;
        std::uint64_t id = 0;
    };

    /// The latest image, encoded: a JPEG while its view renders (a third of
    /// the PNG's encoding time and size), a PNG (lossless, as -o's) once the
    /// view is complete; the number of the pass that made it (counted over all
    /// views) and the view it shows.
    struct Image {
        std::shared_ptr<const Bytes> bytes;
        const char* type = "image/png";  // its Content-Type
        std::uint64_t version = 0;
        std::uint64_t view = 0;
    };

    /// The page names the scene from the start, while it loads.
    explicit PreviewState(std::string sceneName = {});

    // ---- the render loop's side

    /// The scene is prepared: what the page shows from now on. `exposure` (stops) tone-maps the images as -o's.
    void start(const pnb::RenderSettings& settings, const pnb::Camera& camera, float exposure);
    /// The view to render now (its progress started from zero when it was asked for).
    View view() const;
    /// True, with the cancel flag cleared, while `viewId` is still the view asked for.
    bool beginPass(std::uint64_t viewId);
    /// Set when the view changes or the render is to stop: RenderControl::cancel.
    const std::atomic<bool>* cancelFlag() const { return &cancel_; }
    /// Stops the pass in flight (Ctrl-C).
    void cancelRender();
    /// Samples done so far in view `viewId`, counting a pass's finished fraction.
    void progress(std::uint64_t viewId, double samplesDone);
    /// A pass finished: `image` holds its samples, `stats` those of the view's
    /// passes so far. The image is copied for the server when a page has asked
    /// for the status since the last copy, and always when it is the view's last.
    void publish(std::uint64_t viewId, const pnb::Framebuffer& image, const pnb::RenderStats& stats);
    /// The view's render is complete.
    void complete(std::uint64_t viewId);
    /// Waits at most `timeout` for a view other than `viewId`; true when there is one.
    bool waitForNewView(std::uint64_t viewId, std::chrono::milliseconds timeout);

    // ---- the server's side

    /// Phase, progress, camera and the camera's options, as the page reads them.
    std::string statusJson() const;
    /// The latest image, encoded on first request; empty before the first pass.
    std::optional<Image> image();
    /// Replaces the view with move(current view) and restarts the render from
    /// it. Throws pnb::Error(InvalidArgument) for a camera that is not valid
    /// and (InvalidScene) while the scene is loading; the view is then unchanged.
    void moveCamera(const std::function<pnb::Camera(const pnb::Camera&)>& move);
    /// Back to the camera the render started with.
    void resetCamera();

private:
    enum class Phase { Loading, Rendering, Complete };
    void setView(const pnb::Camera& camera);  // a new view, its progress at zero; with mutex_ held

    mutable std::mutex mutex_;
    std::condition_variable viewChanged_;
    std::atomic<bool> cancel_{false};
    Phase phase_ = Phase::Loading;
    pnb::RenderSettings settings_;
    std::string sceneName_;
    float exposure_ = 0.f;
    pnb::Camera initialCamera_, camera_;
    std::uint64_t viewId_ = 0;
    // Progress of the view being rendered.
    Clock::time_point viewStart_{};
    double viewSeconds_ = 0.0;  // frozen when complete
    double samplesDone_ = 0.0;
    pnb::RenderStats stats_;
    // The latest pass's image: a copy, encoded once when first asked for.
    mutable bool watched_ = true;  // the status was read since the last copy
    std::shared_ptr<const pnb::Framebuffer> snapshot_;
    std::uint64_t version_ = 0, snapshotView_ = 0;
    std::uint32_t snapshotSamples_ = 0;
    bool snapshotFinal_ = false;  // the snapshot holds all of its view's samples
    std::mutex encodeMutex_;  // one encoder at a time, outside mutex_
    Image encoded_;
};

}  // namespace penumbra::preview
