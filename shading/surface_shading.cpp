#include "shading/surface_shading.h"

#include <algorithm>
#include <cmath>

#include "core/lane_clones.h"
#include "core/texture_cache.h"

namespace penumbra {

Rgb SurfaceShading::diffuseAlbedo(const Material& m, const Hit& hit, float pathLength, const Vec3f& wo) const {
    if (m.textureIndex < 0 || !textures_) return m.kd;
    // Filter footprint in uv: the pixel's cone width at the hit (a ray cone:
    // distance travelled times the pixel's angle, stretched by the grazing
    // angle), converted to uv units with the triangle's uv-per-world scale.
    float footprint = 0.f;
    Transform place;  // an instanced mesh's triangle is measured where the instance puts it
    const TriangleMesh* meshPtr = pixelSpread_ > 0.f ? scene_.meshOf(hit.ref, &place) : nullptr;
    if (meshPtr) {
        const TriangleMesh& mesh = *meshPtr;
        if (!mesh.uvs.empty()) {
            const uint32_t* idx = &mesh.indices[3 * hit.ref.prim];
            const Vec2f &a = mesh.uvs[idx[0]], &b = mesh.uvs[idx[1]], &c = mesh.uvs[idx[2]];
            const float uvArea = std::fabs((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
            const Vec3f p0 = place.applyPoint(mesh.positions[idx[0]]), p1 = place.applyPoint(mesh.positions[idx[1]]),
                        p2 = place.applyPoint(mesh.positions[idx[2]]);
            const float worldArea = length(cross(p1 - p0, p2 - p0));
            if (worldArea > 0.f) {
                const float cosTheta = std::max(std::fabs(dot(wo, hit.ns)), 0.2f);
                footprint = pathLength * pixelSpread_ / cosTheta * std::sqrt(uvArea / worldArea);
            }
        }
    }
    return m.kd * textures_->lookup(m.textureIndex, hit.uv, footprint);
}

PENUMBRA_LANE_CLONES void SurfaceShading::shade(const Hit& hit, const Ray& ray, float pathLength,
                                                ShadingPoint& sp) const {
    sp.material = &scene_.material(hit.material);
    sp.p = hit.p;
    sp.wo = -ray.d;
    // Shading is two-sided: flip both normals to the viewer's side.
    const bool front = dot(sp.wo, hit.ng) > 0.f;
    sp.front = front;
    sp.ng = front ? hit.ng : -hit.ng;
    sp.ns = front ? hit.ns : -hit.ns;
    sp.kd = diffuseAlbedo(*sp.material, hit, pathLength, sp.wo);
    sp.glossy = sp.material->isGlossy();
}

}  // namespace penumbra
