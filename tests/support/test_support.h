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

/// `bytes` in base64 (RFC 4648, with padding), as data: URIs hold them.
std::string base64(const std::string& bytes);

/// The binary buffer of twoQuadsGltf: two 1.5 x 1.5 quads in the z = 0
/// plane facing +z, centred at x = -1.25 and x = +1.25 (4 + 4 float3
/// positions, then 6 uint16 indices).
std::string twoQuadsBuffer();

/// A glTF 2.0 file: quad 0 emits (1, 0.5, 0.25) (black base colour), quad 1
/// is diffuse with base colour (0.8, 0.4, 0.2) (metallic 0, roughness 1); a
/// point light of intensity 4 at (1.25, 0, 2) (KHR_lights_punctual); a camera
/// at (0, 0, 5) looking along -z with a vertical fov of 0.8 rad. The buffer
/// is `bufferUri` (a file name), or embedded as base64 when empty.
std::string twoQuadsGltf(const std::string& bufferUri = "");

}  // namespace penumbra::test
