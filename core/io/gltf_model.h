// A glTF 2.0 file (.gltf with what it references, or .glb) as tinygltf reads
// it: the one include point of tinygltf (gltf_document.cpp compiles its
// parser from the same header). Every file is read through the path policy
// and opened once (input_file.h), and images are not decoded here: their
// bytes (or, for image files, their open descriptors) go on to the texture
// cache, which decodes them through the image module when the scene is prepared.
#pragma once

// Penumbra decodes images itself and opens files through the path policy:
// tinygltf's stb image callbacks and file functions are left out.
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_FS
#include <tiny_gltf.h>

#include <filesystem>
#include <string>
#include <vector>

#include "core/io/input_file.h"
#include "core/io/load_options.h"
#include "core/log.h"
#include "core/texture_source.h"

namespace penumbra {

/// What readGltfFile read.
struct GltfFile {
    std::filesystem::path path;
    tinygltf::Model model;
    /// One per model.images entry: where its encoded bytes are (name empty:
    /// the image could not be read, and has been warned about).
    std::vector<TextureSource> images;
    /// "<file>: " and, for messages about one part, what names it.
    std::string where(const std::string& part = "") const { return path.string() + (part.empty() ? "" : ": " + part); }
};

/// Reads `file` as glTF 2.0 (binary when it starts with "glTF"). Throws
/// Error naming the file: ParseError for what is not glTF 2.0 or is
/// malformed (a binary container whose chunks do not fit, JSON nested deeper
/// than any glTF needs, a buffer or view that does not fit what it views, an
/// extension it requires that Penumbra does not read), the error of a
/// referenced file that cannot be read or lies outside the allowed folders.
/// A missing or unreadable image is a warning.
GltfFile readGltfFile(const InputFile& file, const LoadOptions& options, const Logger& log);

}  // namespace penumbra
