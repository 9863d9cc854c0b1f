// Helpers shared by the tests: locating the project's assets and the optional
// third-party scenes in ../shared, and temporary directories.
#pragma once

#include <filesystem>
#include <string>

namespace penumbra::test {

/// <repo>/assets/<rel>
std::filesystem::path assetPath(const std::string& rel);

/// <repo>/../shared/scenes/<rel>; empty path when ../shared is absent
/// (tests that need it call GTEST_SKIP()).
std::filesystem::path sharedScenePath(const std::string& rel);

/// Directory with the built programs (penumbra, penumbra-bench, ...).
std::filesystem::path binaryDir();

/// A fresh, empty directory unique to the running test; removed at exit of the test program.
std::filesystem::path tempDir();

/// Writes text to a file (creating parent directories); returns the path.
std::filesystem::path writeFile(const std::filesystem::path& path, const std::string& text);

}  // namespace penumbra::test
