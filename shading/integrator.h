// Whitted-style integrator: emission + ambient + Monte Carlo direct lighting
// from every light at each hit, plus perfect mirror reflection carried
// iteratively with a throughput (no recursion, so any max depth is safe).
#pragma once

#include <cstdint>

#include "accel/accelerator.h"
#include "core/color.h"
#include "core/render_settings.h"
#include "core/scene.h"
#include "lights/light_set.h"

namespace penumbra {

class TextureCache;

/// Rays traced and samples dropped, counted per tile and summed.
struct RayCounts {
    uint64_t camera = 0, shadow = 0, reflection = 0;
    uint64_t nonFinite = 0;  // radiance samples that were NaN/Inf and dropped
    RayCounts& operator+=(const RayCounts& o) {
        camera += o.camera;
        shadow += o.shadow;
        reflection += o.reflection;
        nonFinite += o.nonFinite;
        return *this;
    }
    uint64_t total() const { return camera + shadow + reflection; }
};

/// First-hit data for the AOVs.
struct FirstHit {
    Rgb albedo;
    Vec3f normal;
    float depth = 0.f;
};

/// Sample-set dimensions: 0 = pixel position, 1 = lens, 2... = light samples
/// (bounce d, light j uses kFirstLightDimension + d * (lights + 1) + j).
inline constexpr uint64_t kPixelDimension = 0;
inline constexpr uint64_t kLensDimension = 1;
inline constexpr uint64_t kFirstLightDimension = 2;

/// Identifies the random numbers of one camera sample: every sample is a pure
/// function of (seed, pixel, sample index, dimension).
struct SampleKey {
    uint64_t seed;
    uint64_t pixel;     // y * fullWidth + x
    uint32_t index;     // camera sample index within the pixel
};

class Integrator {
public:
    Integrator(const Scene& scene, const Accelerator& accel, const LightSet& lights, const TextureCache* textures,
               const RenderSettings& settings);

    /// Angle (radians) one pixel subtends at the camera; it sizes the texture
    /// filter footprint (ray cones without differentials). 0 = finest level.
    void setPixelSpread(float radians) { pixelSpread_ = radians; }

    /// Radiance arriving along the camera ray.
    Rgb Li(const Ray& cameraRay, const SampleKey& key, RayCounts& counts, FirstHit* firstHit) const;
    /// The same, with the camera ray's closest hit already found (the renderer
    /// traces camera rays as packets).
    Rgb Li(const Ray& cameraRay, const std::optional<Hit>& primaryHit, const SampleKey& key, RayCounts& counts,
           FirstHit* firstHit) const;

private:
    Rgb directLight(const Hit& hit, const Material& m, const Rgb& kd, const Vec3f& ng, const Vec3f& ns,
                    const Vec3f& wo, const SampleKey& key, int depth, RayCounts& counts) const;
    Rgb diffuseAlbedo(const Material& m, const Hit& hit, float pathLength, const Vec3f& wo) const;

    const Scene& scene_;
    const Accelerator& accel_;
    const LightSet& lights_;
    const TextureCache* textures_;
    RenderSettings settings_;
    float pixelSpread_ = 0.f;
};

}  // namespace penumbra
