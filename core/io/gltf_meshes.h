// One glTF mesh primitive as a TriangleMesh placed in the world: triangles
// from lists, strips and fans (points and lines are not surfaces), positions,
// normals and tangents transformed, both uv sets in the scene's convention
// (v up), vertex colours kept aside for the caller.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/io/gltf_accessors.h"
#include "core/mesh.h"
#include "core/transform.h"

namespace penumbra {

struct GltfPrimitive {
    TriangleMesh mesh;          // empty indices: nothing to draw
    std::vector<Vec3f> colours; // COLOR_0 per vertex (RGB), or empty
    size_t droppedFaces = 0;    // on missing vertices or non-finite positions
};

/// The elements primitive `p` would add, for budgets: its vertices plus its
/// triangles (its index count, or vertex count, over three).
size_t gltfPrimitiveSize(const GltfAccessors& accessors, const tinygltf::Primitive& p, const std::string& where);

/// Reads primitive `p` placed by worldFromObject (a mirroring transform
/// keeps the front side the front side, and flips the tangents' handedness).
/// Attribute errors are Error(ParseError) naming the file and the accessor.
GltfPrimitive readGltfPrimitive(const GltfAccessors& accessors, const tinygltf::Primitive& p,
                                const Transform& worldFromObject, const std::string& where);

}  // namespace penumbra
