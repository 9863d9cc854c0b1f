// What a caller allows the loaders to read, and how strictly they read it.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <vector>

#include "core/material.h"

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
    /// The Phong model of the materials read from mesh files (OBJ/MTL, Assimp
    /// formats); unset: each loader's default (normalised). JSON materials keep their own.
    std::optional<PhongModel> meshModel;
    /// Meshes read from files without vertex normals get smooth normals across
    /// edges whose faces meet at less than this angle (degrees, [0, 180]); 0 = faceted.
    float smoothAngleDegrees = kDefaultSmoothAngleDegrees;
    static constexpr float kDefaultSmoothAngleDegrees = 30.f;
};

}  // namespace penumbra
