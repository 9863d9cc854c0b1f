// The one interface every ray query goes through: camera, shadow and mirror
// rays alike. Two implementations: Embree (the product) and a naive O(N) loop
// (the reference and the benchmark baseline). docs/accelerators.md describes
// both, their rules and their agreement.
#pragma once

#include <penumbra/types.hpp>

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <algorithm>
#include <string>

#include "accel/alpha_test.h"
#include "accel/shape_bounds.h"
#include "core/hit.h"
#include "core/ray.h"
#include "core/ray_lanes.h"
#include "core/scratch_array.h"
#include "core/scene.h"

namespace penumbra {

class TextureCache;

/// The thin answer of a closest-hit query, before Scene::completeHit.
struct PrimIntersection {
    PrimRef ref;
    float t;
    float u, v;
};

using BuildQuality = pnb::BuildQuality;  // api/include/penumbra/types.hpp
using AcceleratorKind = pnb::AcceleratorKind;

class Accelerator {
public:
    virtual ~Accelerator() = default;

    /// Closest hit in (ray.tnear, ray.tfar]; nullopt is a miss. Invalid rays
    /// (see isValidRay) are misses and are counted. Thread-safe.
    std::optional<Hit> intersect(const Ray& ray) const {
        auto pi = intersectPrim(ray);
        if (!pi) return std::nullopt;
        return scene_.completeHit(ray, pi->ref, pi->t, pi->u, pi->v);
    }

    /// Thin closest hit (no surface data); what the agreement checks compare.
    virtual std::optional<PrimIntersection> intersectPrim(const Ray& ray) const = 0;

    /// True when anything lies in (ray.tnear, ray.tfar). Invalid rays count
    /// as unoccluded (and are counted). Thread-safe.
    virtual bool occluded(const Ray& ray) const = 0;

    /// Batched queries: the same answers as the single-ray calls, for
    /// rays.size() rays (any count). Embree answers them as 4/8/16-wide
    /// packets, which beat single rays for coherent rays (camera rays of a
    /// pixel block, one shading point's light samples). coherent: the caller
    /// knows that consecutive rays run close together (the mirror rays of a
    /// pixel block), so that Embree may trace a packet as one frustum, as it
    /// does intersectLanes' camera rays (same primitives; t may differ from
    /// the single-ray answer by a few ulps, as there).
    ///
    /// leaving (empty, or one per ray): the index in Scene::meshes of the
    /// convex mesh ray i leaves from its outer side and away from it
    /// (Scene::convexMeshOf, and the ray's direction above the surface), or
    /// -1. Such a ray cannot meet that mesh again, so a query may leave the
    /// mesh out for it: in a scene of few shapes a packet whose rays all
    /// leave what Embree holds skips Embree's call. A hint: the answers are
    /// the same with or without it.
    virtual void intersectPrimBatch(std::span<const Ray> rays, std::span<std::optional<PrimIntersection>> out,
                                    bool coherent = false, std::span<const int32_t> leaving = {}) const {
        (void)coherent;
        (void)leaving;
        for (size_t i = 0; i < rays.size(); ++i) out[i] = intersectPrim(rays[i]);
    }
    /// out[i] = 1 when rays[i] is occluded, else 0.
    virtual void occludedBatch(std::span<const Ray> rays, std::span<uint8_t> out) const {
        for (size_t i = 0; i < rays.size(); ++i) out[i] = occluded(rays[i]) ? 1 : 0;
    }
    /// out[l] = 1 where lane l holds a ray (rays.active[l]) and it is
    /// occluded, else 0: occluded() for rays given as lanes. Embree takes the
    /// lanes' arrays as a 16-wide packet as they are. leaving (null, or 16):
    /// the hints of intersectPrimBatch.
    virtual void occludedLanes(const RayLanes& rays, uint8_t* out, const int32_t* leaving = nullptr) const {
        (void)leaving;
        for (int l = 0; l < RayLanes::kWidth; ++l) out[l] = rays.active[l] && occluded(rays.ray(l)) ? 1 : 0;
    }
    /// intersectPrimBatch followed by Scene::completeHit.
    void intersectBatch(std::span<const Ray> rays, std::span<std::optional<Hit>> out, bool coherent = false,
                        std::span<const int32_t> leaving = {}) const {
        constexpr size_t kChunk = 16;  // one packet: the renderer's batches are 16 rays
        EmptyOptionals<PrimIntersection, kChunk> thin;
        for (size_t b = 0; b < rays.size(); b += kChunk) {
            const size_t n = std::min(kChunk, rays.size() - b);
            intersectPrimBatch(rays.subspan(b, n), std::span(thin.data(), n), coherent,
                               leaving.empty() ? leaving : leaving.subspan(b, n));
            completeHits(rays.data() + b, thin.data(), out.data() + b, n);
        }
    }

    /// Closest hits of the rays of the active lanes (RayLanes::active), as
    /// intersect() finds them, into the first out.size() (at most 16)
    /// elements; nullopt for idle lanes. Embree takes the lanes' arrays as a
    /// 16-wide packet as they are: the renderer's camera rays. The rays are
    /// also written one by one into rayOut (out.size() of them), the form the
    /// integrators keep: the hits' completion needs that form too.
    void intersectLanes(const RayLanes& rays, std::span<std::optional<Hit>> out, Ray* rayOut) const {
        EmptyOptionals<PrimIntersection, RayLanes::kWidth> thin;
        intersectPrimLanes(rays, thin.data());
        // Every lane's Ray is written before the first hit is completed: a Ray
        // written just before the call that reads it stalls the reads
        // (docs/accelerators.md).
        rays.rays(int(out.size()), rayOut);
        completeHits(rayOut, thin.data(), out.data(), out.size());
    }
    /// intersectPrim() for each active lane's ray, nullopt for idle lanes (all 16 written).
    virtual void intersectPrimLanes(const RayLanes& rays, std::optional<PrimIntersection>* out) const {
        for (int l = 0; l < RayLanes::kWidth; ++l)
            out[l] = rays.active[l] ? intersectPrim(rays.ray(l)) : std::nullopt;
    }

    /// The accelerator of `scene`, a copy of this one's scene whose instances
    /// may have moved (and whose materials and lights may differ): what did
    /// not move is shared, not rebuilt, unless the edited materials change
    /// which geometry can cut out (AlphaTest::sameGeometries). `buffers` keeps
    /// alive the scene whose mesh buffers the shared parts read.
    virtual std::unique_ptr<Accelerator> edited(const Scene& scene, std::shared_ptr<const void> buffers) const = 0;

    virtual std::string name() const = 0;

    /// Bytes held by the acceleration structure itself (not the scene arrays).
    virtual size_t memoryBytes() const = 0;

    /// Rays rejected by isValidRay so far.
    uint64_t invalidRayCount() const { return invalidRays_.load(std::memory_order_relaxed); }

    const Scene& scene() const { return scene_; }

    /// The shapes' padded bounds, for telling that whole sets of shadow rays
    /// meet nothing (ShapeBounds::segmentsClear). Built once with the
    /// accelerator, not per render pass: a mesh's box is a pass over its triangles.
    const ShapeBounds& shapeBounds() const { return shapeBounds_; }

    /// Whether the queries use `leaving` hints (intersectPrimBatch): Embree's,
    /// in a scene of few shapes with a convex mesh. Elsewhere a caller need
    /// not make them.
    bool takesLeavingHints() const { return takesLeavingHints_; }

    /// The alpha cutouts every query applies (accel/alpha_test.h).
    const AlphaTest& alphaTest() const { return alpha_; }

protected:
    /// `textures` (may be null) are what the alpha cutouts read.
    Accelerator(const Scene& scene, std::shared_ptr<const TextureCache> textures)
        : scene_(scene), textures_(textures), alpha_(scene, std::move(textures)), shapeBounds_(scene) {}
    /// completeThin for the n <= 16 hits of a batch. In a scene with meshes,
    /// those of a few lanes on one mesh are completed over the lanes together
    /// (completeBatch, completeTriangleHitLanes); elsewhere the batch takes no detour.
    void completeHits(const Ray* rays, const std::optional<PrimIntersection>* thin, std::optional<Hit>* out,
                      size_t n) const {
        if (!scene_.meshes.empty()) return completeBatch(rays, thin, out, n);
        for (size_t i = 0; i < n; ++i) completeThin(rays[i], thin[i], out[i]);
    }
    void completeBatch(const Ray* rays, const std::optional<PrimIntersection>* thin, std::optional<Hit>* out,
                       size_t n) const;
    /// The batch forms' one rule: a thin hit completed in place (Scene::completeHit), a miss reset.
    void completeThin(const Ray& ray, const std::optional<PrimIntersection>& thin, std::optional<Hit>& out) const {
        if (thin)
            scene_.completeHit(ray, thin->ref, thin->t, thin->u, thin->v, out.emplace());
        else
            out.reset();
    }
    bool acceptRay(const Ray& r) const {
        if (isValidRay(r)) return true;
        countInvalidRays(1);
        return false;
    }
    void countInvalidRays(uint64_t n) const { invalidRays_.fetch_add(n, std::memory_order_relaxed); }

    const Scene& scene_;
    std::shared_ptr<const TextureCache> textures_;
    AlphaTest alpha_;
    bool takesLeavingHints_ = false;  // set by an accelerator that uses them

private:
    ShapeBounds shapeBounds_;
    mutable std::atomic<uint64_t> invalidRays_{0};
};

/// Builds an Embree BVH over a finalized scene. The scene must outlive the
/// accelerator (its mesh buffers are shared with Embree, not copied).
/// `textures` (the scene's, or null: texture alpha counts as 1) are what the
/// alpha cutouts read. Throws Error(ErrorCode::Embree) when Embree reports an error.
std::unique_ptr<Accelerator> makeEmbreeAccelerator(const Scene& scene, BuildQuality quality = BuildQuality::High,
                                                   std::shared_ptr<const TextureCache> textures = {});

/// The O(N) reference: tests every primitive with the same routines.
std::unique_ptr<Accelerator> makeNaiveAccelerator(const Scene& scene,
                                                  std::shared_ptr<const TextureCache> textures = {});

/// The accelerator of that kind; throws Error(InvalidArgument) for a value that is none.
std::unique_ptr<Accelerator> makeAccelerator(AcceleratorKind kind, const Scene& scene,
                                             BuildQuality quality = BuildQuality::High,
                                             std::shared_ptr<const TextureCache> textures = {});

}  // namespace penumbra
