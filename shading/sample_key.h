// Sample keys and the dimensions of the random numbers every integrator
// draws: each number is a pure function of (seed, pixel, camera sample index,
// dimension), so images do not depend on thread count, tile size or batch
// (docs/rendering.md, "Sampling").
#pragma once

#include <cstdint>

#include "core/owen_sobol.h"

namespace penumbra {

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

}  // namespace penumbra
