// Mesh and model files, by extension: OBJ/MTL (obj_loader.h), glTF
// (gltf_loader.h) or the other formats Assimp reads (assimp_loader.h). What the command line renders on its own
// and what a JSON `mesh` entry's "file" names.
#pragma once

#include <filesystem>
#include <string>

#include "core/io/assimp_loader.h"
#include "core/io/input_file.h"
#include "core/io/loaded_scene.h"
#include "core/io/obj_faces.h"
#include "core/log.h"
#include "core/transform.h"

namespace penumbra {

/// What one model file added, and its camera and lights (never added to the scene here).
struct ModelFile {
    ObjStats stats;
    ModelExtras extras;
};

/// Whether the extension (".ply", any case) is .obj, glTF's or one Assimp reads.
bool isModelExtension(const std::string& extension);

/// ".obj", glTF's and Assimp's other extensions, comma-separated, for error messages.
std::string modelFormatsText();

/// Appends the model's meshes and materials, dispatching on model.path()'s
/// extension; throws Error(InvalidArgument) naming the file and listing the
/// supported formats when no loader reads it.
ModelFile appendModelFile(Scene& scene, const InputFile& model, const Transform& worldFromObject,
                          const LoadOptions& options, const Logger& log);

/// A model file as a scene: its meshes, its lights, its first camera (unset
/// when it has none; the caller frames it). Nothing to render is an error.
LoadedScene loadModelScene(const std::filesystem::path& path, const LoadOptions& options, const Logger& log);

}  // namespace penumbra
