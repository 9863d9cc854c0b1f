// glTF 2.0 files (.gltf, .glb) read by tinygltf (gltf_model.h): the node
// hierarchy walked without recursion, meshes placed in the world, materials
// with every core texture channel (gltf_materials.h), tangent frames for
// normal maps, the first perspective camera and KHR_lights_punctual lights
// (docs/mtl-mapping.md, "glTF").
#pragma once

#include "core/io/input_file.h"
#include "core/io/load_options.h"
#include "core/io/model_extras.h"
#include "core/io/obj_faces.h"
#include "core/log.h"
#include "core/scene.h"
#include "core/transform.h"

namespace penumbra {

/// Whether the extension (".gltf", ".glb", any case) is glTF's.
bool isGltfExtension(const std::string& extension);

/// Appends the model's meshes (placed by worldFromObject) and materials to
/// `scene`; its camera and lights go to `extras`. Throws Error naming the file
/// when it cannot be read (readGltfFile), when its nodes would place more than
/// kMaxGltfElements vertices and triangles; warns for what is skipped.
ObjStats appendGltf(Scene& scene, const InputFile& model, const Transform& worldFromObject, const LoadOptions& options,
                    const Logger& log, ModelExtras& extras);

/// The most vertices and triangles together that the nodes of one glTF file
/// may place (a mesh counts once per node that draws it), checked before any
/// is made: 2^28, some 10 GiB of meshes.
inline constexpr size_t kMaxGltfElements = size_t(1) << 28;

}  // namespace penumbra
