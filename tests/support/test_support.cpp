#include "support/test_support.h"

#include <gtest/gtest.h>
#include <unistd.h>

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

}  // namespace penumbra::test
