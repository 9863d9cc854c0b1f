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

#include "shading/bsdf/bsdf.h"
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
    /// The bounces of the lanes still going at `depth`: each samples its next
    /// direction with its point of the bounce dimension (the Lambertian ones
    /// lane-wise); those that go on get their ray, put in `next` with their
    /// lane's index in `nextLane`; the others become inactive. Returns how
    /// many go on.
    size_t scatterBatch(std::span<PathVertexLane> lanes, std::span<uint8_t> active, int depth,
                        std::span<const SampleKey> keys, Ray* next, uint8_t* nextLane, RayCounts& counts) const;
    /// Takes the lane's sampled bounce b: false when the path ends there,
    /// else its ray is the lane's and `next`.
    bool scatter(PathVertexLane& lane, int depth, const std::optional<BsdfBounce>& b, Ray& next,
                 RayCounts& counts) const;

    const LightSet& lights_;
    RenderSettings settings_;
    SurfaceShading surfaces_;
    DirectLight direct_;
};

}  // namespace penumbra
