#include "core/instance.h"

#include "core/shapes.h"

namespace penumbra {

size_t Prototype::triangleCount() const {
    size_t n = 0;
    for (const TriangleMesh& m : meshes) n += m.triangleCount();
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
    const Bounds3f o = prototype.bounds();
    Bounds3f b;
    if (o.empty()) return b;
    for (int i = 0; i < 8; ++i)
        b.extend(instance.worldFromObject.applyPoint(
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

}  // namespace penumbra
