// Mesh and scene files read through Assimp (PLY, STL, FBX, COLLADA and the
// other formats it reads, glTF excepted; docs/mtl-mapping.md, "Assimp formats").
// Every file, the model and what it references, is read through the path
// policy and opened once (input_file.h): Assimp never opens a path itself.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/io/input_file.h"
#include "core/io/model_extras.h"
#include "core/io/obj_faces.h"
#include "core/log.h"
#include "core/scene.h"
#include "core/transform.h"

namespace penumbra {

/// Whether Assimp reads files with this extension (".ply", any case).
bool assimpReadsExtension(const std::string& extension);

/// The extensions Assimp reads, lower case with the dot, sorted.
std::vector<std::string> assimpExtensions();

/// Appends the model's meshes (placed by worldFromObject) and materials to
/// `scene`; its camera and lights go to `extras`. Throws Error naming the file
/// when Assimp cannot read it (or a file it references); warns for what is skipped.
ObjStats appendAssimp(Scene& scene, const InputFile& model, const Transform& worldFromObject, const LoadOptions& options,
                      const Logger& log, ModelExtras& extras);

}  // namespace penumbra
