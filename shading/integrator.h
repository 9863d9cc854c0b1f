// The interface every integrator implements and the renderer calls, once per
// batch of camera samples, and makeIntegrator, the one place that maps
// RenderSettings::integrator to an implementation. A new integrator is a
// class of its own file (whitted_integrator.h, path_integrator.h) and one
// line in makeIntegrator (shading/integrator.cpp).
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <span>

#include "accel/accelerator.h"
#include "core/color.h"
#include "core/render_settings.h"
#include "core/scene.h"
#include "lights/light_set.h"
#include "shading/ray_counts.h"
#include "shading/sample_key.h"

namespace penumbra {

class TextureCache;

/// What an integrator is built from, once per render pass: the prepared
/// scene's parts (which outlive it), the settings, the angle (radians) one
/// pixel subtends at the camera, which sizes texture filter footprints, and
/// the settings of the benchmark tools.
struct IntegratorInputs {
    const Scene& scene;
    const Accelerator& accel;
    const LightSet& lights;
    const TextureCache* textures;
    const RenderSettings& settings;
    float pixelSpread = 0.f;
    InternalSettings internal = {};
};

class Integrator {
public:
    /// Most camera samples one radianceBatch call takes (a 4x4 pixel block).
    static constexpr size_t kMaxBatch = 16;

    virtual ~Integrator() = default;

    /// Radiance arriving along each camera ray of a batch (at most kMaxBatch),
    /// whose closest hits the caller has found (as packets). Each result
    /// depends only on its own ray, hit and key, never on the rest of the
    /// batch. firstHits may be empty (no AOVs).
    virtual void radianceBatch(std::span<const Ray> cameraRays, std::span<const std::optional<Hit>> hits,
                               std::span<const SampleKey> keys, std::span<Rgb> radiance, std::span<FirstHit> firstHits,
                               RayCounts& counts) const = 0;

    /// Radiance along one camera ray (a batch of one; for tests and tools).
    Rgb Li(const Ray& cameraRay, const SampleKey& key, RayCounts& counts, FirstHit* firstHit = nullptr) const;

protected:
    explicit Integrator(const Accelerator& accel) : accel_(accel) {}
    const Accelerator& accel_;
};

/// The integrator settings.integrator names, built from `in`.
std::unique_ptr<Integrator> makeIntegrator(const IntegratorInputs& in);

}  // namespace penumbra
