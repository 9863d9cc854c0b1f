// Whitted-style integrator: emission + ambient + Monte Carlo direct lighting
// from every light at each hit, plus perfect mirror reflection and, at
// dielectrics, Whitted's transmitted ray beside the mirror ray (Fresnel
// weights), carried iteratively with a throughput: each lane follows one ray
// and keeps the other branches on a small stack of its own (no recursion, so
// any max depth is safe; the stack grows by at most one entry per bounce).
#pragma once

#include <cstdint>
#include <optional>
#include <span>

#include "accel/accelerator.h"
#include "accel/shape_bounds.h"
#include "core/color.h"
#include "core/owen_sobol.h"
#include "core/render_settings.h"
#include "core/scene.h"
#include "lights/light_set.h"
#include "shading/shading_point.h"

namespace penumbra {

class TextureCache;

/// Rays traced and samples dropped, counted per tile and summed.
struct RayCounts {
    uint64_t camera = 0, shadow = 0, reflection = 0;
    uint64_t nonFinite = 0;  // radiance samples that were NaN/Inf and dropped
    uint64_t transmission = 0;  // refracted rays (dielectrics)
    uint64_t indirect = 0;      // path: diffuse and glossy bounce rays
    uint64_t pathLengthSum = 0; // rays along each camera sample's path (whitted: deepest branch)
    uint32_t pathLengthMax = 0;
    uint64_t brdf = 0;          // whitted: BRDF-sampled rays of direct light under MIS (closest-hit queries)
    RayCounts& operator+=(const RayCounts& o) {
        camera += o.camera;
        shadow += o.shadow;
        reflection += o.reflection;
        nonFinite += o.nonFinite;
        transmission += o.transmission;
        indirect += o.indirect;
        pathLengthSum += o.pathLengthSum;
        pathLengthMax = pathLengthMax > o.pathLengthMax ? pathLengthMax : o.pathLengthMax;
        brdf += o.brdf;
        return *this;
    }
    uint64_t total() const { return camera + shadow + reflection + transmission + indirect + brdf; }
};

/// First-hit data for the AOVs.
struct FirstHit {
    Rgb albedo;
    Vec3f normal;
    float depth = 0.f;
};

/// Sample-set dimensions: 0 = pixel position, 1 = lens, 2... = direct light
/// (bounce d, light j uses kFirstLightDimension + d * (lights + 2) + j; then
/// one for power-selected light samples and one for BRDF samples).
inline constexpr uint32_t kPixelDimension = 0;
inline constexpr uint32_t kLensDimension = 1;
inline constexpr uint32_t kFirstLightDimension = 2;

/// Identifies the random numbers of one camera sample: every sample is a pure
/// function of (seed, pixel, sample index, dimension). pixelKey is
/// pixelSampleKey(seed, pixel) (core/multi_jitter.h), hashed once per pixel.
struct SampleKey {
    uint64_t pixelKey;
    uint32_t index;  // camera sample index within the pixel
};

/// The points camera sample `key` draws in dimension `dim`: sample k of the
/// n it takes at a shading point is point key.index * n + k of the pixel's
/// Owen-scrambled Sobol sequence for that dimension (core/owen_sobol.h), so
/// each shading point's n points are stratified and so are all spp * n of
/// the pixel.
inline uint64_t dimensionKey(const SampleKey& key, uint32_t dim) {
    return key.pixelKey ^ ((uint64_t(dim) + 1) * 0x9e3779b97f4a7c15ULL);
}
inline OwenSobol2D dimensionSequence(const SampleKey& key, uint32_t dim) { return OwenSobol2D(dimensionKey(key, dim)); }

/// Radiance a ray leaving the scene along `dir` sees: the environment light
/// when the scene has one (lights.environment()), else Scene::background. The
/// one rule for escaped rays, shared by every integrator.
Rgb escapedRadiance(const Scene& scene, const LightSet& lights, const Vec3f& dir);

/// Path state of one camera sample while a batch of them is shaded.
struct PathLane;

class Integrator {
public:
    /// Most camera samples one radianceBatch call takes (a 4x4 pixel block).
    static constexpr size_t kMaxBatch = 16;

    Integrator(const Scene& scene, const Accelerator& accel, const LightSet& lights, const TextureCache* textures,
               const RenderSettings& settings);

    /// Angle (radians) one pixel subtends at the camera; it sizes the texture
    /// filter footprint (ray cones without differentials). 0 = finest level.
    void setPixelSpread(float radians) { pixelSpread_ = radians; }

    /// Radiance arriving along each camera ray of a batch (at most kMaxBatch),
    /// whose closest hits the caller has found (as packets). The batch is
    /// shaded together: the shadow rays of all its shading points go out as
    /// packets, and so do the mirror rays of each bounce. Each result depends
    /// only on its own ray, hit and key, never on the rest of the batch.
    /// firstHits may be empty (no AOVs).
    void radianceBatch(std::span<const Ray> cameraRays, std::span<const std::optional<Hit>> hits,
                       std::span<const SampleKey> keys, std::span<Rgb> radiance, std::span<FirstHit> firstHits,
                       RayCounts& counts) const;

    /// Radiance along one camera ray (a batch of one; for tests and tools).
    Rgb Li(const Ray& cameraRay, const SampleKey& key, RayCounts& counts, FirstHit* firstHit) const;

    /// Writes into sp the shading point of a hit reached along `ray` after
    /// pathLength (both integrators build it this one way: two-sided normals,
    /// textured kd), in place: a lane's shading point is read right after.
    void shade(const Hit& hit, const Ray& ray, float pathLength, ShadingPoint& sp) const;

private:
    /// Adds each lane's direct light (times its throughput) to its radiance.
    void addDirectLight(std::span<PathLane> lanes, std::span<const uint8_t> active, int depth, RayCounts& counts) const;
    /// addDirectLight for lanes at different bounce depths (dielectrics split lanes).
    void addDirectLightByDepth(std::span<PathLane> lanes, std::span<uint8_t> active, RayCounts& counts) const;
    /// Sets the lane's next ray after its shading point (mirror, or a dielectric's mirror ray with the
    /// transmitted one kept pending); false when the branch ends.
    bool continueLane(PathLane& lane, RayCounts& counts) const;
    /// Makes the lane's last pending ray its current one; false when none is left.
    bool resumePending(PathLane& lane) const;
    Rgb diffuseAlbedo(const Material& m, const Hit& hit, float pathLength, const Vec3f& wo) const;

    // Whether every shadow ray from the surface at p (geometric normal ng) to
    // area light j certainly meets nothing (ShapeBounds::segmentsClear):
    // then its samples there need no query.
    bool shadowsClear(size_t j, const Vec3f& p, const Vec3f& ng) const;

    const Scene& scene_;
    const Accelerator& accel_;
    const LightSet& lights_;
    const TextureCache* textures_;
    RenderSettings settings_;
    // Per light, where it is one rectangle or disk: the box its samples lie
    // in (padded), the primitive and its plane.
    struct ClearTarget {
        ShapeBounds::Targets targets;
        PrimRef self;
        Vec3f planePoint, planeNormal;
    };
    std::vector<std::optional<ClearTarget>> clearTargets_;
    float pixelSpread_ = 0.f;
    bool continues_ = false;  // some material sends rays on (mirror or glass) and the depth allows one
};

}  // namespace penumbra
