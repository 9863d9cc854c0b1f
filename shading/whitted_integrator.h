// Whitted-style integrator: emission + ambient + Monte Carlo direct lighting
// from every light at each hit, plus perfect mirror reflection (kr, or the
// specular lobe of a polished metal-roughness surface: kMirrorRoughness) and, at
// dielectrics, Whitted's transmitted ray beside the mirror ray (Fresnel
// weights), carried iteratively with a throughput: each lane follows one ray
// and keeps the other branches on a small stack of its own (no recursion, so
// any max depth is safe; the stack grows by at most one entry per bounce).
//
// Up to the default --max-depth every branch is traced. Beyond it, where the
// rays a dielectric splits into would multiply without end, a lane follows one
// of them, picked in proportion to its Fresnel weight, and a branch of low
// throughput takes Russian roulette: the work then grows with the depth at
// most as a mirror's does, and the estimate stays unbiased (docs/rendering.md).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "shading/direct_light.h"
#include "shading/integrator.h"
#include "shading/surface_shading.h"

namespace penumbra {

/// Path state of one camera sample while a batch of them is shaded.
struct PathLane;

class WhittedIntegrator final : public Integrator {
public:
    /// Bounce depths up to which every branch is traced: the default --max-depth
    /// (RenderSettings::maxDepth), so that renders at it are exact Whitted.
    static constexpr int kExactDepth = 10;
    /// Beyond kExactDepth, a branch whose throughput's largest component is
    /// below this survives Russian roulette with probability (that
    /// component / this) and then carries it.
    static constexpr float kRouletteThroughput = 1.f / 16.f;
    /// Metal-roughness surfaces at or below this roughness reflect their
    /// specular lobe as a mirror bounce (weighted by its Fresnel reflectance,
    /// shading/bsdf/metal_roughness.h), which shows what they reflect; their
    /// direct light is the diffuse base's. Rougher ones take the whole BRDF
    /// in direct light, under MIS, and no bounce, as glossy Phong does.
    static constexpr float kMirrorRoughness = 0.1f;

    explicit WhittedIntegrator(const IntegratorInputs& in);

    /// The batch is shaded together: the shadow rays of all its shading
    /// points go out as packets, and so do the mirror rays of each bounce.
    void radianceBatch(std::span<const Ray> cameraRays, std::span<const std::optional<Hit>> hits,
                       std::span<const SampleKey> keys, std::span<Rgb> radiance, std::span<FirstHit> firstHits,
                       RayCounts& counts) const override;

private:
    /// radianceBatch's body, compiled for each lane width (core/lane_clones.h).
    void shadeBatch(std::span<const Ray> cameraRays, std::span<const std::optional<Hit>> hits,
                    std::span<const SampleKey> keys, std::span<Rgb> radiance, std::span<FirstHit> firstHits,
                    RayCounts& counts) const;
    /// Adds each lane's direct light (times its throughput) to its radiance:
    /// the lanes that reflect light, as the points of one estimate.
    void addDirectLight(std::span<PathLane> lanes, std::span<const uint8_t> active, int depth, RayCounts& counts) const;
    /// The closest hits of a bounce's rays (intersectBatch), the convex meshes
    /// they leave hinted. Out of line: inlined, the batch query (eight
    /// arguments, two on the stack) made GCC keep a frame pointer in
    /// shadeBatch's AVX2 clone, a register fewer for its loops.
    void traceNext(const Ray* rays, size_t n, const int32_t* leaving, std::optional<Hit>* hits) const;
    /// addDirectLight for lanes at different bounce depths (dielectrics split lanes).
    void addDirectLightByDepth(std::span<PathLane> lanes, std::span<uint8_t> active, RayCounts& counts) const;
    /// Writes the lane's next ray after its shading point into `next` (mirror, or a dielectric's
    /// mirror ray with the transmitted one kept pending); false when the branch ends.
    /// Inline: it runs once per lane and bounce, in shadeBatch's lane clones.
    inline bool continueLane(PathLane& lane, Ray& next, RayCounts& counts) const;
    /// continueLane beyond kExactDepth: one continuation, and Russian roulette.
    bool continueSampled(PathLane& lane, Ray& next, RayCounts& counts) const;
    /// Takes the lane's last pending ray (its state, and the ray into `next`); false when none is left.
    bool resumePending(PathLane& lane, Ray& next) const;

    const Scene& scene_;
    RenderSettings settings_;
    SurfaceShading surfaces_;
    DirectLight direct_;
    bool continues_ = false;  // some material sends rays on (mirror or glass) and the depth allows one
    bool splits_ = false;     // and some is glass, which splits a lane's ray in two (pending rays)
};

}  // namespace penumbra
