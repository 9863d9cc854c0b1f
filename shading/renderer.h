// The renderer: a prepared scene (accelerator, lights, textures built once)
// rendered into a film by tiles in parallel. This is the composition root of
// the library: the CLI and the embedding API both go through it.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "accel/accelerator.h"
#include "core/camera.h"
#include "core/film.h"
#include "core/log.h"
#include "core/render_settings.h"
#include "core/scene.h"
#include "lights/light_set.h"
#include "shading/integrator.h"

namespace penumbra {

class TextureCache;

struct PrepareOptions {
    AcceleratorKind accelerator = AcceleratorKind::Embree;
    BuildQuality quality = BuildQuality::High;
};

/// The light a scene without any gets (Scene::defaultLight): a uniform white
/// environment of this radiance.
inline constexpr float kDefaultEnvironmentRadiance = 1.f;

/// A scene made ready to render: finalized, with its BVH, light set and
/// texture cache. Build once, render many views and settings. Immutable and
/// safe to share between concurrent renders.
class PreparedScene {
public:
    /// Takes the scene by value (move it in); finalizes it and builds
    /// everything. Throws Error on failure (Embree errors included).
    PreparedScene(Scene scene, const PrepareOptions& options, const Logger& log);
    ~PreparedScene();
    PreparedScene(const PreparedScene&) = delete;
    PreparedScene& operator=(const PreparedScene&) = delete;

    const Scene& scene() const { return scene_; }
    const Accelerator& accelerator() const { return *accel_; }
    const LightSet& lights() const { return *lights_; }
    const TextureCache* textures() const { return textures_.get(); }
    double buildSeconds() const { return buildSeconds_; }
    const SceneFixups& fixups() const { return fixups_; }
    /// True when the scene had no light at all and got the default
    /// environment (Scene::defaultLight; a warning said so).
    bool defaultLightAdded() const { return defaultLightAdded_; }

private:
    Scene scene_;
    SceneFixups fixups_;
    std::unique_ptr<Accelerator> accel_;
    std::unique_ptr<LightSet> lights_;
    std::unique_ptr<TextureCache> textures_;
    double buildSeconds_ = 0.0;
    bool defaultLightAdded_ = false;
};

using pnb::RenderStats;

/// One render call's outcome: the public stats (samplesPerPixel = what the film
/// holds after the call) and whether the host cancelled it.
struct PassResult {
    RenderStats stats;
    bool cancelled = false;
};

/// Host hooks for one render call.
struct RenderControl {
    /// Called after each finished tile with (tiles done, tiles total); never
    /// concurrently with itself. May be empty.
    std::function<void(size_t, size_t)> progress;
    /// When set and it becomes true, the render stops within one batch of at most
    /// 16 camera samples per thread (checked inside tiles; docs/embedding.md).
    const std::atomic<bool>* cancel = nullptr;
};

/// Renders camera samples [firstSample, firstSample + sampleCount) of an
/// spp-sample multi-jittered set (settings.spp) into `film`, adding them to
/// what it holds. Rendering samples [0, spp) in one call or in several passes
/// gives bit-identical films, for any thread count and tile size. The film
/// must match settings (size, crop). A cancelled call leaves the film partly
/// accumulated (PassResult::cancelled is set): discard it. `internal` holds
/// what only the benchmark tools set (the comparison baselines).
PassResult renderPass(const PreparedScene& prepared, const CameraDesc& camera, const RenderSettings& settings,
                       Film& film, uint32_t firstSample, uint32_t sampleCount, const RenderControl& control = {},
                       const InternalSettings& internal = {});

/// Convenience: a new film with all settings.spp samples.
Film makeFilm(const RenderSettings& settings);
PassResult render(const PreparedScene& prepared, const CameraDesc& camera, const RenderSettings& settings, Film& film,
                   const RenderControl& control = {}, const InternalSettings& internal = {});

}  // namespace penumbra
