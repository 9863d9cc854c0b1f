// Loading scenes from files: OBJ/MTL (obj_loader.cpp) and JSON (scene_file.cpp).
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/log.h"
#include "core/render_settings.h"
#include "core/scene.h"
#include "core/transform.h"

namespace penumbra {

struct LoadOptions {
    /// Strict mode: what would be skipped with a warning is an error instead.
    bool strict = false;
    /// When non-empty, only files below one of these directories may be read
    /// (the scene file itself, mtllib, textures, meshes referenced from JSON).
    std::vector<std::filesystem::path> allowedRoots;
    /// Unrestricted loading (allowedRoots empty) can still report the files it
    /// reads outside these directories to onReadOutside (the CLI passes the
    /// scene file's folder and prints one summary line).
    std::vector<std::filesystem::path> noticeRoots;
    std::function<void(const std::filesystem::path&)> onReadOutside;
};

/// A scene as loaded from a file, with what the file says about the view.
struct LoadedScene {
    Scene scene;
    std::optional<CameraDesc> camera;  // JSON may set it; OBJ files never do
    SettingsPatch settings;            // JSON "render" block
    std::filesystem::path sourcePath;
};

/// What appendObj added, for callers that report it.
struct ObjStats {
    size_t triangles = 0;
    size_t emissiveTriangles = 0;
    size_t droppedFaces = 0;   // bad vertex indices / non-finite positions / degenerate
    size_t materials = 0;
};

/// Reads an OBJ (and its MTL files) and appends its meshes, materials and
/// textures to `scene`, placed by worldFromObject. Faces with a Ke material
/// become emitters (the light set picks them up). Throws Error naming the file
/// for what cannot be read; warns (naming the file) for what can be skipped.
ObjStats appendObj(Scene& scene, const std::filesystem::path& objPath, const Transform& worldFromObject,
                   const LoadOptions& options, const Logger& log);

/// An OBJ file as a scene (no camera; the caller frames it).
LoadedScene loadObjScene(const std::filesystem::path& path, const LoadOptions& options, const Logger& log);

/// A JSON scene file (docs/scene-format.md). Errors name the file and the JSON
/// path (for example "scene.json: /shapes/3/radius: must be > 0").
LoadedScene loadJsonScene(const std::filesystem::path& path, const LoadOptions& options, const Logger& log);

/// Dispatches on the extension (.obj or .json, case-insensitive).
LoadedScene loadScene(const std::filesystem::path& path, const LoadOptions& options, const Logger& log);

/// A camera that frames the scene's bounds (used for OBJ files without camera options):
/// looks along -z at the bounds' centre from far enough to see the whole box.
CameraDesc frameBounds(const Bounds3f& bounds, float vfovDegrees, float aspect);

/// Checks `file` against options.allowedRoots; throws Error(InvalidArgument)
/// naming the file when it lies outside all of them. When unrestricted, only
/// reports files outside options.noticeRoots (if any) to options.noticeLog.
/// `willRead` = false for checks made before probing the file system (the
/// file actually read is checked again), so each read is reported once.
void checkPathAllowed(const std::filesystem::path& file, const LoadOptions& options, bool willRead = true);

}  // namespace penumbra
