// What the pieces of the C++ API share: the hidden implementations behind the
// public handles, the exception guard every entry point runs in, and the few
// conversions between the public and the internal types that are not one type.
// Internal to api/: no host sees it.
#pragma once

#include <penumbra/penumbra.hpp>

#include <filesystem>
#include <new>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/camera.h"
#include "core/film.h"
#include "core/log.h"
#include "core/render_settings.h"
#include "core/scene.h"
#include "core/transform.h"
#include "shading/renderer.h"

namespace pnb {

namespace pn = penumbra;

// ---------------------------------------------------------------- implementations

struct Scene::Impl {
    pn::Scene scene;
    std::optional<pn::CameraDesc> camera;
    pn::SettingsPatch settings;
    std::string source;  // the scene file it was loaded from; empty for a scene built in code
};

struct PreparedScene::Impl {
    Impl(pn::Scene scene, const pn::PrepareOptions& options, const pn::Logger& log,
         std::optional<pn::CameraDesc> cam, pn::SettingsPatch patch)
        : prepared(std::move(scene), options, log), camera(cam), settings(patch) {}
    pn::PreparedScene prepared;
    std::optional<pn::CameraDesc> camera;
    pn::SettingsPatch settings;
};

struct Framebuffer::Impl {
    pn::Film film;
    bool incomplete = false;  // a pass was cut short: the sums are partial
    std::uint64_t seed = 0;
    double renderSeconds = 0.0;
};

struct Renderer::Impl {
    pn::Logger log;
};

// What an asynchronous job shares with its thread.
struct JobState {
    std::atomic<double> progress{0.0};
    std::atomic<bool> cancel{false};
    std::atomic<JobStatus> status{JobStatus::Running};
    std::atomic<bool> done{false};
    std::mutex mutex;
    std::condition_variable finished;
    std::optional<Error> error;
    RenderStats stats;
    Framebuffer image;
};

struct RenderJob::Impl {
    std::shared_ptr<JobState> state;
    std::thread thread;
    ~Impl() {
        state->cancel.store(true);
        if (thread.joinable()) thread.join();
    }
};

namespace detail {
struct Access {
    using SceneImpl = Scene::Impl;
    using PreparedImpl = PreparedScene::Impl;
    using FramebufferImpl = Framebuffer::Impl;
    using JobImpl = RenderJob::Impl;
    static Scene::Impl& of(Scene& s) { return *s.impl_; }
    static const Scene::Impl& of(const Scene& s) { return *s.impl_; }
    static const PreparedScene::Impl* of(const PreparedScene& p) { return p.impl_.get(); }
    static void set(PreparedScene& p, std::shared_ptr<const PreparedScene::Impl> impl) { p.impl_ = std::move(impl); }
    static Framebuffer::Impl& of(Framebuffer& f) { return *f.impl_; }
    static const Framebuffer::Impl& of(const Framebuffer& f) { return *f.impl_; }
    static const pn::Logger& log(const Renderer& r) { return r.impl_->log; }
    static void set(RenderJob& j, std::unique_ptr<RenderJob::Impl> impl) { j.impl_ = std::move(impl); }
};
}  // namespace detail

using SceneImpl = detail::Access::SceneImpl;
using PreparedImpl = detail::Access::PreparedImpl;
using FramebufferImpl = detail::Access::FramebufferImpl;
using JobImpl = detail::Access::JobImpl;
using detail::Access;

// ---------------------------------------------------------------- helpers

[[noreturn]] inline void fail(ErrorCode code, const std::string& message) { throw Error(code, message); }

inline void require(bool ok, const std::string& message) {
    if (!ok) fail(ErrorCode::InvalidArgument, message);
}

/// Runs f, turning every failure into pnb::Error (the library's own errors
/// already are). Host callbacks may throw pnb::Error themselves; that passes
/// through unchanged.
template <class F>
auto guarded(F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw Error(ErrorCode::OutOfMemory, "out of memory");
    } catch (const std::filesystem::filesystem_error& e) {
        throw Error(ErrorCode::IoError, e.what());
    } catch (const std::exception& e) {
        throw Error(ErrorCode::Internal, e.what());
    } catch (...) {
        throw Error(ErrorCode::Internal, "unknown exception");
    }
}

// Conversions (api/conversions.cpp). Render settings, crop windows, error
// codes, log levels, Phong models and build qualities are one type inside and
// out; vectors, colours, cameras and stats keep an internal form of their own.
pn::Vec3f in(const Vec3& v);
Vec3 out(const pn::Vec3f& v);
pn::Rgb in(const Color& c);
Color out(const pn::Rgb& c);
pn::Transform in(const Matrix3x4& m);
Matrix3x4 out(const pn::Transform& t);
/// Default settings with a scene file's "render" block applied.
RenderSettings settingsFrom(const pn::SettingsPatch& patch);
/// The scene's camera, else one framing `bounds`.
Camera defaultCameraFor(const std::optional<pn::CameraDesc>& cam, const pn::Bounds3f& bounds, float aspect, float vfov);
/// Adds a pass's counts to a job's total.
void accumulate(RenderStats& total, const RenderStats& pass);

/// The prepared data behind a handle; throws for an empty one.
const PreparedImpl& requirePrepared(const PreparedScene& p);
/// A framebuffer for valid settings (the public constructor validates them first); throws
/// Error(OutOfMemory) when it would need more than half the machine's memory.
Framebuffer newFramebuffer(const RenderSettings& settings);

}  // namespace pnb
