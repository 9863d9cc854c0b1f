#include "core/io/mesh_options.h"

#include "core/mesh_normals.h"

namespace penumbra {

void applyMeshOptions(Scene& scene, size_t firstMesh, size_t firstMaterial, const LoadOptions& options) {
    if (options.meshModel)
        for (size_t i = firstMaterial; i < scene.materials.size(); ++i) scene.materials[i].model = *options.meshModel;
    for (size_t i = firstMesh; i < scene.meshes.size(); ++i) smoothNormals(scene.meshes[i], options.smoothAngleDegrees);
}

}  // namespace penumbra
