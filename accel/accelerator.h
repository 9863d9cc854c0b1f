// The one interface every ray query goes through: camera, shadow and mirror
// rays alike. Two implementations: Embree (the product) and a naive O(N) loop
// (the reference and the benchmark baseline).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "core/hit.h"
#include "core/ray.h"
#include "core/scene.h"

namespace penumbra {

/// The thin answer of a closest-hit query, before Scene::completeHit.
struct PrimIntersection {
    PrimRef ref;
    float t;
    float u, v;
};

enum class BuildQuality { Low, Medium, High };

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

    virtual std::string name() const = 0;

    /// Bytes held by the acceleration structure itself (not the scene arrays).
    virtual size_t memoryBytes() const = 0;

    /// Rays rejected by isValidRay so far.
    uint64_t invalidRayCount() const { return invalidRays_.load(std::memory_order_relaxed); }

    const Scene& scene() const { return scene_; }

protected:
    explicit Accelerator(const Scene& scene) : scene_(scene) {}
    bool acceptRay(const Ray& r) const {
        if (isValidRay(r)) return true;
        invalidRays_.fetch_add(1, std::memory_order_relaxed);
        return false;
    }

    const Scene& scene_;

private:
    mutable std::atomic<uint64_t> invalidRays_{0};
};

/// Builds an Embree BVH over a finalized scene. The scene must outlive the
/// accelerator (its mesh buffers are shared with Embree, not copied).
/// Throws Error(ErrorCode::Embree) when Embree reports an error.
std::unique_ptr<Accelerator> makeEmbreeAccelerator(const Scene& scene, BuildQuality quality = BuildQuality::High);

/// The O(N) reference: tests every primitive with the same routines.
std::unique_ptr<Accelerator> makeNaiveAccelerator(const Scene& scene);

/// "embree" or "naive" (case-sensitive); throws Error(InvalidArgument) otherwise.
std::unique_ptr<Accelerator> makeAccelerator(const std::string& name, const Scene& scene,
                                             BuildQuality quality = BuildQuality::High);

}  // namespace penumbra
