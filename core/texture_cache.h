// Filtered lookups into the scene's textures. Every texture is decoded
// completely when the cache is built (through the image module, from one open
// descriptor per file or from the bytes of an image inside a model file) and
// MIP-mapped here; lookups never touch a file.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/color.h"
#include "core/log.h"
#include "core/material.h"
#include "core/math.h"
#include "core/texture_source.h"

namespace penumbra {

/// How much memory the decoded textures of one cache may take, MIP levels
/// included. Checked against each image's header before its pixels are decoded.
struct TextureBudget {
    uint64_t maxBytes = uint64_t(1) << 30;  // 1 GiB: a 16k x 12k RGB 8-bit texture with its MIP levels
};

/// A filtered texel: linear RGB and alpha (1 where the image has none).
struct Rgba {
    Rgb rgb{1.f};
    float a = 1.f;
};

class TextureCache {
public:
    /// Decodes every texture of `sources` (Scene::textures): an image's bytes
    /// when it has them, else the loader's descriptor (read with pread only,
    /// never closed, the name never reopened), else the file `name`, opened
    /// here once. A texture that cannot be read (missing, not a regular file,
    /// corrupt, truncated, or over what is left of `budget`, embedded images
    /// included) is disabled with one warning naming it, so nothing fails
    /// later during rendering. Nothing of `sources` is used after the
    /// constructor returns.
    TextureCache(const std::vector<TextureSource>& sources, const Logger& log, TextureBudget budget = {});
    ~TextureCache();
    TextureCache(const TextureCache&) = delete;
    TextureCache& operator=(const TextureCache&) = delete;

    /// Linear RGB of texture `texture` at `uv`, trilinearly filtered over a
    /// square footprint `footprint` wide in uv units (0: the finest level).
    /// OBJ convention: v points up the image; the texture repeats outside
    /// [0,1]. sRGB-encoded texels are linearised before they are filtered
    /// or averaged into MIP levels (8-bit ones keep their codes); grey
    /// images give grey. Rgb(1) for a negative or disabled texture or a
    /// non-finite uv. Thread-safe.
    Rgb lookup(int texture, Vec2f uv, float footprint) const;

    /// What a material's texture slot reads at texture coordinates `uv` (of
    /// the slot's uv set, OBJ's convention), through the slot's transform,
    /// wrap modes and filter, with `footprint` as for lookup: linear RGB (sRGB
    /// decoded where the texture is sRGB) and alpha. Rgba{} (white, opaque)
    /// for an unused slot, a disabled texture or a non-finite uv.
    Rgba sample(const TextureRef& slot, Vec2f uv, float footprint) const;
    /// The slot's channel (TextureRef::channel) as sample reads it: one value
    /// of a linear texture (metallic, roughness, an opacity map); channel 3
    /// is the alpha channel, or the first where the image has none (MTL's
    /// matte channel); 1 where sample gives Rgba{}.
    float sampleChannel(const TextureRef& slot, Vec2f uv, float footprint) const;
    /// A tangent-space normal map's unit normal (2 RGB - 1, X and Y times
    /// `scale`, as glTF defines it); (0, 0, 1) where sample gives Rgba{}.
    Vec3f sampleNormal(const TextureRef& slot, Vec2f uv, float footprint, float scale) const;
    /// A height map's unit normal in the same tangent space (x along +u, y
    /// along +v): the slot's channel (sampleChannel) is the height, and its
    /// rise per texel of the full-resolution image, stepping along u and
    /// along v, times `scale` is the surface's slope (the convention of
    /// height maps drawn for normal-map converters: it does not depend on
    /// the surface's size). Central differences one texel, or `footprint`
    /// where wider, to each side; (0, 0, 1) where sample gives Rgba{}.
    Vec3f sampleHeightNormal(const TextureRef& slot, Vec2f uv, float footprint, float scale) const;

    /// Number of textures (enabled or not).
    size_t size() const;
    /// Whether `texture` was decoded and is used by lookups.
    bool enabled(int texture) const;
    /// Whether `texture` has an alpha channel with any texel below 1 (so
    /// alpha it lends a material can hide anything).
    bool hasTransparency(int texture) const;
    /// Bytes held by the decoded textures and their MIP levels.
    uint64_t memoryBytes() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra
