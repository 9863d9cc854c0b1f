// Filtered lookups into the scene's diffuse textures (OpenImageIO TextureSystem,
// kept out of this header). One private texture system per cache: no global state.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/color.h"
#include "core/log.h"
#include "core/math.h"

namespace penumbra {

class TextureCache {
public:
    /// Opens every texture of `paths` (Scene::textures) once to check it can be
    /// read; one that cannot is disabled with a warning naming the file, so
    /// nothing fails later during rendering.
    TextureCache(const std::vector<std::string>& paths, const Logger& log);
    ~TextureCache();
    TextureCache(const TextureCache&) = delete;
    TextureCache& operator=(const TextureCache&) = delete;

    /// Linear RGB of texture `texture` at `uv`, trilinearly filtered over a
    /// square footprint `footprint` wide in uv units (0: the finest level).
    /// OBJ convention: v points up the image; the texture repeats outside
    /// [0,1]. 8-bit (sRGB-encoded) images are linearised; grey images give
    /// grey. Rgb(1) for a negative or disabled texture or a non-finite uv.
    /// Thread-safe.
    Rgb lookup(int texture, Vec2f uv, float footprint) const;

    /// Number of textures (enabled or not).
    size_t size() const;
    /// Whether `texture` opened and is used by lookup().
    bool enabled(int texture) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra
