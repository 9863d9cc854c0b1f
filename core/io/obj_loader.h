// OBJ/MTL loading (docs/mtl-mapping.md) on top of tinyobjloader.
#pragma once

#include <filesystem>

#include "core/io/input_file.h"
#include "core/io/loaded_scene.h"
#include "core/io/obj_faces.h"
#include "core/log.h"
#include "core/transform.h"

namespace penumbra {

/// Reads an OBJ (and its MTL files) and appends its meshes, materials and
/// textures to `scene`, placed by worldFromObject. Faces with a Ke material
/// become emitters (the light set picks them up). Throws Error naming the file
/// for what cannot be read; warns (naming the file) for what can be skipped.
ObjStats appendObj(Scene& scene, const std::filesystem::path& objPath, const Transform& worldFromObject,
                   const LoadOptions& options, const Logger& log);

/// The same for an OBJ already opened (after its path check) by openInputFile.
ObjStats appendObj(Scene& scene, const InputFile& obj, const Transform& worldFromObject, const LoadOptions& options,
                   const Logger& log);

/// An OBJ file as a scene (no camera; the caller frames it).
LoadedScene loadObjScene(const std::filesystem::path& path, const LoadOptions& options, const Logger& log);

}  // namespace penumbra
