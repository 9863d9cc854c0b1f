// Smooth vertex normals for meshes read without any (PLY and STL scans, OBJ
// files without `vn`): the one place every mesh loader asks for them.
#pragma once

#include "core/mesh.h"

namespace penumbra {

/// Gives a mesh without normals smooth ones: each triangle corner gets the
/// angle-weighted mean of the normals of the triangles around the same
/// position (vertices welded by position, so UV seams and unindexed formats
/// such as STL still smooth) whose normals lie within `maxAngleDegrees` of
/// the corner's own triangle; vertices whose corners end up with different
/// normals are split, so edges sharper than the threshold stay sharp.
/// Leaves the mesh as it is when it has normals or the angle is 0 (faceted).
void smoothNormals(TriangleMesh& mesh, float maxAngleDegrees);

}  // namespace penumbra
