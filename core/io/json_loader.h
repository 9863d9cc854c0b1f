// The JSON scene format (docs/scene-format.md).
#pragma once

#include <filesystem>

#include "core/io/loaded_scene.h"
#include "core/log.h"

namespace penumbra {

/// A JSON scene file. Errors name the file and the JSON path (for example
/// "scene.json: /shapes/3/radius: must be > 0").
LoadedScene loadJsonScene(const std::filesystem::path& path, const LoadOptions& options, const Logger& log);

}  // namespace penumbra
