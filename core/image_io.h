// Writing the film (and reading images back, for tests and tools). OpenImageIO
// encodes and decodes in memory behind libpenumbra_oiio.so (core/oiio/), loaded
// on the first image; PNG (core/png_encoder.h, compressed by libdeflate) and PFM are written by
// Penumbra itself, so neither loads that module; the bytes are written all or
// nothing by core/atomic_file.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/film.h"

namespace penumbra {

enum class ImageFormat { Exr, Hdr, Pfm, Png, Jpg, Tif };

/// Format from the file extension (case-insensitive); throws
/// Error(InvalidArgument) naming the file for an unknown extension.
ImageFormat imageFormatFromPath(const std::filesystem::path& path);
/// True for formats that store linear floats (EXR, HDR, PFM).
bool isFloatFormat(ImageFormat f);

struct ImageMetadata {
    int spp = 0;
    uint64_t seed = 0;
    double renderSeconds = 0.0;
    std::string software;
};

struct ImageWriteOptions {
    float exposure = 0.f;  // stops; LDR formats only (float formats are written exactly as computed)
    bool aovs = false;     // EXR: extra channels; other formats: a sibling <stem>.aovs.exr
    ImageMetadata metadata;
    // Where the film's pixels lie in the full frame: EXRs record a data window
    // at (dataOriginX, dataOriginY) inside a fullWidth x fullHeight display
    // window; other formats ignore it. 0 x 0 (the default): the whole image.
    int dataOriginX = 0, dataOriginY = 0;
    int fullWidth = 0, fullHeight = 0;
};

/// Writes the film's averaged radiance. Float formats get the linear values
/// unchanged; PNG/JPG/TIF are exposure-scaled, sRGB-encoded and clamped to
/// 8 bits. The whole file is encoded in memory, written to a temporary file in
/// the target folder with checked writes and fsync, and renamed into place
/// (with an AOV sibling, both are complete before either is renamed): a full
/// disk, a file-size limit or an encoder error throws Error(IoError) naming
/// the file and leaves any existing image and no temporary file. No library
/// can end the process (JPEG over 65500 pixels a side is refused up front).
void writeImage(const std::filesystem::path& path, const Film& film, const ImageWriteOptions& options);

/// The bytes writeImage would write for a file of `format`, encoded in
/// memory (with options.aovs, EXR gets the AOV channels; other formats have
/// no room for them: Error(InvalidArgument)). `name` names the image in errors.
std::vector<unsigned char> encodeImage(ImageFormat format, const Film& film, const ImageWriteOptions& options,
                                       const std::string& name);

/// Throws Error(InvalidArgument/IoError) if `path` cannot be written (folder
/// missing or not writable, unknown format). Used to check options before rendering.
void checkWritable(const std::filesystem::path& path);

/// An image read back as floats (linear for float formats, 0..1 for 8-bit ones).
struct ImageData {
    int width = 0, height = 0, channels = 0;
    std::vector<std::string> channelNames;
    std::vector<float> pixels;  // interleaved, row 0 on top
    std::vector<std::pair<std::string, std::string>> attributes;
    float at(int x, int y, int c) const { return pixels[(size_t(y) * width + x) * channels + c]; }
};
/// Throws Error(IoError) naming the file.
ImageData readImage(const std::filesystem::path& path);

/// sRGB transfer functions: linear -> encoded (clamps to [0, 1]) and
/// encoded -> linear (for values in [0, 1]).
float linearToSrgb(float v);
float srgbToLinear(float v);

}  // namespace penumbra
