// Whether a mesh is convex with its triangles facing outwards, for the
// accelerators' `leaving` hints: a ray that leaves such a mesh above one of
// its triangles cannot meet the mesh again, so a query may leave it out.
#pragma once

#include "core/mesh.h"

namespace penumbra {

/// How far any vertex lies in front of any triangle's plane (the side its
/// counter-clockwise winding faces), in scene units: about zero, up to the
/// rounding of the coordinates, for a convex mesh whose triangles face
/// outwards (a box, a capped cylinder, an icosphere). Infinity where the mesh
/// is not so (a vertex lies farther than 2^-17 of the largest coordinate in
/// front of some triangle), is empty, or is too large to check: the test
/// takes triangles x vertices steps, and stops at 2^22 of them.
float convexSlack(const TriangleMesh& mesh);

}  // namespace penumbra
