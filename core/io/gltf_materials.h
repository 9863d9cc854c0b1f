// glTF materials as Penumbra's metal-roughness materials (docs/mtl-mapping.md,
// "glTF"): factors, the texture of every core channel with its uv set,
// sampler and KHR_texture_transform, alpha, and the extensions
// KHR_materials_emissive_strength, _transmission and _ior.
#pragma once

#include <cstdint>

#include "core/io/gltf_model.h"
#include "core/log.h"
#include "core/scene.h"

namespace penumbra {

/// Appends the file's materials to `scene` in the file's order, then glTF's
/// default material (for primitives without one), and registers the
/// textures they use. Returns the index of the first; what is wrong with a
/// material (a bad alphaCutoff, a texture that does not exist, ...) is a
/// warning naming the file and the material, and the value is left at its default.
uint32_t appendGltfMaterials(const GltfFile& file, Scene& scene, const Logger& log);

}  // namespace penumbra
