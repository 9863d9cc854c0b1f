#include "core/instance.h"

#include <limits>

#include "core/error.h"
#include "core/shapes.h"

#ifndef PENUMBRA_MAX_COPIED_TRIANGLES
#define PENUMBRA_MAX_COPIED_TRIANGLES 100000000
#endif

namespace penumbra {
namespace {

uint64_t saturatingMul(uint64_t a, uint64_t b) {
    uint64_t r;
    return __builtin_mul_overflow(a, b, &r) ? std::numeric_limits<uint64_t>::max() : r;
}

uint64_t saturatingAdd(uint64_t a, uint64_t b) {
    uint64_t r;
    return __builtin_add_overflow(a, b, &r) ? std::numeric_limits<uint64_t>::max() : r;
}

std::string counted(uint64_t n) {
    return n == std::numeric_limits<uint64_t>::max() ? "more than 2^64" : std::to_string(n);
}

}  // namespace

uint64_t maxCopiedTriangles() { return PENUMBRA_MAX_COPIED_TRIANGLES; }

void CopyCount::add(uint64_t copies, uint64_t triangles, uint64_t vertices) {
    triangles_ = saturatingAdd(triangles_, saturatingMul(copies, triangles));
    vertices_ = saturatingAdd(vertices_, saturatingMul(copies, vertices));
}

void CopyCount::check(const std::string& what) const {
    const uint64_t limit = maxCopiedTriangles();
    if (triangles_ <= limit && vertices_ / 3 <= limit) return;
    throw Error(ErrorCode::InvalidScene,
                what + " would copy " + counted(triangles_) + " triangles (" + counted(vertices_) +
                    " vertices), more than the " + std::to_string(limit) +
                    " triangles (three times as many vertices) that copies may add to a scene; top-level instances "
                    "of non-emissive prototypes are not copied");
}

size_t Prototype::triangleCount() const {
    size_t n = 0;
    for (const TriangleMesh& m : meshes) n += m.triangleCount();
    return n;
}

size_t Prototype::vertexCount() const {
    size_t n = 0;
    for (const TriangleMesh& m : meshes) n += m.positions.size();
    return n;
}

Bounds3f Prototype::bounds() const {
    Bounds3f b;
    for (const TriangleMesh& m : meshes) b.extend(penumbra::bounds(m));
    return b;
}

Instance makeInstance(uint32_t prototype, const Transform& worldFromObject, uint32_t material) {
    Instance in;
    in.prototype = prototype;
    in.worldFromObject = worldFromObject;
    if (!worldFromObject.inverse(in.objectFromWorld)) in.objectFromWorld = Transform();
    in.material = material;
    return in;
}

Bounds3f instanceBounds(const Prototype& prototype, const Instance& instance) {
    return instanceBounds(prototype.bounds(), instance.worldFromObject);
}

Bounds3f instanceBounds(const Bounds3f& o, const Transform& worldFromObject) {
    Bounds3f b;
    if (o.empty()) return b;
    for (int i = 0; i < 8; ++i)
        b.extend(worldFromObject.applyPoint(
            Vec3f{(i & 1) ? o.hi.x : o.lo.x, (i & 2) ? o.hi.y : o.lo.y, (i & 4) ? o.hi.z : o.lo.z}));
    return b;
}

TriangleMesh placedCopy(const TriangleMesh& mesh, const Transform& worldFromObject) {
    TriangleMesh m;
    m.name = mesh.name;
    m.positions.reserve(mesh.positions.size());
    for (const Vec3f& p : mesh.positions) m.positions.push_back(worldFromObject.applyPoint(p));
    m.indices = mesh.indices;
    m.normals.reserve(mesh.normals.size());
    for (const Vec3f& n : mesh.normals) m.normals.push_back(normalize(worldFromObject.applyNormal(n)));
    m.uvs = mesh.uvs;
    m.uvs1 = mesh.uvs1;
    // Tangents turn with the surface; a mirroring placement flips the bitangent's side.
    const float flip = worldFromObject.determinant() < 0.f ? -1.f : 1.f;
    m.tangents.reserve(mesh.tangents.size());
    for (const Tangent& t : mesh.tangents)
        m.tangents.push_back({normalize(worldFromObject.applyVector(t.direction)), flip * t.sign});
    m.faceMaterials = mesh.faceMaterials;
    m.material = mesh.material;
    return m;
}

void appendPlacedCopies(const Prototype& prototype, const Transform& worldFromObject, uint32_t material,
                        std::vector<TriangleMesh>& out) {
    for (const TriangleMesh& m : prototype.meshes) {
        TriangleMesh copy = placedCopy(m, worldFromObject);
        if (material != kNoMaterialOverride) {
            copy.material = material;
            copy.faceMaterials.clear();
        }
        out.push_back(std::move(copy));
    }
}

}  // namespace penumbra
