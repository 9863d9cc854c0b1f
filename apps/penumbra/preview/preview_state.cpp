#include "preview_state.h"

#include <nlohmann/json.hpp>

#include "orbit_camera.h"

namespace penumbra::preview {
namespace {

nlohmann::json vec(const pnb::Vec3& v) { return {v.x, v.y, v.z}; }

}  // namespace

PreviewState::PreviewState(std::string sceneName) : sceneName_(std::move(sceneName)) {}

void PreviewState::start(const pnb::RenderSettings& settings, const pnb::Camera& camera, float exposure) {
    const std::lock_guard lock(mutex_);
    settings_ = settings;
    exposure_ = exposure;
    initialCamera_ = camera;
    setView(camera);
}

void PreviewState::setView(const pnb::Camera& camera) {
    camera_ = camera;
    ++viewId_;
    phase_ = Phase::Rendering;
    viewStart_ = Clock::now();
    viewSeconds_ = 0.0;
    samplesDone_ = 0.0;
    stats_ = {};
    cancel_.store(true);
    viewChanged_.notify_all();
}

PreviewState::View PreviewState::view() const {
    const std::lock_guard lock(mutex_);
    return {camera_, viewId_};
}

bool PreviewState::beginPass(std::uint64_t viewId) {
    // Under the mutex, so that a move either comes before (and the pass does
    // not start) or after the flag is cleared (and cancels the pass).
    const std::lock_guard lock(mutex_);
    if (viewId != viewId_) return false;
    cancel_.store(false);
    return true;
}

void PreviewState::cancelRender() { cancel_.store(true); }

void PreviewState::progress(std::uint64_t viewId, double samplesDone) {
    const std::lock_guard lock(mutex_);
    if (viewId == viewId_) samplesDone_ = samplesDone;
}

void PreviewState::publish(std::uint64_t viewId, const pnb::Framebuffer& image, const pnb::RenderStats& stats) {
    {
        const std::lock_guard lock(mutex_);
        if (viewId != viewId_) return;
        const bool last = image.sampleCount() >= std::uint32_t(settings_.spp);
        samplesDone_ = image.sampleCount();
        stats_ = stats;
        // A copy costs the framebuffer's size (24 bytes a pixel) and its time:
        // made while a page watches, and always of the view's final image.
        if (!watched_ && !last) return;
        watched_ = false;
    }
    auto copy = std::make_shared<const pnb::Framebuffer>(image);  // outside the mutex: milliseconds for large images
    const std::lock_guard lock(mutex_);
    if (viewId != viewId_) return;
    snapshot_ = std::move(copy);
    snapshotSamples_ = image.sampleCount();
    snapshotFinal_ = snapshotSamples_ >= std::uint32_t(settings_.spp);
    snapshotView_ = viewId;
    ++version_;
}

void PreviewState::complete(std::uint64_t viewId) {
    const std::lock_guard lock(mutex_);
    if (viewId != viewId_) return;
    phase_ = Phase::Complete;
    viewSeconds_ = std::chrono::duration<double>(Clock::now() - viewStart_).count();
}

bool PreviewState::waitForNewView(std::uint64_t viewId, std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    return viewChanged_.wait_for(lock, timeout, [&] { return viewId_ != viewId; });
}

std::string PreviewState::statusJson() const {
    const std::lock_guard lock(mutex_);
    watched_ = true;
    nlohmann::json j;
    j["phase"] = phase_ == Phase::Loading ? "loading" : phase_ == Phase::Rendering ? "rendering" : "complete";
    j["scene"] = sceneName_;
    j["view"] = viewId_;
    j["version"] = version_;
    if (phase_ == Phase::Loading) return j.dump();
    const double seconds = phase_ == Phase::Complete ? viewSeconds_
                                                      : std::chrono::duration<double>(Clock::now() - viewStart_).count();
    j["width"] = settings_.width;
    j["height"] = settings_.height;
    j["spp"] = settings_.spp;
    j["samples"] = samplesDone_;
    j["seconds"] = seconds;
    // The rest of the view at the rate of its samples so far.
    j["eta"] = samplesDone_ > 0 ? nlohmann::json(seconds * (settings_.spp - samplesDone_) / samplesDone_) : nullptr;
    j["rays_per_second"] = stats_.renderSeconds > 0 ? double(stats_.totalRays()) / stats_.renderSeconds : 0.0;
    j["image_samples"] = snapshotSamples_;
    j["image_view"] = snapshotView_;
    j["camera"] = {{"eye", vec(camera_.eye)},
                   {"look_at", vec(camera_.lookAt)},
                   {"up", vec(camera_.up)},
                   {"fov", camera_.vfovDegrees}};
    j["options"] = cameraOptions(camera_);
    return j.dump();
}

std::optional<PreviewState::Image> PreviewState::image() {
    const std::lock_guard encoding(encodeMutex_);
    std::shared_ptr<const pnb::Framebuffer> snapshot;
    std::uint64_t version = 0, view = 0;
    bool final = false;
    pnb::ImageOptions options;
    {
        const std::lock_guard lock(mutex_);
        if (!snapshot_) return std::nullopt;
        if (encoded_.bytes && encoded_.version == version_) return encoded_;
        snapshot = snapshot_;
        version = version_;
        view = snapshotView_;
        final = snapshotFinal_;
        options.exposure = exposure_;
    }
    // Encoded while the render goes on: the snapshot is this thread's alone to read.
    const char* format = final ? "png" : "jpg";
    encoded_ = {std::make_shared<const Bytes>(snapshot->encodeImage(format, options)),
                final ? "image/png" : "image/jpeg", version, view};
    return encoded_;
}

void PreviewState::moveCamera(const std::function<pnb::Camera(const pnb::Camera&)>& move) {
    const std::lock_guard lock(mutex_);
    if (phase_ == Phase::Loading) throw pnb::Error(pnb::ErrorCode::InvalidScene, "the scene is still loading");
    const pnb::Camera moved = move(camera_);
    pnb::validate(moved);
    setView(moved);
}

void PreviewState::resetCamera() {
    moveCamera([this](const pnb::Camera&) { return initialCamera_; });
}

}  // namespace penumbra::preview
