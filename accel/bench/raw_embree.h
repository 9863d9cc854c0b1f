// The raw Embree ceiling for the benchmark: the scene's triangles in an Embree
// scene of their own, queried with rtcIntersect1/rtcOccluded1 (and 4/8/16-wide
// packets) and nothing else: no PrimRef mapping, no planes, no Scene::completeHit.
// Comparing the renderer's rates with these shows its overhead per ray.
// This header is std-only; accel/ stays the only module that includes Embree.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

#include "accel/accelerator.h"
#include "core/ray.h"
#include "core/scene.h"

namespace penumbra {

/// The thin answer of one raw closest-hit query: mesh = index into
/// Scene::meshes (kRawMiss for a miss), prim = triangle index.
struct RawHit {
    uint32_t mesh;
    uint32_t prim;
    float t;
};
inline constexpr uint32_t kRawMiss = 0xffffffffu;

/// How the raw scene is built. The defaults match the renderer's Embree
/// accelerator (robust traversal, the quality PrepareOptions uses), so the two
/// differ only in what the renderer adds around the queries.
struct RawEmbreeOptions {
    BuildQuality quality = BuildQuality::High;
    bool robust = true;
};

/// An Embree device and scene holding the triangle meshes of a finalized
/// Scene (shared buffers, as the renderer's accelerator does). Analytic shapes
/// are left out: the ceiling is only meaningful for triangle-only scenes
/// (see coversScene()). The Scene must outlive this object.
class RawEmbreeScene {
public:
    /// Builds the device and the BVH. Throws Error(ErrorCode::Embree) when
    /// Embree reports an error.
    explicit RawEmbreeScene(const Scene& scene, const RawEmbreeOptions& options = {});
    ~RawEmbreeScene();
    RawEmbreeScene(const RawEmbreeScene&) = delete;
    RawEmbreeScene& operator=(const RawEmbreeScene&) = delete;

    /// Seconds spent in rtcNewDevice (a fixed cost the renderer pays per accelerator).
    double deviceSeconds() const;
    /// Seconds from rtcNewScene to the end of rtcCommitScene.
    double buildSeconds() const;
    /// Bytes Embree allocated for the scene (its memory monitor), as the
    /// renderer's EmbreeAccelerator::memoryBytes() counts them.
    size_t memoryBytes() const;
    size_t triangleCount() const;
    /// True when the scene holds nothing but triangles, so the raw scene
    /// answers exactly what the renderer's accelerator answers.
    bool coversScene() const;
    /// True when this Embree build traces `width`-wide packets natively
    /// (4, 8 or 16); other widths are emulated by Embree.
    bool nativePacket(int width) const;

    /// rtcIntersect1 for rays[0, count); out[i] receives ray i's answer.
    void intersect1(const Ray* rays, size_t count, RawHit* out) const;
    /// rtcOccluded1 for rays[0, count); out[i] = 1 when ray i is occluded.
    /// Each ray's tfar is used as given.
    void occluded1(const Ray* rays, size_t count, uint8_t* out) const;
    /// The same through rtcIntersect4/8/16 on consecutive groups of `width`
    /// rays (the last group masked). width must be 4, 8 or 16.
    void intersectPackets(int width, const Ray* rays, size_t count, RawHit* out) const;
    /// rtcOccluded4/8/16 on consecutive groups of `width` rays.
    void occludedPackets(int width, const Ray* rays, size_t count, uint8_t* out) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra
