// libFuzzer target: the input is an OBJ file, optionally followed by a line
// "#---mtl---" and the text of its material library. Both go through
// appendObj (pre-pass, tinyobjloader, validation, triangulation) as
// "fuzz.obj" and "fuzz.mtl"; a loaded scene is finalized and checked.
// Penumbra Errors are the expected way to fail; anything else (a crash, a
// sanitizer report, another exception, a broken invariant) is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.h"
#include "core/transform.h"
#include "fuzz_support.h"

namespace {

constexpr std::string_view kMtlSeparator = "\n#---mtl---\n";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace penumbra;
    static const fuzz::ScratchDir dir;  // libFuzzer gives no context pointer: one directory per process
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    const size_t cut = input.find(kMtlSeparator);
    const std::string_view obj = input.substr(0, cut);
    const std::filesystem::path objPath = dir.write("fuzz.obj", obj);
    if (cut != std::string_view::npos) {
        dir.write("fuzz.mtl", input.substr(cut + kMtlSeparator.size()));
    } else {
        std::error_code ec;
        std::filesystem::remove(dir.path() / "fuzz.mtl", ec);
    }

    const Logger log = fuzz::silentLogger();
    for (bool strict : {false, true}) {
        Scene scene;
        try {
            ObjStats stats = appendObj(scene, objPath, Transform(), fuzz::confinedTo(dir, strict), log);
            if (stats.triangles != scene.triangleCount()) fuzz::violated("ObjStats::triangles != the scene's count");
            scene.finalize(log);
            fuzz::checkScene(scene);
            (void)scene.bounds();
        } catch (const Error&) {
            // A clean rejection; strict mode rejects at least what lenient mode does.
            if (!strict) break;
        }
    }
    return 0;
}
