// A decoded linear RGB image held in memory (the environment light's lat-long
// map), and its decoder: through the image module (core/oiio/), from an open
// descriptor, with the texture budget checked against the header first.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/color.h"
#include "core/texture_cache.h"

namespace penumbra {

/// Linear RGB pixels, row 0 on top.
struct RgbImage {
    int width = 0, height = 0;
    std::vector<Rgb> pixels;  // width * height
    const Rgb& at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
};

/// What decodeRgbImage cleaned up (the environment warns about it once).
struct RgbImageFixups {
    size_t nonFinite = 0;  // NaN/Inf channel values set to 0
    size_t negative = 0;   // negative channel values set to 0
};

/// Decodes the image in `fd` (a regular file, read with pread only, neither
/// closed nor reopened; `name` picks the reader by extension and names the file
/// in errors). Grey images give grey RGB; 8-bit (sRGB-encoded) images are
/// linearised; float images (EXR, HDR, PFM) are taken as linear radiance.
/// Throws Error(IoError) "<name>: cannot read image (why)" for a file that is
/// not a regular file, not an image, truncated or corrupt, and for one whose
/// header says it decodes to more than budget.maxBytes.
RgbImage decodeRgbImage(const std::string& name, int fd, const TextureBudget& budget, RgbImageFixups* fixups = nullptr);

/// The same, opening `path` itself, once (without blocking on a FIFO; only
/// regular files are read). For images named in code, with no loader descriptor.
RgbImage decodeRgbImage(const std::string& path, const TextureBudget& budget, RgbImageFixups* fixups = nullptr);

}  // namespace penumbra
