// Tangent frames from a mesh's uv layout, for normal maps whose file gives no
// tangents: each triangle's dp/du (with the handedness of dp/dv), summed at
// its vertices and made perpendicular to each vertex's normal.
#pragma once

#include <cstddef>
#include <optional>

#include "core/math.h"
#include "core/mesh.h"

namespace penumbra {

/// The tangent of a triangle with corners p and texture coordinates uv
/// (v up): dp/du made perpendicular to n and normalised, and the sign
/// with which sign * cross(n, tangent) follows dp/dv. nullopt where the uvs
/// are degenerate (collinear) or the result is not finite.
std::optional<Tangent> triangleTangent(const Vec3f p[3], const Vec2f uv[3], const Vec3f& n);

/// The tangent of a surface whose derivatives along its texture coordinates
/// are dpdu and dpdv (any lengths) where its unit normal is n: dp/du made
/// perpendicular to n and normalised, with the sign that makes sign *
/// cross(n, tangent) follow dp/dv. nullopt where dp/du is parallel to n or
/// anything is not finite.
std::optional<Tangent> tangentFrom(const Vec3f& dpdu, const Vec3f& dpdv, const Vec3f& n);

/// Fills mesh.tangents from uv set `uvSet` (0: uvs, 1: uvs1), one per vertex,
/// perpendicular to the vertex normals (or to the triangles' normals where
/// the mesh has none). False, leaving the mesh as it was, when it has no such
/// uvs. Vertices whose triangles all have degenerate uvs get a tangent
/// perpendicular to the normal; their count goes to *degenerate.
bool generateTangents(TriangleMesh& mesh, int uvSet, size_t* degenerate = nullptr);

/// Some unit vector perpendicular to unit n (the tangent of last resort).
Vec3f anyPerpendicular(const Vec3f& n);

}  // namespace penumbra
