#include "support/test_support.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <fstream>

namespace penumbra::test {
namespace fs = std::filesystem;

fs::path assetPath(const std::string& rel) { return fs::path(PENUMBRA_SOURCE_DIR) / "assets" / rel; }

fs::path sharedScenePath(const std::string& rel) {
    fs::path p = fs::path(PENUMBRA_SOURCE_DIR).parent_path() / "shared" / "scenes" / rel;
    std::error_code ec;
    return fs::exists(p, ec) ? p : fs::path();
}

fs::path binaryDir() { return fs::path(PENUMBRA_BINARY_DIR) / "bin"; }

fs::path tempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "global";
    for (char& c : name)
        if (c == '/') c = '_';
    fs::path dir = fs::temp_directory_path() / ("penumbra-test-" + std::to_string(::getpid())) / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

fs::path writeFile(const fs::path& path, const std::string& text) {
    fs::create_directories(path.parent_path());
    std::ofstream out(path, std::ios::binary);
    out << text;
    return path;
}

std::string base64(const std::string& bytes) {
    static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 2]));
        out += kDigits[(v >> 18) & 63];
        out += kDigits[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? kDigits[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? kDigits[v & 63] : '=';
    }
    return out;
}

std::string twoQuadsBuffer() {
    std::string b;
    auto put = [&](const void* p, size_t n) { b.append(static_cast<const char*>(p), n); };
    for (float cx : {-1.25f, 1.25f}) {
        const float x0 = cx - 0.75f, x1 = cx + 0.75f;
        const float q[4][3] = {{x0, -0.75f, 0.f}, {x1, -0.75f, 0.f}, {x1, 0.75f, 0.f}, {x0, 0.75f, 0.f}};
        put(q, sizeof q);
    }
    const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    put(idx, sizeof idx);
    return b;  // 96 + 12 bytes
}

std::string twoQuadsGltf(const std::string& bufferUri) {
    const std::string buffer = twoQuadsBuffer();
    const std::string uri = bufferUri.empty() ? "data:application/octet-stream;base64," + base64(buffer) : bufferUri;
    return R"({
  "asset": {"version": "2.0"},
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "color": [1, 1, 1], "intensity": 4}]}},
  "scene": 0,
  "scenes": [{"nodes": [0, 1, 2, 3]}],
  "nodes": [
    {"name": "lamp", "mesh": 0},
    {"name": "card", "mesh": 1},
    {"name": "bulb", "translation": [1.25, 0, 2], "extensions": {"KHR_lights_punctual": {"light": 0}}},
    {"name": "view", "translation": [0, 0, 5], "camera": 0}
  ],
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "aspectRatio": 1.0, "znear": 0.1}}],
  "meshes": [
    {"name": "lamp", "primitives": [{"attributes": {"POSITION": 0}, "indices": 2, "material": 0}]},
    {"name": "card", "primitives": [{"attributes": {"POSITION": 1}, "indices": 2, "material": 1}]}
  ],
  "materials": [
    {"name": "glow", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0, "roughnessFactor": 1},
     "emissiveFactor": [1, 0.5, 0.25]},
    {"name": "clay", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.4, 0.2, 1], "metallicFactor": 0, "roughnessFactor": 1}}
  ],
  "buffers": [{"byteLength": )" + std::to_string(buffer.size()) + R"(, "uri": ")" + uri + R"("}],
  "bufferViews": [
    {"buffer": 0, "byteOffset": 0, "byteLength": 96, "target": 34962},
    {"buffer": 0, "byteOffset": 96, "byteLength": 12, "target": 34963}
  ],
  "accessors": [
    {"bufferView": 0, "byteOffset": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-2, -0.75, 0], "max": [-0.5, 0.75, 0]},
    {"bufferView": 0, "byteOffset": 48, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0.5, -0.75, 0], "max": [2, 0.75, 0]},
    {"bufferView": 1, "byteOffset": 0, "componentType": 5123, "count": 6, "type": "SCALAR"}
  ]
}
)";
}

}  // namespace penumbra::test
