// Path tracing (--integrator path): paths of diffuse, glossy, mirror and glass
// bounces with next-event estimation at every vertex with smooth lobes (the
// direct-light estimator, shading/direct_light.h, weighing each light sample
// against the path's own next bounce by Veach's power heuristic), emitters and
// the environment reached by a bounce weighted by the same heuristic, and
// Russian roulette after a few bounces. docs/rendering.md states the model.
//
// It has the Whitted integrator's batched shape: camera hits arrive in batches
// of up to 16 (shading/renderer.cpp); their shadow rays go out as packets of
// 16 and every bounce's continuation rays as one packet. A path never splits,
// so the lanes of a batch stay at the same depth. Every random number is a
// pure function of (seed, pixel, sample index, dimension) (shading/sample_key.h),
// so images are bit-identical for any thread count and tile size.
#pragma once

#include <cstdint>
#include <optional>
#include <span>

#include "shading/direct_light.h"
#include "shading/integrator.h"
#include "shading/surface_shading.h"

namespace penumbra {

/// Path state of one camera sample (path_integrator.cpp).
struct PathVertexLane;

class PathIntegrator final : public Integrator {
public:
    /// Bounces before Russian roulette may end a path.
    static constexpr int kRouletteDepth = 3;
    /// Throughput (largest component) below which a path takes Russian
    /// roulette, surviving with probability (throughput / this).
    static constexpr float kRouletteThroughput = 0.25f;

    explicit PathIntegrator(const IntegratorInputs& in);

    void radianceBatch(std::span<const Ray> cameraRays, std::span<const std::optional<Hit>> hits,
                       std::span<const SampleKey> keys, std::span<Rgb> radiance, std::span<FirstHit> firstHits,
                       RayCounts& counts) const override;

private:
    /// What the lane's ray sees when it leaves the scene: the environment
    /// light's radiance (weighed by MIS after a bounce from smooth lobes, as
    /// an emitter hit is) or the background (no light samples it: weight 1).
    Rgb escaped(const PathVertexLane& lane) const;
    /// Emission, the shading point and the lobes of every lane still going
    /// at `depth`; the lanes that end there become inactive.
    void shadeVertices(std::span<PathVertexLane> lanes, std::span<uint8_t> active, int depth,
                       std::span<FirstHit> firstHits) const;
    /// Samples the lane's next direction with the point u of its bounce
    /// dimension; false when the path ends there.
    bool scatter(PathVertexLane& lane, int depth, Vec2f u, RayCounts& counts) const;

    const LightSet& lights_;
    RenderSettings settings_;
    SurfaceShading surfaces_;
    DirectLight direct_;
};

}  // namespace penumbra
