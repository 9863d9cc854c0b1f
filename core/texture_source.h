// Where a texture's encoded image comes from: a file the loader opened (read
// by descriptor, never reopened by name), bytes inside a model file (a GLB
// buffer view, a data: URI), or a path named in code (opened once, when the
// scene is prepared), and how its values are to be read.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace penumbra {

/// How a texture's RGB values relate to linear values.
enum class TextureColorSpace : uint8_t {
    FromFile,  ///< as the file says (oiio:ColorSpace); without a word, 8-bit images are sRGB (OBJ, JSON, API)
    Srgb,      ///< sRGB-encoded whatever the file says (glTF base colour and emissive)
    Linear,    ///< values as stored (glTF metallic-roughness, normal and transmission maps; MTL bump, roughness, ...)
};

struct TextureSource {
    /// The file's path, or "<model file>#image<N>" for an image inside a model
    /// file: names it in messages; with colorSpace, what makes two materials share one texture.
    std::string name;
    TextureColorSpace colorSpace = TextureColorSpace::FromFile;
    /// The loader's open descriptor of the file (read with pread only), kept
    /// open by `file` (an InputFile, core/io/input_file.h); -1: none.
    int fd = -1;
    std::shared_ptr<const void> file;
    /// The encoded image itself (an image inside a model file); null: read the file.
    std::shared_ptr<const std::vector<unsigned char>> bytes;
};

}  // namespace penumbra
