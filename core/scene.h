// The scene: plain arrays of shapes, meshes, materials and light descriptions.
// Built by loaders or in code, then finalize()d once; afterwards it is
// immutable and shared read-only by accelerators, lights and the integrator.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/color.h"
#include "core/hit.h"
#include "core/instance.h"
#include "core/log.h"
#include "core/material.h"
#include "core/mesh.h"
#include "core/ray.h"
#include "core/shapes.h"
#include "core/texture_source.h"

namespace penumbra {

class InputFile;  // core/io/input_file.h

/// Isotropic point light: intensity I (W/sr per channel); irradiance I cos / d^2.
struct PointLight {
    Vec3f position;
    Rgb intensity{1.f};
};

/// Directional light arriving along `direction` (the direction light travels)
/// with irradiance E on a surface facing it.
struct DirectionalLight {
    Vec3f direction{0.f, -1.f, 0.f};
    Rgb irradiance{1.f};
};

/// Light arriving from infinitely far away in every direction: a constant
/// colour, or a lat-long (equirectangular) image (docs/rendering.md, "Environment
/// light", for the mapping: +y is up, u = 0.5 looks along -z, rotation about +y).
struct EnvironmentDesc {
    Rgb color{1.f};        // radiance when there is no image
    std::string image;     // lat-long image (EXR, HDR, PFM, PNG, ...); empty: `color`
    /// The loader's open image file (read this, never reopen the path); null
    /// for images named in code: opened by path, once, when the scene is prepared.
    std::shared_ptr<const InputFile> imageFile;
    float rotateDegrees = 0.f;  // about +y, counter-clockwise seen from above
    float scale = 1.f;          // multiplies the image or the colour
};

/// Counts of what finalize() repaired or dropped.
struct SceneFixups {
    size_t droppedTriangles = 0;  // bad indices, non-finite or degenerate (zero-area) vertices
    size_t droppedShapes = 0;     // analytic shapes with non-finite or degenerate parameters
    size_t droppedInstances = 0;  // unknown or empty prototype, non-finite or singular transform, out of range
};

class Scene {
public:
    std::vector<Material> materials;
    std::vector<Sphere> spheres;
    std::vector<Plane> planes;
    std::vector<Box> boxes;
    std::vector<Rectangle> rectangles;
    std::vector<Disk> disks;
    std::vector<TriangleMesh> meshes;
    std::vector<PointLight> pointLights;
    std::vector<DirectionalLight> directionalLights;
    /// The textures materials sample (Material::textureIndex, TextureRef::texture):
    /// files the loaders opened, images inside model files, or paths named in code.
    std::vector<TextureSource> textures;
    Rgb ambient{0.f};                   // global ambient light La
    Rgb background{0.f};                // radiance of rays that leave the scene
    std::vector<Prototype> prototypes;  // meshes drawn only through instances (core/instance.h)
    std::vector<Instance> instances;
    /// Environment light: lights the scene and is what rays that leave it see
    /// (replacing `background`). Empty: none.
    std::optional<EnvironmentDesc> environment;
    /// When the scene has no light at all (no emitter, point or directional
    /// light, ambient light, environment or background), preparing it adds
    /// a uniform white environment of radiance 1 and warns, so that it is not
    /// silently black. False: render such a scene black.
    bool defaultLight = true;

    /// Validates and repairs the scene so that every accelerator sees exactly
    /// the same primitives: drops triangles with out-of-range indices,
    /// non-finite or zero-area vertices, drops analytic shapes with non-finite
    /// or degenerate parameters, normalises plane/disk normals, clamps material
    /// ids, and drops mesh normals/UVs whose count does not match the vertices.
    /// Each kind of repair is logged once with its count. A scene without
    /// materials gets the default grey one. Instances with an unknown or empty
    /// prototype or a non-finite or singular transform are dropped; instances
    /// of emissive prototypes (or with an emissive material override) are
    /// expanded into world-space meshes (core/instance.h); throws
    /// Error(InvalidScene) when those copies would pass CopyCount's limit.
    /// Idempotent.
    SceneFixups finalize(const Logger& log);

    /// Whether finalize() expands this instance into meshes: its prototype,
    /// or its material override, emits light.
    bool expandsInstance(const Instance& in) const;
    /// Adds the copies finalize() makes of the instances it expands.
    void countExpansion(CopyCount& count) const;

    /// Whether anything lights the scene: geometry with an emissive material,
    /// a point or directional light, an environment, or a non-black ambient
    /// light or background. (The default light of Scene::defaultLight.)
    bool hasLight() const;

    /// Bounds of all finite geometry (planes excluded).
    Bounds3f bounds() const;

    /// Turns an accelerator's thin answer into a full Hit. Both accelerators
    /// call this, so their hits are identical given the same (ref, t, u, v).
    Hit completeHit(const Ray& ray, const PrimRef& ref, float t, float u, float v) const {
        Hit h;
        completeHit(ray, ref, t, u, v, h);
        return h;
    }
    /// The same, written into h in place (every field; the renderer's batches).
    /// ref by reference: by value it is spilled as two 8-byte stores and read
    /// back as one 16-byte load, which the CPU cannot forward from two stores
    /// (docs/benchmarks.md, "No wide reload of narrow stores").
    void completeHit(const Ray& ray, const PrimRef& ref, float t, float u, float v, Hit& h) const;
    /// Whether material id has a texture, so that its hits need texture
    /// coordinates (Hit::uv); false for an id with no material. One byte per
    /// material, made by finalize(): the hot path reads no Material (before
    /// finalize(), the materials are asked).
    bool textured(uint32_t id) const {
        return id < uvNeeded_.size() ? uvNeeded_[id] != 0 : id < materials.size() && materials[id].needsUv();
    }

    /// The second uv set at a mesh hit (Hit::uv where the mesh has no second
    /// set or the hit is on another shape). Like tangentAt, it finds the
    /// hit's barycentrics again from h.p, so that completeHit computes
    /// nothing for the materials that need neither.
    Vec2f uv1At(const Hit& h) const;
    /// The world-space tangent at a hit, perpendicular to h.ns, with the
    /// bitangent's sign (Tangent): interpolated from the mesh's tangents, else
    /// the triangle's own from its uvs (uv set `uvSet`); on the other shapes,
    /// the directions their uv grow in (uvDerivatives); else any perpendicular.
    Tangent tangentAt(const Hit& h, int uvSet = 0) const;

    /// The index of `source` in `textures`, added unless a texture of the same
    /// name and colour space is there already (then `source` is dropped).
    int addTexture(TextureSource source);
    /// The first texture named `name`, in any colour space (its open file can
    /// serve another), or null.
    const TextureSource* findTexture(const std::string& name) const;

    /// Where a Mesh hit lies on a convex mesh whose triangles face outwards
    /// (core/mesh_convexity.h), with every vertex within half the ray offset
    /// (rayOffsetScale) at any of its points of the triangles' planes: that
    /// mesh's index. A ray leaving the hit above its front side then cannot
    /// meet the mesh again (the accelerators' `leaving` hints). -1 for any
    /// other hit, and before finalize().
    int32_t convexMeshOf(const PrimRef& ref) const {
        return ref.kind == ShapeKind::Mesh && ref.object < convexMeshes_.size() ? convexMeshes_[ref.object] : -1;
    }
    /// convexMeshOf of each mesh, by index; null where no mesh is convex
    /// (then no hit needs asking).
    const int32_t* convexMeshes() const {
        for (int32_t c : convexMeshes_)
            if (c >= 0) return convexMeshes_.data();
        return nullptr;
    }

    /// Triangles as rendered: each instance counts its prototype's triangles.
    size_t triangleCount() const;
    /// The mesh a Mesh or Instance hit lies on and the transform that places
    /// it (identity for Scene::meshes); nullptr for the other shapes.
    const TriangleMesh* meshOf(const PrimRef& ref, Transform* worldFromObject) const;
    size_t primitiveCount() const;
    const Material& material(uint32_t id) const { return materials[id]; }

private:
    void completeInstanceHit(const PrimRef& ref, float u, float v, Hit& h) const;

    /// A mesh hit's triangle: its mesh, corner indices, placement, corners in the world, barycentrics.
    struct HitTriangle {
        const TriangleMesh* mesh;
        const uint32_t* idx;
        Transform place;
        Vec3f p[3];
        Vec2f bary;
    };
    std::optional<HitTriangle> hitTriangle(const Hit& h) const;

    std::vector<uint8_t> uvNeeded_;  // Material::needsUv() of each material, from finalize()
    std::vector<int32_t> convexMeshes_;  // each mesh's convexMeshOf, from finalize()
};

}  // namespace penumbra
