// Loading scenes from files: dispatch on the extension to the OBJ/MTL loader
// (obj_loader.h), the Assimp formats (model_file.h) or the JSON loader (json_loader.h); automatic framing. The
// path policy they all read through is at the bottom (path_policy.h,
// input_file.h). This header gives callers the whole loading interface.
#pragma once

#include <filesystem>

#include "core/camera.h"
#include "core/io/json_loader.h"
#include "core/io/load_options.h"
#include "core/io/loaded_scene.h"
#include "core/io/obj_loader.h"
#include "core/io/path_policy.h"
#include "core/log.h"

namespace penumbra {

/// Dispatches on the extension (.json, .obj or one Assimp reads, case-insensitive);
/// an unknown one is an error naming the file and listing the supported formats.
LoadedScene loadScene(const std::filesystem::path& path, const LoadOptions& options, const Logger& log);

/// A camera that frames the scene's bounds (used for scene files without a camera):
/// looks along -z at the bounds' centre from far enough to see the whole box,
/// or, where the box's face towards +z is small (a model seen edge-on from
/// the front), from a raised three-quarter view (45 degrees round towards +x, 30 up).
CameraDesc frameBounds(const Bounds3f& bounds, float vfovDegrees, float aspect);

}  // namespace penumbra
