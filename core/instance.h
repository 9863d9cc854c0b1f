// Instancing: a prototype is a named group of meshes kept once, in its own
// object space, and drawn only through instances; an instance places a
// prototype with an affine transform (and may replace its materials). Twenty
// instances of a dragon cost one dragon's vertices and BVH plus 20 transforms.
//
// Emissive prototypes are not instanced: Scene::finalize expands every
// instance whose prototype uses an emissive material (or whose material
// override is emissive) into ordinary world-space meshes in Scene::meshes, so
// each copy is an area light like any mesh (see docs/scene-format.md).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/mesh.h"
#include "core/transform.h"

namespace penumbra {

/// A named group of meshes in object space. Its meshes are not part of the
/// scene on their own: only instances draw them.
struct Prototype {
    std::string name;
    std::vector<TriangleMesh> meshes;

    size_t triangleCount() const;
    size_t vertexCount() const;
    /// Bounds of the meshes' vertices in object space.
    Bounds3f bounds() const;
    /// Whether any face of any mesh uses an emissive material of `materials`
    /// (an id out of range counts as material 0, as Scene::finalize repairs it).
    template <class MaterialList>
    bool usesEmissive(const MaterialList& materials) const;
};

/// The most triangles that copies of meshes may add to one scene (three times
/// as many vertices); the build sets it (CMake PENUMBRA_MAX_COPIED_TRIANGLES,
/// default 100 million, about 4 GB of copies).
uint64_t maxCopiedTriangles();

/// Copies of meshes that a scene asks for, counted before they are made:
/// prototypes placed inside prototypes (flattened by the JSON loader), one
/// model mesh placed by several nodes, emissive instances (expanded by
/// Scene::finalize). Unlike an instance, each copy costs its full memory, so
/// a few kilobytes of nested placements could ask for 2^40 triangles.
class CopyCount {
public:
    /// Adds `copies` copies of a group of `triangles` triangles and `vertices` vertices (saturating).
    void add(uint64_t copies, uint64_t triangles, uint64_t vertices);
    /// Throws Error(InvalidScene) "`what` would copy N triangles ..." when the
    /// count passes maxCopiedTriangles() triangles or three times as many vertices.
    void check(const std::string& what) const;
    uint64_t triangles() const { return triangles_; }
    uint64_t vertices() const { return vertices_; }

private:
    uint64_t triangles_ = 0, vertices_ = 0;
};

/// `material` value meaning "each face keeps the prototype's material".
inline constexpr uint32_t kNoMaterialOverride = UINT32_MAX;

/// One placement of a prototype.
struct Instance {
    uint32_t prototype = 0;               // index into Scene::prototypes
    Transform worldFromObject;            // must be invertible
    Transform objectFromWorld;            // kept in sync by makeInstance() (and Scene::finalize)
    uint32_t material = kNoMaterialOverride;  // when set, replaces the material of every face
};

/// An instance with its inverse transform filled in (identity when singular;
/// Scene::finalize drops such instances).
Instance makeInstance(uint32_t prototype, const Transform& worldFromObject, uint32_t material = kNoMaterialOverride);

/// Bounds of an instance in world space: the prototype's object-space box
/// with its 8 corners transformed.
Bounds3f instanceBounds(const Prototype& prototype, const Instance& instance);
/// The same from the prototype's object-space bounds (for callers that keep them).
Bounds3f instanceBounds(const Bounds3f& objectBounds, const Transform& worldFromObject);

/// A world-space copy of `mesh` placed by worldFromObject: positions
/// transformed, normals by the inverse transpose, tangents as vectors (their
/// sign flipped by a mirroring transform), indices and UVs kept (so its front
/// side is where the placed instance's is).
TriangleMesh placedCopy(const TriangleMesh& mesh, const Transform& worldFromObject);

/// Appends placedCopy of each of the prototype's meshes to `out`, every face
/// given `material` unless it is kNoMaterialOverride.
void appendPlacedCopies(const Prototype& prototype, const Transform& worldFromObject, uint32_t material,
                        std::vector<TriangleMesh>& out);

template <class MaterialList>
bool Prototype::usesEmissive(const MaterialList& materials) const {
    auto emissive = [&](uint32_t id) { return materials[id < materials.size() ? id : 0].isEmissive(); };
    for (const TriangleMesh& m : meshes) {
        if (m.faceMaterials.empty() && emissive(m.material)) return true;
        for (uint32_t id : m.faceMaterials)
            if (emissive(id)) return true;
    }
    return false;
}

}  // namespace penumbra
