#include "core/scene_range.h"

#include <algorithm>

#include "core/scene.h"

namespace penumbra {
namespace {

template <class T>
size_t dropShapes(std::vector<T>& v) {
    const size_t before = v.size();
    v.erase(std::remove_if(v.begin(), v.end(), [](const T& s) { return !withinSceneRange(bounds(s)); }), v.end());
    return before - v.size();
}

size_t dropTriangles(TriangleMesh& m) {
    const size_t nt = m.triangleCount();
    size_t kept = 0;
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t i0 = m.indices[3 * t], i1 = m.indices[3 * t + 1], i2 = m.indices[3 * t + 2];
        if (!withinSceneRange(m.positions[i0]) || !withinSceneRange(m.positions[i1]) ||
            !withinSceneRange(m.positions[i2]))
            continue;
        if (kept != t) {
            m.indices[3 * kept] = i0;
            m.indices[3 * kept + 1] = i1;
            m.indices[3 * kept + 2] = i2;
            if (!m.faceMaterials.empty()) m.faceMaterials[kept] = m.faceMaterials[t];
        }
        ++kept;
    }
    m.indices.resize(kept * 3);
    if (!m.faceMaterials.empty()) m.faceMaterials.resize(kept);
    return nt - kept;
}

}  // namespace

bool withinSceneRange(const Vec3f& p) {
    for (int i = 0; i < 3; ++i)
        if (!(p[i] > -kMaxSceneCoordinate && p[i] < kMaxSceneCoordinate)) return false;
    return true;
}

bool withinSceneRange(const Bounds3f& b) { return withinSceneRange(b.lo) && withinSceneRange(b.hi); }

RangeDrops dropBeyondSceneRange(Scene& scene) {
    RangeDrops d;
    d.shapes += dropShapes(scene.spheres);
    d.shapes += dropShapes(scene.boxes);
    d.shapes += dropShapes(scene.rectangles);
    d.shapes += dropShapes(scene.disks);
    // Indices are valid here: finalize() repaired the meshes first.
    for (auto& m : scene.meshes) d.triangles += dropTriangles(m);
    scene.meshes.erase(std::remove_if(scene.meshes.begin(), scene.meshes.end(),
                                      [](const TriangleMesh& m) { return m.indices.empty(); }),
                       scene.meshes.end());
    for (auto& p : scene.prototypes) {
        for (auto& m : p.meshes) d.triangles += dropTriangles(m);
        p.meshes.erase(std::remove_if(p.meshes.begin(), p.meshes.end(),
                                      [](const TriangleMesh& m) { return m.indices.empty(); }),
                       p.meshes.end());
    }
    // An instance of a prototype left empty has nothing to draw.
    const size_t before = scene.instances.size();
    scene.instances.erase(std::remove_if(scene.instances.begin(), scene.instances.end(),
                                         [&](const Instance& in) {
                                             const Prototype& p = scene.prototypes[in.prototype];
                                             return p.meshes.empty() || !withinSceneRange(instanceBounds(p, in));
                                         }),
                          scene.instances.end());
    d.instances = before - scene.instances.size();
    return d;
}

}  // namespace penumbra
