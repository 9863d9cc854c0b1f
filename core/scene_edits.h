// Edits of a finalized scene: what Renderer::update changes in a prepared
// scene without preparing it again (docs/embedding.md, "Editing a prepared
// scene"). Applied to a copy, they give the scene that preparing the edited
// scene from scratch would finalize into, or an error that names the edit.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "core/scene.h"

namespace penumbra {

struct SceneEdits {
    /// Instance (its index as the scene was built, Instance::sourceIndex) -> new worldFromObject.
    std::vector<std::pair<uint32_t, Transform>> transforms;
    /// Material id -> new material (its texture, if any, already one of Scene::textures).
    std::vector<std::pair<uint32_t, Material>> materials;
    /// Point light index -> intensity; directional light index -> irradiance.
    std::vector<std::pair<uint32_t, Rgb>> pointLights, directionalLights;
    /// The environment's rotation about +y (degrees) and scale.
    std::optional<float> environmentRotateDegrees, environmentScale;

    bool movesInstances() const { return !transforms.empty(); }
};

/// Applies `edits` to `scene` (finalized). Throws Error(InvalidArgument)
/// naming the first edit that is not one: an id that names nothing, a
/// non-finite or singular transform, a non-finite or negative colour or
/// scale, an environment edit of a scene without one, and the edits that
/// would change what preparing makes of the scene's instances (moving an
/// instance that was expanded into meshes because it emits light, or beyond
/// the coordinate range; making a material that prototypes use start or stop
/// emitting). `scene` is left half-edited then: apply to a copy.
void applyEdits(Scene& scene, const SceneEdits& edits);

}  // namespace penumbra
