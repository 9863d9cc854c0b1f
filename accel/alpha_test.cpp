#include "accel/alpha_test.h"

#include <bit>

#include "core/hash.h"
#include "core/scene.h"
#include "core/texture_cache.h"

namespace penumbra {
namespace {

// Whether a slot's texture can lower alpha: the colour texture through
// transparent texels of its alpha channel, an opacity map through any texel.
bool colourCanHide(const TextureRef& r, const TextureCache* t) {
    return r.used() && t && t->hasTransparency(r.texture);
}
bool mapCanHide(const TextureRef& r, const TextureCache* t) { return r.used() && t && t->enabled(r.texture); }

}  // namespace

uint32_t alphaRayKey(float ox, float oy, float oz, float dx, float dy, float dz) {
    auto bits = [](float x) { return uint64_t(std::bit_cast<uint32_t>(x)); };
    const uint64_t h = hashValues({bits(ox) << 32 | bits(oy), bits(oz) << 32 | bits(dx), bits(dy) << 32 | bits(dz)});
    return static_cast<uint32_t>(h >> 32);
}

AlphaTest::AlphaTest(const Scene& scene, std::shared_ptr<const TextureCache> textures)
    : scene_(scene), textures_(std::move(textures)) {
    const TextureCache* t = textures_.get();
    for (const Material& m : scene.materials) {
        Cutout c;
        c.mode = m.alphaMode;
        c.cutoff = m.alphaCutoff;
        c.opacity = m.opacity;
        // The colour texture: a Phong material's diffuse texture, read as an unadorned slot.
        c.colour = m.kind == MaterialKind::Phong ? TextureRef::of(TextureSlot{}, m.textureIndex) : m.baseColorMap;
        c.opacityMap = m.opacityMap;
        const bool textured = colourCanHide(c.colour, t) || mapCanHide(c.opacityMap, t);
        bool cuts = false;
        if (c.mode == AlphaMode::Mask) cuts = c.cutoff > 0.f && (c.opacity < c.cutoff || textured);
        if (c.mode == AlphaMode::Blend) cuts = c.opacity < 1.f || textured;
        materials_.push_back(c);
        cuts_.push_back(cuts ? 1 : 0);
        any_ |= cuts;
    }
    for (const Rectangle& r : scene.rectangles) rectanglesCut_ |= cutsOut(r.material);
    auto countOpaque = [&](const auto& shapes) {
        for (const auto& s : shapes) opaqueShapes_ += cutsOut(s.material) ? 1 : 0;
    };
    countOpaque(scene.spheres);
    countOpaque(scene.boxes);
    countOpaque(scene.disks);
    countOpaque(scene.planes);
    // A prototype's mesh needs the test where an instance draws it with a material that cuts out.
    std::vector<std::vector<uint8_t>> own(scene.prototypes.size());
    for (size_t p = 0; p < scene.prototypes.size(); ++p)
        for (const TriangleMesh& m : scene.prototypes[p].meshes) own[p].push_back(meshCutsOut(m) ? 1 : 0);
    prototypeCuts_.resize(own.size());
    for (size_t p = 0; p < own.size(); ++p) prototypeCuts_[p].assign(own[p].size(), 0);
    for (const Instance& in : scene.instances) {
        const bool overridden = in.material != kNoMaterialOverride;
        for (size_t k = 0; k < own[in.prototype].size(); ++k)
            prototypeCuts_[in.prototype][k] |= overridden ? (cutsOut(in.material) ? 1 : 0) : own[in.prototype][k];
    }
}

bool AlphaTest::meshCutsOut(const TriangleMesh& mesh) const {
    if (!any_) return false;
    if (mesh.faceMaterials.empty()) return cutsOut(mesh.material);
    for (uint32_t id : mesh.faceMaterials)
        if (cutsOut(id)) return true;
    return false;
}

bool AlphaTest::prototypeMeshCutsOut(uint32_t index, uint32_t part) const {
    return index < prototypeCuts_.size() && part < prototypeCuts_[index].size() && prototypeCuts_[index][part] != 0;
}

float AlphaTest::alpha(const Cutout& c, const Hit& h) const {
    float a = c.opacity;
    const TextureCache* t = textures_.get();
    if (!t) return a;
    const bool secondSet = (c.colour.used() && c.colour.uvSet == 1) || (c.opacityMap.used() && c.opacityMap.uvSet == 1);
    const Vec2f uv1 = secondSet ? scene_.uv1At(h) : h.uv;
    // The finest level: a cutout's edge stays where it is at any distance.
    if (c.colour.used()) a *= t->sample(c.colour, c.colour.uvSet == 1 ? uv1 : h.uv, 0.f).a;
    if (c.opacityMap.used()) a *= t->sampleChannel(c.opacityMap, c.opacityMap.uvSet == 1 ? uv1 : h.uv, 0.f);
    return a;
}

bool AlphaTest::present(const Ray& ray, const PrimRef& ref, float t, float u, float v, uint32_t key) const {
    if (ref.kind != ShapeKind::Mesh && ref.kind != ShapeKind::Instance && ref.kind != ShapeKind::Rectangle)
        return true;
    Hit h;
    scene_.completeHit(ray, ref, t, u, v, h);
    if (!cutsOut(h.material)) return true;
    const Cutout& c = materials_[h.material];
    const float a = alpha(c, h);
    if (c.mode == AlphaMode::Mask) return a >= c.cutoff;
    const uint64_t prim = uint64_t(ref.prim) << 32 | ref.part;
    const uint64_t shape = uint64_t(static_cast<uint8_t>(ref.kind)) << 32 | ref.object;
    return toUnitFloat(hashValues({key, shape, prim})) < a;
}

}  // namespace penumbra
