#include "core/scene_edits.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "core/scene_range.h"

namespace penumbra {

namespace {

[[noreturn]] void refuse(const std::string& message) { throw Error(ErrorCode::InvalidArgument, message); }

bool nonNegative(const Rgb& c) {
    return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b) && c.r >= 0.f && c.g >= 0.f && c.b >= 0.f;
}

// The instance the scene was built with as number `id`; finalize keeps the
// order, so the numbers are sorted.
Instance& instanceNumbered(Scene& scene, uint32_t id) {
    auto it = std::lower_bound(scene.instances.begin(), scene.instances.end(), id,
                               [](const Instance& in, uint32_t n) { return in.sourceIndex < n; });
    if (it == scene.instances.end() || it->sourceIndex != id)
        refuse("edit: instance " + std::to_string(id) +
               " is not an instance of the prepared scene (no such index, dropped when it was prepared, or "
               "expanded into meshes because it emits light: prepare the edited scene instead)");
    return *it;
}

void moveInstance(Scene& scene, uint32_t id, const Transform& worldFromObject) {
    Instance& in = instanceNumbered(scene, id);
    const std::string what = "edit: instance " + std::to_string(id);
    if (!placeable(worldFromObject)) refuse(what + ": the transform must be finite and invertible");
    if (!withinSceneRange(instanceBounds(scene.prototypes[in.prototype], makeInstance(in.prototype, worldFromObject))))
        refuse(what + ": the transform moves it beyond +-1.8e18, the largest coordinate the accelerators represent");
    in.worldFromObject = worldFromObject;
    worldFromObject.inverse(in.objectFromWorld);
}

// Whether any prototype's face, or any instance's override, uses material `id`:
// then its emitting decides whether instances are expanded into meshes.
bool usedByInstances(const Scene& scene, uint32_t id) {
    for (const Instance& in : scene.instances)
        if (in.material == id) return true;
    for (const Prototype& p : scene.prototypes)
        for (const TriangleMesh& m : p.meshes) {
            if (m.faceMaterials.empty() ? m.material == id
                                        : std::find(m.faceMaterials.begin(), m.faceMaterials.end(), id) !=
                                              m.faceMaterials.end())
                return true;
        }
    return false;
}

void replaceMaterial(Scene& scene, uint32_t id, const Material& material) {
    const std::string what = "edit: material " + std::to_string(id);
    if (id >= scene.materials.size())
        refuse(what + " does not exist (the scene has " + std::to_string(scene.materials.size()) + " materials)");
    if (material.textureIndex >= static_cast<int>(scene.textures.size()))
        refuse(what + ": its texture is not one the prepared scene read: prepare the edited scene instead");
    if (material.isEmissive() != scene.materials[id].isEmissive() && usedByInstances(scene, id))
        refuse(what + ": prototypes use it, and an instance that emits light is expanded into meshes when prepared: "
                      "prepare the edited scene instead");
    scene.materials[id] = material;
}

template <class Light, class Field>
void setLight(std::vector<Light>& lights, uint32_t index, const Rgb& value, Field field, const char* kind) {
    const std::string what = std::string("edit: ") + kind + " light " + std::to_string(index);
    if (index >= lights.size())
        refuse(what + " does not exist (the scene has " + std::to_string(lights.size()) + ")");
    if (!nonNegative(value)) refuse(what + ": the colour must be finite and >= 0");
    lights[index].*field = value;
}

}  // namespace

void applyEdits(Scene& scene, const SceneEdits& edits) {
    for (const auto& [id, t] : edits.transforms) moveInstance(scene, id, t);
    for (const auto& [id, m] : edits.materials) replaceMaterial(scene, id, m);
    for (const auto& [i, c] : edits.pointLights) setLight(scene.pointLights, i, c, &PointLight::intensity, "point");
    for (const auto& [i, c] : edits.directionalLights)
        setLight(scene.directionalLights, i, c, &DirectionalLight::irradiance, "directional");
    if (edits.environmentRotateDegrees || edits.environmentScale) {
        if (!scene.environment) refuse("edit: the scene has no environment to turn or scale");
        if (edits.environmentRotateDegrees) {
            if (!std::isfinite(*edits.environmentRotateDegrees)) refuse("edit: environment rotation must be finite");
            scene.environment->rotateDegrees = *edits.environmentRotateDegrees;
        }
        if (edits.environmentScale) {
            if (!std::isfinite(*edits.environmentScale) || *edits.environmentScale < 0.f)
                refuse("edit: environment scale must be finite and >= 0");
            scene.environment->scale = *edits.environmentScale;
        }
    }
}

}  // namespace penumbra
