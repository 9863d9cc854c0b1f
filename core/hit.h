// What a closest-hit query returns.
#pragma once

#include <cstdint>

#include "core/math.h"

namespace penumbra {

/// Instance: a triangle of a mesh drawn through an instance (core/instance.h).
enum class ShapeKind : uint8_t { Mesh = 0, Sphere = 1, Plane = 2, Box = 3, Rectangle = 4, Disk = 5, Instance = 6 };

/// Identifies one primitive of the scene: shape kind, object index within that
/// kind's array of the Scene, and triangle index (meshes) or 0. For an
/// instance hit, object is the index in Scene::instances, prim the triangle
/// and part the mesh within the instance's prototype (0 for everything else).
struct PrimRef {
    ShapeKind kind = ShapeKind::Mesh;
    uint32_t object = 0;
    uint32_t prim = 0;
    uint32_t part = 0;
    bool operator==(const PrimRef&) const = default;
};

/// A complete surface hit, built by Scene::completeHit from an accelerator's
/// thin answer (PrimRef, t, u, v) so every accelerator produces identical hits.
struct Hit {
    float t = 0.f;
    Vec3f p;        // hit point, computed from the surface parametrisation
    Vec3f ng;       // unit geometric normal of the front side (not flipped towards the ray)
    Vec3f ns;       // unit shading normal, in the same hemisphere as ng
    Vec2f uv;       // texture coordinates (mesh UVs if present, else shape parameters); on a sphere,
                    // plane or box only where the hit's material has a texture (Scene::textured),
                    // else (0, 0): nothing else reads them
    PrimRef ref;
    uint32_t material = 0;
};

}  // namespace penumbra
