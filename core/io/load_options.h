// What a caller allows the loaders to read, and how strictly they read it.
#pragma once

#include <filesystem>
#include <functional>
#include <vector>

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

}  // namespace penumbra
