// What LoadOptions asks of every mesh read from a file (OBJ or Assimp): the
// Phong model of its materials and smooth normals where it has none.
#pragma once

#include <cstddef>

#include "core/io/load_options.h"
#include "core/scene.h"

namespace penumbra {

/// Applies options.meshModel to scene.materials[firstMaterial..] and
/// smoothNormals (core/mesh_normals.h) with options.smoothAngleDegrees to
/// scene.meshes[firstMesh..]: what a loader appended from one file.
void applyMeshOptions(Scene& scene, size_t firstMesh, size_t firstMaterial, const LoadOptions& options);

}  // namespace penumbra
