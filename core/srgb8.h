// Linear values to 8-bit sRGB codes for PNG, JPEG and TIFF output.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace penumbra {

/// The 8-bit code of a linear value: round(255 * linearToSrgb(v)), the
/// definition Srgb8 reproduces.
uint8_t srgb8Code(float v);

/// srgb8Code by 255 thresholds found once per image: where a code starts is
/// looked up instead of a pow per channel, which made encoding an 8-bit image
/// a visible part of a short render. The codes are srgb8Code's bit for bit:
/// each threshold is the smallest float with the next code, found by
/// bisection over the floats with srgb8Code itself, which is non-decreasing
/// (checked over every float in [0, 1]). Negative values and NaN give 0,
/// values above 1 give 255.
class Srgb8 {
public:
    Srgb8();
    uint8_t operator()(float v) const { return uint8_t(search(firstCodes_.data(), thresholds_.data(), v)); }
    /// codes[i] = (*this)(values[i]) for i < n, as one loop over the values:
    /// it vectorises, the table and the thresholds gathered 8 or 16 values at a time.
    void codes(const float* values, size_t n, uint8_t* codes) const;
    /// The smallest float whose code is `code` (1..255).
    float threshold(unsigned code) const { return thresholds_[code]; }

private:
    // The floats of [0, 1] in buckets of 2^16 by their bit patterns: a bucket
    // spans under 0.8% of its values, and consecutive thresholds lie at least
    // 0.9% apart (near 1, where v grows as code^2.4), so at most one code
    // starts inside a bucket. A value's code is its bucket's first code, plus
    // one past that threshold: two loads where a binary search took eight.
    static constexpr int kBucketShift = 16;
    static constexpr size_t kBuckets = (0x3F800000u >> kBucketShift) + 1;  // through the bucket of 1.0f

    [[gnu::always_inline]] static int32_t search(const int32_t* first, const float* t, float v) {
        const float c = v > 0.f ? (v < 1.f ? v : 1.f) : 0.f;  // NaN fails the first test: 0
        const int32_t code = first[std::bit_cast<uint32_t>(c) >> kBucketShift];
        return code + int32_t(t[code + 1] <= c);
    }

    std::array<float, 257> thresholds_{};  // [0] 0 and [256] infinity: never met
    // 64 KiB, on the heap: an Srgb8 is a local of threads with small stacks (the preview's server).
    std::vector<int32_t> firstCodes_;
};

}  // namespace penumbra
