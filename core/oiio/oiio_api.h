// The table of functions that libpenumbra_oiio.so (core/oiio/oiio_module.cpp,
// the one file that includes OpenImageIO) exports to libpenumbra. Only
// standard types cross it, so libpenumbra and its hosts never link
// OpenImageIO's ~260 shared libraries: a process pays for them (time and about
// 125 MiB resident) on its first image read or written, and a process that
// renders into memory or to PFM never does. Both sides are built together, so
// the table is versioned only to catch a stale module from another build.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::oiio {

inline constexpr int kApiVersion = 2;
/// The symbol libpenumbra looks up with dlsym; its type is `const Api* ()`.
inline constexpr const char* kEntryPoint = "penumbra_oiio_api";

enum class PixelType : int { U8, F32 };

/// One metadata entry of an encoded image.
struct Attribute {
    enum class Kind : int { Int, Float, String };
    std::string name;
    Kind kind = Kind::String;
    int i = 0;
    float f = 0.f;
    std::string s;
};

/// Pixels to encode: interleaved, row 0 on top.
struct EncodeRequest {
    std::string format;  // OpenImageIO's format name: "openexr", "hdr", "png", "jpeg", "tiff"
    int width = 0, height = 0, channels = 0;
    PixelType type = PixelType::F32;
    const void* pixels = nullptr;
    std::vector<std::string> channelNames;  // empty: OpenImageIO's defaults (R, G, B)
    std::vector<Attribute> attributes;
    // EXR only: the pixels are the data window at (dataX, dataY) of a
    // fullWidth x fullHeight display window (a crop that knows its place); 0 x 0: the whole image.
    int dataX = 0, dataY = 0, fullWidth = 0, fullHeight = 0;
};

/// What a decoder found; pixels are filled only when the image fits the budget.
struct Decoded {
    int width = 0, height = 0, channels = 0;  // channels of the file
    int bytesPerChannel = 0;                  // as stored in the file
    bool floatData = false;                   // the file stores floating-point values
    std::string colorSpace;                   // oiio:ColorSpace, may be empty
    std::vector<std::string> channelNames;
    std::vector<std::pair<std::string, std::string>> attributes;
    uint64_t fileBytes = 0;                   // set when the file itself is over the budget (no header read)
    int decodedChannels = 0;                  // channels in `pixels`
    PixelType type = PixelType::F32;          // type of `pixels`
    std::vector<unsigned char> pixels;        // interleaved, row 0 on top
};

enum class Status : int { Ok, Failed, OverBudget };

struct DecodeRequest {
    int fd = -1;             // read with pread only; neither closed nor reopened
    const unsigned char* bytes = nullptr;  // or the encoded image in memory (then fd is not read)
    size_t size = 0;
    std::string name;        // the file's name: picks the reader by extension, names it in errors
    int maxChannels = 0;     // decode channels [0, min(file, maxChannels)); 0: all
    bool floatPixels = true; // false: 8-bit files decode as U8, others as F32
    uint64_t maxBytes = 0;   // decoded size allowed (width*height*channels*bytes as decoded); 0: no limit
    bool headerOnly = false; // stop after the header (and the budget check): Ok with no pixels
};

struct Api {
    int version = kApiVersion;
    /// Encodes into `out` (memory, so no file system error can reach the
    /// libraries). False with `error` on failure; never throws. The caller
    /// keeps JPEG within 65500 pixels a side (libjpeg exits the process beyond).
    bool (*encode)(const EncodeRequest& request, std::vector<unsigned char>& out, std::string& error) noexcept;
    /// Reads the file into memory, or takes the request's bytes (OverBudget
    /// with fileBytes if they alone exceed maxBytes + 1 MiB), reads the header, checks the budget before
    /// any pixel is decoded (OverBudget, header fields filled), then decodes
    /// the whole image; a truncated or corrupt file is Failed with the
    /// library's message.
    Status (*decode)(const DecodeRequest& request, Decoded& out, std::string& error) noexcept;
};

}  // namespace penumbra::oiio
