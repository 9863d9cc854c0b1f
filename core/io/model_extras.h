// What a model file (glTF, or a format Assimp reads) says beyond its meshes
// and materials: its camera and lights, which the caller may use.
#pragma once

#include <optional>
#include <vector>

#include "core/camera.h"
#include "core/scene.h"

namespace penumbra {

struct ModelExtras {
    std::optional<CameraDesc> camera;  // its first camera, in world space
    std::vector<PointLight> pointLights;
    std::vector<DirectionalLight> directionalLights;
};

}  // namespace penumbra
