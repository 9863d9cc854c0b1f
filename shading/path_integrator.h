// Path tracing (--integrator path): paths of diffuse, glossy, mirror and glass
// bounces with next-event estimation at every non-specular vertex, light and
// BRDF samples combined by multiple importance sampling (Veach's power
// heuristic), emitters hit by a bounce weighted by the same heuristic, and
// Russian roulette after a few bounces. docs/rendering.md states the model.
//
// It has the Whitted integrator's batched shape: camera hits arrive in batches
// of up to 16 (shading/renderer.cpp); their shadow rays go out as packets of
// 16 and every bounce's continuation rays as one packet. A path never splits,
// so the lanes of a batch stay at the same depth. Every random number is a
// pure function of (seed, pixel, sample index, dimension) (core/multi_jitter.h),
// so images are bit-identical for any thread count and tile size.
#pragma once

#include <cstdint>
#include <optional>
#include <span>

#include "shading/integrator.h"
#include "shading/surface_shading.h"

namespace penumbra {

/// Path state of one camera sample (path_integrator.cpp).
struct PathVertexLane;

class PathIntegrator final : public Integrator {
public:
    /// Bounces before Russian roulette may end a path.
    static constexpr int kRouletteDepth = 3;

    explicit PathIntegrator(const IntegratorInputs& in);

    void radianceBatch(std::span<const Ray> cameraRays, std::span<const std::optional<Hit>> hits,
                       std::span<const SampleKey> keys, std::span<Rgb> radiance, std::span<FirstHit> firstHits,
                       RayCounts& counts) const override;

private:
    /// What the lane's ray sees when it leaves the scene, times its MIS weight:
    /// the scene's background (no light samples it: weight 1). The environment
    /// light (LightSet::environment()) takes its place here when the scene has
    /// one, weighted after a non-specular bounce as emitterHitWeight does.
    Rgb escaped(const PathVertexLane& lane) const;
    /// Next-event estimation with MIS at every lane's vertex, added to its L.
    void addDirectLight(std::span<PathVertexLane> lanes, std::span<const uint8_t> active, int depth,
                        RayCounts& counts) const;
    /// MIS weight of emission reached by a BRDF-sampled bounce from prevP
    /// (geometric normal prevN, solid-angle pdf bsdfPdf) at `hit`, against
    /// the light samples that could have found it.
    float emitterHitWeight(const Vec3f& prevP, const Vec3f& prevN, float bsdfPdf, const Hit& hit) const;
    /// Solid-angle pdf with which the non-specular lobes (Phong) sample wi.
    float scatterPdf(const PathVertexLane& lane, const Vec3f& wi) const;
    /// Samples the lane's next direction; false when the path ends there.
    bool scatter(PathVertexLane& lane, int depth, RayCounts& counts) const;

    const Scene& scene_;
    const LightSet& lights_;
    RenderSettings settings_;
    SurfaceShading surfaces_;
    const LightPicker* picker_;  // null: every light takes every vertex's samples
};

}  // namespace penumbra
