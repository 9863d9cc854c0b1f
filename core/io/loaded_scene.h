// What a loader returns: the scene and what the file says about the view.
#pragma once

#include <filesystem>
#include <optional>

#include "core/camera.h"
#include "core/io/load_options.h"
#include "core/render_settings.h"
#include "core/scene.h"

namespace penumbra {

/// A scene as loaded from a file, with what the file says about the view.
struct LoadedScene {
    Scene scene;
    std::optional<CameraDesc> camera;  // JSON may set it; OBJ files never do
    SettingsPatch settings;            // JSON "render" block
    std::filesystem::path sourcePath;
};

}  // namespace penumbra
