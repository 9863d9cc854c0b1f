// Sample keys and the dimensions of the random numbers every integrator
// draws: each number is a pure function of (seed, pixel, camera sample index,
// dimension), so images do not depend on thread count, tile size or batch
// (docs/rendering.md, "Sampling").
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/hash.h"
#include "core/owen_sobol.h"

namespace penumbra {

/// The dimensions of the pixel sets: the position in the pixel and on the lens.
inline constexpr uint32_t kPixelDimension = 0;
inline constexpr uint32_t kLensDimension = 1;
/// The first dimension of the shading points' numbers (VertexDimensions).
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

/// The points that camera samples keys[0 .. n) draw in dimension `dim`, one
/// each: dimensionSequence(keys[l], dim).point(keys[l].index) as x[l], y[l],
/// the same values, as loops over the lanes (OwenSobol2D::pointLanes). For a
/// batch's lanes that each take one sample at a shading point.
inline void dimensionPointLanes(const SampleKey* keys, size_t n, uint32_t dim, float (&x)[OwenSobol2D::kLanes],
                                float (&y)[OwenSobol2D::kLanes]) {
    constexpr size_t W = OwenSobol2D::kLanes;
    alignas(64) uint64_t lanesKey[W];
    alignas(64) uint32_t index[W];
    alignas(64) const uint32_t first[W] = {};
    for (size_t l = 0; l < W; ++l) {
        lanesKey[l] = l < n ? dimensionKey(keys[l], dim) : 0;
        index[l] = l < n ? keys[l].index : 0;
    }
    OwenSobol2D::pointLanes(lanesKey, index, 1, first, x, y);
}

/// The one layout of the dimensions a shading point draws from, for every
/// integrator: the shading points at bounce depth d (the camera ray's hit is
/// depth 0, a path's next vertex or a mirror's reflection depth 1, ...) own
/// the block of lights + 2 dimensions that starts at
/// kFirstLightDimension + d * (lights + 2):
///   light(j)      the light samples of light j, where every light is sampled;
///   pickedLights  the light samples that pick their light (LightPicker):
///                 x picks the light and, rescaled, is the sample's x;
///   bsdf          the BSDF samples: the direct-light estimator's own under
///                 MIS, or the one that continues a path (x picks the lobe
///                 and, rescaled, is the sample's x).
struct VertexDimensions {
    VertexDimensions(int depth, size_t lights)
        : base(kFirstLightDimension + uint32_t(depth) * (uint32_t(lights) + 2)), lights(uint32_t(lights)) {}
    uint32_t light(size_t j) const { return base + uint32_t(j); }
    uint32_t pickedLights() const { return base + lights; }
    uint32_t bsdf() const { return base + lights + 1; }

    uint32_t base, lights;
};

/// The numbers of the random decisions of one branch of camera sample `key`
/// at bounce depth `depth`: `survive` decides Russian roulette, `pick` which
/// continuation a surface that splits a ray follows. A hash of (pixel key,
/// sample index, depth, branch), not points of a sequence: the decisions need
/// no dimensions of the layout, and the branches a Whitted ray splits into
/// (each numbered `branch`) get numbers of their own.
struct BranchNumbers {
    float survive, pick;
};
inline BranchNumbers branchNumbers(const SampleKey& key, int depth, uint32_t branch) {
    const uint64_t h = hashValues({key.pixelKey, key.index, uint64_t(uint32_t(depth)), branch});
    return {toUnitFloat(h), toUnitFloat(h << 24)};
}

}  // namespace penumbra
