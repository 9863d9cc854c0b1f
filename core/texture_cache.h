// Filtered lookups into the scene's diffuse textures. Every texture is decoded
// completely when the cache is built (through the image module, from one open
// descriptor per file) and MIP-mapped here; lookups never touch a file.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/color.h"
#include "core/log.h"
#include "core/math.h"

namespace penumbra {

/// How much memory the decoded textures of one cache may take, MIP levels
/// included. Checked against each file's header before its pixels are decoded.
struct TextureBudget {
    uint64_t maxBytes = uint64_t(1) << 30;  // 1 GiB: a 16k x 12k RGB 8-bit texture with its MIP levels
};

class TextureCache {
public:
    /// Decodes every texture of `paths` (Scene::textures). `fds[i] >= 0` is an
    /// open descriptor of texture i (the loader's, opened after its path
    /// check): it is read with pread only, never closed, and the path is never
    /// reopened (`paths[i]` then only names the file in messages). Without one,
    /// the cache opens `paths[i]` itself, once. A texture that cannot be read
    /// (missing, not a regular file, corrupt, truncated, or over what is left
    /// of `budget`) is disabled with one warning naming the file, so nothing
    /// fails later during rendering. The descriptors are not used after the
    /// constructor returns.
    TextureCache(const std::vector<std::string>& paths, const Logger& log, const std::vector<int>& fds = {},
                 TextureBudget budget = {});
    ~TextureCache();
    TextureCache(const TextureCache&) = delete;
    TextureCache& operator=(const TextureCache&) = delete;

    /// Linear RGB of texture `texture` at `uv`, trilinearly filtered over a
    /// square footprint `footprint` wide in uv units (0: the finest level).
    /// OBJ convention: v points up the image; the texture repeats outside
    /// [0,1]. 8-bit (sRGB-encoded) images are linearised after filtering;
    /// grey images give grey. Rgb(1) for a negative or disabled texture or a
    /// non-finite uv. Thread-safe.
    Rgb lookup(int texture, Vec2f uv, float footprint) const;

    /// Number of textures (enabled or not).
    size_t size() const;
    /// Whether `texture` was decoded and is used by lookup().
    bool enabled(int texture) const;
    /// Bytes held by the decoded textures and their MIP levels.
    uint64_t memoryBytes() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra
