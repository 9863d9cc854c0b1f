// Linear values to 8-bit sRGB codes for PNG, JPEG and TIFF output.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace penumbra {

/// The 8-bit code of a linear value: round(255 * linearToSrgb(v)), the
/// definition Srgb8 reproduces.
uint8_t srgb8Code(float v);

/// srgb8Code by 255 thresholds found once per image: where a code starts is
/// searched in 8 branch-free comparisons instead of a pow per channel, which
/// made encoding an 8-bit image a visible part of a short render. The codes
/// are srgb8Code's bit for bit: each threshold is the smallest float with the
/// next code, found by bisection over the floats with srgb8Code itself, which
/// is non-decreasing (checked over every float in [0, 1]). Negative values
/// and NaN give 0, values above 1 give 255.
class Srgb8 {
public:
    Srgb8();
    uint8_t operator()(float v) const { return uint8_t(search(thresholds_.data(), v)); }
    /// codes[i] = (*this)(values[i]) for i < n, as one loop over the values:
    /// it vectorises, the thresholds gathered 8 or 16 values at a time.
    void codes(const float* values, size_t n, uint8_t* codes) const;
    /// The smallest float whose code is `code` (1..255).
    float threshold(unsigned code) const { return thresholds_[code]; }

private:
    // Where v falls among the thresholds t: eight halvings without branches,
    // written out (as a loop of steps they kept codes() from vectorising).
    [[gnu::always_inline]] static int32_t search(const float* t, float v) {
        int32_t code = t[128] <= v ? 128 : 0;
        code += t[code + 64] <= v ? 64 : 0;
        code += t[code + 32] <= v ? 32 : 0;
        code += t[code + 16] <= v ? 16 : 0;
        code += t[code + 8] <= v ? 8 : 0;
        code += t[code + 4] <= v ? 4 : 0;
        code += t[code + 2] <= v ? 2 : 0;
        code += t[code + 1] <= v ? 1 : 0;
        return code;
    }

    std::array<float, 256> thresholds_{};  // [0] is never read: the search starts above it
};

}  // namespace penumbra
