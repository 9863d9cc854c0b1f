// libFuzzer target: model files read through Assimp (core/io/assimp_loader.cpp).
// The first byte of the input picks the format (kFormats[byte % size]), the
// rest is the file, loaded by loadScene as "fuzz.<ext>" next to a valid glTF
// buffer "fuzz.bin" (so that inputs referring to it reach that path); a loaded
// scene is finalized and checked. Penumbra Errors are the expected way to
// fail; anything else (a crash, a hang, a sanitizer report, another
// exception, a broken invariant) is a finding.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "core/error.h"
#include "fuzz_support.h"

namespace {

// Appended formats keep the earlier ones' first bytes (the seeds use 0 to 9).
constexpr std::array<std::string_view, 10> kFormats = {"ply", "stl", "gltf", "glb", "off", "dae", "fbx", "3ds", "x", "ac"};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace penumbra;
    static const fuzz::ScratchDir dir;
    if (size == 0) return 0;
    static const bool buffer = [] {
        // Two float3 positions and a triangle's uint16 indices: enough for small accessors.
        const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        const uint16_t idx[4] = {0, 1, 2, 0};
        std::string b(reinterpret_cast<const char*>(p), sizeof p);
        b.append(reinterpret_cast<const char*>(idx), sizeof idx);
        dir.write("fuzz.bin", b);
        return true;
    }();
    (void)buffer;
    const std::string ext(kFormats[data[0] % kFormats.size()]);
    const std::filesystem::path file =
        dir.write("fuzz." + ext, std::string_view(reinterpret_cast<const char*>(data + 1), size - 1));

    const Logger log = fuzz::silentLogger();
    try {
        LoadedScene loaded = loadScene(file, fuzz::confinedTo(dir, false), log);
        loaded.scene.finalize(log);
        fuzz::checkScene(loaded.scene);
        (void)loaded.scene.bounds();
    } catch (const Error&) {
        // a clean rejection
    }
    std::error_code ec;
    std::filesystem::remove(file, ec);
    return 0;
}
