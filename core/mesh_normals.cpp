#include "core/mesh_normals.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

namespace penumbra {
namespace {

/// A position's bits, with -0 read as +0, so equal coordinates weld.
struct PositionKey {
    uint32_t b[3];
    bool operator==(const PositionKey&) const = default;
};
struct PositionHash {
    size_t operator()(const PositionKey& k) const noexcept {
        uint64_t h = 1469598103934665603ull;
        for (uint32_t v : k.b) h = (h ^ v) * 1099511628211ull;
        return static_cast<size_t>(h ^ (h >> 29));
    }
};

PositionKey keyOf(const Vec3f& p) {
    PositionKey k{};
    const float c[3] = {p.x == 0.f ? 0.f : p.x, p.y == 0.f ? 0.f : p.y, p.z == 0.f ? 0.f : p.z};
    std::memcpy(k.b, c, sizeof k.b);
    return k;
}

float angleBetween(const Vec3f& a, const Vec3f& b) {
    const float la = length(a), lb = length(b);
    if (!(la > 0.f) || !(lb > 0.f)) return 0.f;
    return std::acos(std::clamp(dot(a, b) / (la * lb), -1.f, 1.f));
}

// Past this many triangles around one position (a fan or a pathological
// file), its corners keep their face normals: the pairwise test is quadratic.
constexpr size_t kMaxValence = 1024;

}  // namespace

void smoothNormals(TriangleMesh& mesh, float maxAngleDegrees) {
    if (!mesh.normals.empty() || !(maxAngleDegrees > 0.f) || mesh.indices.empty()) return;
    const size_t nt = mesh.triangleCount(), nv = mesh.positions.size();
    for (uint32_t i : mesh.indices)
        if (i >= nv) return;  // finalize() repairs such meshes; nothing sensible to smooth
    const float cosMax = std::cos(std::min(maxAngleDegrees, 180.f) * kPi / 180.f);

    // Face normals and each corner's interior angle (its weight).
    std::vector<Vec3f> faceNormal(nt);
    std::vector<float> cornerAngle(3 * nt);
    for (size_t t = 0; t < nt; ++t) {
        Vec3f p[3];
        mesh.vertices(t, p[0], p[1], p[2]);
        const Vec3f n = cross(p[1] - p[0], p[2] - p[0]);
        const float l = length(n);
        faceNormal[t] = l > 0.f && std::isfinite(l) ? n / l : Vec3f{};
        for (int k = 0; k < 3; ++k) cornerAngle[3 * t + k] = angleBetween(p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
    }

    // Corners grouped by welded position (CSR: groupStart/groupCorners).
    std::unordered_map<PositionKey, uint32_t, PositionHash> groupOf;
    groupOf.reserve(nv);
    std::vector<uint32_t> vertexGroup(nv);
    for (size_t v = 0; v < nv; ++v)
        vertexGroup[v] = groupOf.try_emplace(keyOf(mesh.positions[v]), static_cast<uint32_t>(groupOf.size())).first->second;
    std::vector<uint32_t> groupStart(groupOf.size() + 1, 0);
    for (uint32_t i : mesh.indices) ++groupStart[vertexGroup[i] + 1];
    for (size_t g = 1; g < groupStart.size(); ++g) groupStart[g] += groupStart[g - 1];
    std::vector<uint32_t> fill(groupStart.begin(), groupStart.end() - 1), groupCorners(mesh.indices.size());
    for (size_t c = 0; c < mesh.indices.size(); ++c) groupCorners[fill[vertexGroup[mesh.indices[c]]]++] = static_cast<uint32_t>(c);

    // Each corner's normal; corners at one position (of one vertex, where UVs
    // tell vertices apart) with bit-identical normals share one output vertex
    // (the same neighbours summed in the same order give the same bits).
    struct Split {
        Vec3f normal;
        uint32_t index;
    };
    // Vertices with uvs or tangents keep them: corners are then told apart by vertex.
    const bool hasUvs = mesh.uvs.size() == nv, hasUvs1 = mesh.uvs1.size() == nv, hasTangents = mesh.tangents.size() == nv;
    const bool byVertex = hasUvs || hasUvs1 || hasTangents;
    std::vector<std::vector<Split>> splits(byVertex ? nv : groupOf.size());
    PositionBuffer positions;
    positions.reserve(nv);
    std::vector<Vec3f> normals;
    normals.reserve(nv);
    std::vector<Vec2f> uvs, uvs1;
    std::vector<Tangent> tangents;
    std::vector<uint32_t> indices(mesh.indices.size());
    for (size_t c = 0; c < mesh.indices.size(); ++c) {
        const uint32_t v = mesh.indices[c];
        const Vec3f& own = faceNormal[c / 3];
        Vec3f n = own;
        const uint32_t g = vertexGroup[v];
        if (groupStart[g + 1] - groupStart[g] <= kMaxValence) {
            n = Vec3f{};
            for (uint32_t k = groupStart[g]; k < groupStart[g + 1]; ++k) {
                const uint32_t other = groupCorners[k];
                const Vec3f& fn = faceNormal[other / 3];
                if (dot(own, fn) >= cosMax) n += fn * cornerAngle[other];
            }
            const float l = length(n);
            n = l > 0.f && std::isfinite(l) ? n / l : own;
        }
        auto& list = splits[byVertex ? v : g];
        auto it = std::find_if(list.begin(), list.end(), [&](const Split& s) {
            return s.normal.x == n.x && s.normal.y == n.y && s.normal.z == n.z;
        });
        if (it == list.end()) {
            list.push_back({n, static_cast<uint32_t>(positions.size())});
            positions.push_back(mesh.positions[v]);
            normals.push_back(n);
            if (hasUvs) uvs.push_back(mesh.uvs[v]);
            if (hasUvs1) uvs1.push_back(mesh.uvs1[v]);
            if (hasTangents) tangents.push_back(mesh.tangents[v]);
            it = list.end() - 1;
        }
        indices[c] = it->index;
    }
    mesh.positions = std::move(positions);
    mesh.normals = std::move(normals);
    mesh.indices = std::move(indices);
    if (hasUvs) mesh.uvs = std::move(uvs);
    if (hasUvs1) mesh.uvs1 = std::move(uvs1);
    if (hasTangents) mesh.tangents = std::move(tangents);
}

}  // namespace penumbra
