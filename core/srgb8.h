// Linear values to 8-bit sRGB codes for PNG, JPEG and TIFF output.
#pragma once

#include <array>
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
    uint8_t operator()(float v) const {
        unsigned code = 0;
        for (unsigned step = 128; step != 0; step >>= 1) code += thresholds_[code + step] <= v ? step : 0;
        return uint8_t(code);
    }
    /// The smallest float whose code is `code` (1..255).
    float threshold(unsigned code) const { return thresholds_[code]; }

private:
    std::array<float, 256> thresholds_{};  // [0] is never read: the search starts above it
};

}  // namespace penumbra
