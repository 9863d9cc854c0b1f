#include "core/srgb8.h"

#include <bit>
#include <cmath>
#include <limits>

#include "core/image_io.h"
#include "core/lane_clones.h"

namespace penumbra {

uint8_t srgb8Code(float v) { return uint8_t(std::lround(linearToSrgb(v) * 255.f)); }

Srgb8::Srgb8() {
    // Non-negative floats order as their bit patterns, so bisect on the bits.
    const uint32_t oneBits = std::bit_cast<uint32_t>(1.f);
    thresholds_[0] = 0.f;
    for (unsigned code = 1; code < 256; ++code) {
        uint32_t lo = 0, hi = oneBits;  // srgb8Code(1) == 255 >= code
        while (lo < hi) {
            const uint32_t mid = lo + (hi - lo) / 2;
            if (srgb8Code(std::bit_cast<float>(mid)) >= code) hi = mid;
            else lo = mid + 1;
        }
        thresholds_[code] = std::bit_cast<float>(lo);
    }
    thresholds_[256] = std::numeric_limits<float>::infinity();
    // Each bucket's first code: the thresholds at or below its smallest float.
    firstCodes_.resize(kBuckets);
    unsigned code = 0;
    for (size_t b = 0; b < kBuckets; ++b) {
        const float smallest = std::bit_cast<float>(uint32_t(b) << kBucketShift);
        while (code < 255 && thresholds_[code + 1] <= smallest) ++code;
        firstCodes_[b] = int32_t(code);
    }
}

PENUMBRA_LANE_CLONES void Srgb8::codes(const float* values, size_t n, uint8_t* codes) const {
    // 64 values at a time into 32-bit codes, then narrowed: storing bytes
    // directly kept the loop from vectorising.
    const int32_t* first = firstCodes_.data();
    const float* t = thresholds_.data();
    constexpr size_t kBlock = 64;
    for (size_t start = 0; start < n; start += kBlock) {
        const size_t m = n - start < kBlock ? n - start : kBlock;
        alignas(64) int32_t block[kBlock];
        for (size_t i = 0; i < m; ++i) block[i] = search(first, t, values[start + i]);
        for (size_t i = 0; i < m; ++i) codes[start + i] = uint8_t(block[i]);
    }
}

}  // namespace penumbra
