#include "core/mesh_tangents.h"

#include <cmath>
#include <vector>

namespace penumbra {
namespace {

/// `v` less its component along unit n, normalised; zero when nothing is left.
Vec3f perpendicularPart(const Vec3f& v, const Vec3f& n) {
    const Vec3f t = v - dot(v, n) * n;
    const float l = length(t);
    return l > 1e-20f && std::isfinite(l) ? t / l : Vec3f{};
}

}  // namespace

Vec3f anyPerpendicular(const Vec3f& n) {
    const Vec3f a = std::fabs(n.x) < 0.9f ? Vec3f{1.f, 0.f, 0.f} : Vec3f{0.f, 1.f, 0.f};
    return normalize(cross(a, n));
}

std::optional<Tangent> triangleTangent(const Vec3f p[3], const Vec2f uv[3], const Vec3f& n) {
    const Vec3f e1 = p[1] - p[0], e2 = p[2] - p[0];
    const float du1 = uv[1].x - uv[0].x, dv1 = uv[1].y - uv[0].y;
    const float du2 = uv[2].x - uv[0].x, dv2 = uv[2].y - uv[0].y;
    const float det = du1 * dv2 - du2 * dv1;
    if (!(std::fabs(det) > 0.f) || !std::isfinite(det)) return std::nullopt;
    const float r = 1.f / det;
    const Vec3f dpdu = (dv2 * e1 - dv1 * e2) * r;
    const Vec3f dpdv = (du1 * e2 - du2 * e1) * r;
    return tangentFrom(dpdu, dpdv, n);
}

std::optional<Tangent> tangentFrom(const Vec3f& dpdu, const Vec3f& dpdv, const Vec3f& n) {
    const Vec3f t = perpendicularPart(dpdu, n);
    if (lengthSquared(t) == 0.f || !isFinite(dpdv)) return std::nullopt;
    return Tangent{t, dot(cross(n, t), dpdv) < 0.f ? -1.f : 1.f};
}

bool generateTangents(TriangleMesh& mesh, int uvSet, size_t* degenerate) {
    const std::vector<Vec2f>& uvs = uvSet == 1 ? mesh.uvs1 : mesh.uvs;
    const size_t nv = mesh.positions.size();
    if (uvs.size() != nv || nv == 0) return false;
    const bool normals = mesh.normals.size() == nv;
    // Per vertex: the sums of its triangles' dp/du and dp/dv (weighted by area
    // through the unnormalised cross products) and of their normals.
    std::vector<Vec3f> sumU(nv), sumV(nv), sumN(normals ? 0 : nv);
    for (size_t tri = 0; tri < mesh.triangleCount(); ++tri) {
        const uint32_t* idx = &mesh.indices[3 * tri];
        if (idx[0] >= nv || idx[1] >= nv || idx[2] >= nv) continue;
        const Vec3f e1 = mesh.positions[idx[1]] - mesh.positions[idx[0]];
        const Vec3f e2 = mesh.positions[idx[2]] - mesh.positions[idx[0]];
        const float du1 = uvs[idx[1]].x - uvs[idx[0]].x, dv1 = uvs[idx[1]].y - uvs[idx[0]].y;
        const float du2 = uvs[idx[2]].x - uvs[idx[0]].x, dv2 = uvs[idx[2]].y - uvs[idx[0]].y;
        const float det = du1 * dv2 - du2 * dv1;
        const Vec3f faceNormal = cross(e1, e2);
        if (std::fabs(det) > 0.f && std::isfinite(det)) {
            // dp/du and dp/dv scaled by |det| (area in uv), signed by det's orientation.
            const float s = det < 0.f ? -1.f : 1.f;
            const Vec3f u = (dv2 * e1 - dv1 * e2) * s, v = (du1 * e2 - du2 * e1) * s;
            if (isFinite(u) && isFinite(v))
                for (int k = 0; k < 3; ++k) {
                    sumU[idx[k]] += u;
                    sumV[idx[k]] += v;
                }
        }
        if (!normals)
            for (int k = 0; k < 3; ++k) sumN[idx[k]] += faceNormal;
    }
    size_t bad = 0;
    std::vector<Tangent> tangents(nv);
    for (size_t i = 0; i < nv; ++i) {
        Vec3f n = normals ? mesh.normals[i] : sumN[i];
        const float ln = length(n);
        n = ln > 0.f && std::isfinite(ln) ? n / ln : Vec3f{0.f, 0.f, 1.f};
        Vec3f t = perpendicularPart(sumU[i], n);
        if (lengthSquared(t) == 0.f) {
            ++bad;
            t = anyPerpendicular(n);
        }
        tangents[i] = Tangent{t, dot(cross(n, t), sumV[i]) < 0.f ? -1.f : 1.f};
    }
    mesh.tangents = std::move(tangents);
    if (degenerate) *degenerate = bad;
    return true;
}

}  // namespace penumbra
