// Alpha cutouts: the one rule that says whether a surface is there where a
// ray meets it. Both accelerators ask it of every candidate hit on geometry
// whose material can cut out (Embree through filter functions, the naive loop
// directly), so camera, bounce and shadow rays all see through the same holes,
// and the two agree hit for hit. docs/rendering.md, "Alpha cutouts", describes it.
//
// alpha = opacity x the colour texture's alpha x the opacity map's channel,
// read at the finest MIP level (so it does not depend on how far the ray
// travelled). Mask: present where alpha >= alphaCutoff. Blend: stochastic
// transparency, present with probability alpha; the decision hashes the
// world ray's bits with the primitive, so it is the same in every query of
// that ray whatever the thread count, tile size or accelerator.
//
// Meshes (with their instances) and rectangles cut out; spheres, boxes, disks
// and planes stay opaque (their tests report only the nearest of their
// surfaces, so the one behind a hole could not be seen): opaqueShapesWithAlpha
// counts them for a warning.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/hit.h"
#include "core/material.h"
#include "core/ray.h"

namespace penumbra {

class Scene;
struct TriangleMesh;
class TextureCache;

/// The key of a ray that Blend decisions hash: its origin and direction bits.
uint32_t alphaRayKey(float ox, float oy, float oz, float dx, float dy, float dz);
inline uint32_t alphaRayKey(const Ray& r) { return alphaRayKey(r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z); }

class AlphaTest {
public:
    /// The rule for `scene`'s materials, reading textures through `textures`
    /// (null: texture alpha counts as 1). Both must outlive the test.
    AlphaTest(const Scene& scene, std::shared_ptr<const TextureCache> textures);

    /// Whether any material of the scene can hide its surface.
    bool any() const { return any_; }
    /// Whether material `id` can hide its surface: a Mask or Blend mode with
    /// an opacity, a colour texture with transparent texels or an opacity
    /// map that can take alpha below the cutoff (Blend: below 1).
    bool cutsOut(uint32_t id) const { return id < cuts_.size() && cuts_[id] != 0; }
    /// Whether hits on `mesh` of Scene::meshes need the test.
    bool meshCutsOut(const TriangleMesh& mesh) const;
    /// Whether the rectangles need the test.
    bool rectanglesCutOut() const { return rectanglesCut_; }
    /// Whether prototype `index`'s mesh `part` needs the test in some instance.
    bool prototypeMeshCutsOut(uint32_t index, uint32_t part) const;
    /// Spheres, boxes, disks and planes whose material cuts out: drawn opaque.
    size_t opaqueShapesWithAlpha() const { return opaqueShapes_; }
    /// Whether `other` (the rule of an edited copy of the scene) needs the
    /// same geometries tested.
    bool sameGeometries(const AlphaTest& other) const { return cuts_ == other.cuts_; }

    /// Whether the surface is there at the thin hit (ref, t, u, v) of a ray
    /// whose key (alphaRayKey of the world ray) is `key`. `ray` is the ray in
    /// the hit primitive's space (only analytic shapes read it). Thread-safe,
    /// allocates nothing.
    bool present(const Ray& ray, const PrimRef& ref, float t, float u, float v, uint32_t key) const;

private:
    // What the rule reads of a material: copied out, so a query reads no Material.
    struct Cutout {
        AlphaMode mode = AlphaMode::Opaque;
        float cutoff = 0.5f;
        float opacity = 1.f;
        TextureRef colour, opacityMap;  // the colour texture's alpha and the opacity map's channel
    };
    float alpha(const Cutout& c, const Hit& h) const;

    const Scene& scene_;
    std::shared_ptr<const TextureCache> textures_;
    std::vector<Cutout> materials_;
    std::vector<uint8_t> cuts_;                      // per material
    std::vector<std::vector<uint8_t>> prototypeCuts_;  // per prototype, per mesh
    bool any_ = false, rectanglesCut_ = false;
    size_t opaqueShapes_ = 0;
};

}  // namespace penumbra
