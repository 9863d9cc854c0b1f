// PNG files encoded in memory: 8-bit RGB, the sRGB chunk and text entries, the
// image data compressed by libdeflate (faster than zlib for a smaller
// file: README, "Output"). Penumbra's PNG output goes through here rather than
// OpenImageIO, whose ~260 shared libraries a process would otherwise load
// (about 0.2-0.4 s and 120 MiB) to write one image; reading PNGs stays with
// OpenImageIO.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace penumbra {

/// An 8-bit sRGB image to encode: interleaved RGB, row 0 on top.
struct PngImage {
    int width = 0, height = 0;
    const uint8_t* rgb = nullptr;
    std::span<const std::pair<std::string, std::string>> text;  // tEXt entries (key, value)
    int level = 6;  // libdeflate's compression level, 0 (none) to 12
};

/// The PNG file's bytes, appended to `out`; false with the reason in `error`
/// for what PNG cannot store (an empty or too large image, a text keyword
/// outside PNG's rules) and when memory runs out.
[[nodiscard]] bool encodePng(const PngImage& image, std::vector<unsigned char>& out, std::string& error);

}  // namespace penumbra
