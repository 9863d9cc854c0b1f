#include "core/emission.h"

#include "core/scene.h"
#include "core/texture_cache.h"

namespace penumbra {

bool texturedEmission(const Material& m, const TextureCache* textures) {
    return textures && m.emissiveMap.used() && textures->enabled(m.emissiveMap.texture);
}

Rgb emittedRadiance(const Material& m, const TextureCache* textures, Vec2f uv0, Vec2f uv1) {
    if (!texturedEmission(m, textures)) return m.ke;
    // The finest level: emitters are seen through light samples as often as by camera rays.
    return Rgb(m.ke) * textures->sample(m.emissiveMap, m.emissiveMap.uvSet == 1 ? uv1 : uv0, 0.f).rgb;
}

Rgb emittedRadiance(const Scene& scene, const TextureCache* textures, const Material& m, const Hit& hit) {
    if (!texturedEmission(m, textures) || hit.ref.kind != ShapeKind::Mesh ||
        scene.meshes[hit.ref.object].uvs.empty())
        return m.ke;
    return emittedRadiance(m, textures, hit.uv, m.emissiveMap.uvSet == 1 ? scene.uv1At(hit) : hit.uv);
}

Rgb meanEmittedRadiance(const Material& m, const TextureCache* textures) {
    if (!texturedEmission(m, textures)) return m.ke;
    // A grid of footprint-wide lookups: the MIP level of that footprint averages each cell.
    constexpr int kGrid = 16;
    Rgb sum{};
    for (int y = 0; y < kGrid; ++y)
        for (int x = 0; x < kGrid; ++x) {
            const Vec2f uv{(x + 0.5f) / kGrid, (y + 0.5f) / kGrid};
            sum += textures->sample(m.emissiveMap, uv, 1.f / kGrid).rgb;
        }
    return Rgb(m.ke) * sum * (1.f / (kGrid * kGrid));
}

}  // namespace penumbra
