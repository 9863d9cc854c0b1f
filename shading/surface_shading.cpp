#include "shading/surface_shading.h"

#include <algorithm>
#include <cmath>

#include "core/emission.h"
#include "core/lane_clones.h"
#include "core/texture_cache.h"

namespace penumbra {

float SurfaceShading::footprint(const Hit& hit, float pathLength, const Vec3f& wo) const {
    // Filter footprint in uv: the pixel's cone width at the hit (a ray cone:
    // distance travelled times the pixel's angle, stretched by the grazing
    // angle), converted to uv units with the triangle's uv-per-world scale.
    Transform place;  // an instanced mesh's triangle is measured where the instance puts it
    const TriangleMesh* meshPtr = pixelSpread_ > 0.f ? scene_.meshOf(hit.ref, &place) : nullptr;
    if (!meshPtr || meshPtr->uvs.empty()) return 0.f;
    const TriangleMesh& mesh = *meshPtr;
    const uint32_t* idx = &mesh.indices[3 * hit.ref.prim];
    const Vec2f &a = mesh.uvs[idx[0]], &b = mesh.uvs[idx[1]], &c = mesh.uvs[idx[2]];
    const float uvArea = std::fabs((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
    const Vec3f p0 = place.applyPoint(mesh.positions[idx[0]]), p1 = place.applyPoint(mesh.positions[idx[1]]),
                p2 = place.applyPoint(mesh.positions[idx[2]]);
    const float worldArea = length(cross(p1 - p0, p2 - p0));
    if (!(worldArea > 0.f)) return 0.f;
    const float cosTheta = std::max(std::fabs(dot(wo, hit.ns)), 0.2f);
    return pathLength * pixelSpread_ / cosTheta * std::sqrt(uvArea / worldArea);
}

Rgb SurfaceShading::diffuseAlbedo(const Material& m, const Hit& hit, float pathLength, const Vec3f& wo) const {
    if (m.textureIndex < 0 || !textures_) return m.kd;
    return m.kd * textures_->lookup(m.textureIndex, hit.uv, footprint(hit, pathLength, wo));
}

void SurfaceShading::shadeMaps(const Material& m, const Hit& hit, float pathLength, ShadingPoint& sp) const {
    sp.glossy = m.isGlossy();
    if (!m.shadedAsMetalRoughness()) sp.kd = diffuseAlbedo(m, hit, pathLength, sp.wo);
    const float width = textures_ ? footprint(hit, pathLength, sp.wo) : 0.f;
    const Vec2f uv1 = textures_ && m.needsUv1() ? scene_.uv1At(hit) : hit.uv;
    const auto uvOf = [&](const TextureRef& r) { return r.uvSet == 1 ? uv1 : hit.uv; };
    if (m.normalMap.used() && textures_) {
        // The map's normal (a height map's: from its slopes) in the tangent frame
        // of the unflipped shading normal, then turned to wo's side.
        const Vec2f uv = uvOf(m.normalMap);
        const Vec3f local = m.bumpMap ? textures_->sampleHeightNormal(m.normalMap, uv, width, m.normalScale)
                                      : textures_->sampleNormal(m.normalMap, uv, width, m.normalScale);
        const Tangent t = scene_.tangentAt(hit, m.normalMap.uvSet);
        const Vec3f bitangent = t.sign * cross(hit.ns, t.direction);
        Vec3f n = normalize(t.direction * local.x + bitangent * local.y + hit.ns * local.z);
        if (!sp.front) n = -n;
        // A mapped normal may turn away from the viewer: bent back until wo lies just above its surface.
        constexpr float kMinCos = 0.01f;
        const float c = dot(n, sp.wo);
        if (c < kMinCos) n = normalize(n + (kMinCos - c) * sp.wo);
        if (isFinite(n) && lengthSquared(n) > 0.f) sp.ns = n;
    }
    if (!m.shadedAsMetalRoughness()) return;
    Rgb base = m.baseColor;
    float metallic = m.metallic, roughness = m.roughness;
    if (textures_) {
        if (m.baseColorMap.used()) base *= textures_->sample(m.baseColorMap, uvOf(m.baseColorMap), width).rgb;
        if (m.metallicMap.used()) metallic *= textures_->sampleChannel(m.metallicMap, uvOf(m.metallicMap), width);
        if (m.roughnessMap.used()) roughness *= textures_->sampleChannel(m.roughnessMap, uvOf(m.roughnessMap), width);
    }
    sp.kd = base;
    sp.metallic = metallic;
    sp.roughness = roughness;
    sp.metalRoughness = true;
    sp.glossy = true;
    sp.mirrorSpecular = roughness <= mirrorRoughness_;
}

PENUMBRA_LANE_CLONES void SurfaceShading::shade(const Hit& hit, const Ray& ray, float pathLength,
                                                ShadingPoint& sp) const {
    const Material& m = scene_.material(hit.material);
    sp.material = &m;
    sp.p = hit.p;
    sp.wo = -ray.d;
    // Shading is two-sided: flip both normals to the viewer's side.
    const bool front = dot(sp.wo, hit.ng) > 0.f;
    sp.front = front;
    sp.ng = front ? hit.ng : -hit.ng;
    sp.ns = front ? hit.ns : -hit.ns;
    sp.metalRoughness = false;
    sp.mirrorSpecular = false;
    if (m.kind == MaterialKind::Phong && !m.normalMap.used()) [[likely]] {
        sp.kd = diffuseAlbedo(m, hit, pathLength, sp.wo);
        sp.glossy = m.isGlossy();
    } else {
        shadeMaps(m, hit, pathLength, sp);
    }
    // Last: placed first, its load and test changed how the code above reads
    // the hit (two components of its normal by one 8-byte load, across the
    // narrower stores that had just written them).
    if (convexMeshes_) [[unlikely]]
        sp.convexMesh = sp.front && hit.ref.kind == ShapeKind::Mesh ? convexMeshes_[hit.ref.object] : -1;
}

Rgb SurfaceShading::emission(const Hit& hit, const ShadingPoint& sp) const {
    return emittedRadiance(scene_, textures_, *sp.material, hit);
}

}  // namespace penumbra
