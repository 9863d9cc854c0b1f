// libFuzzer target: the input is a JSON scene file, loaded by loadJsonScene
// as "scene.json" next to a small valid mesh ("mesh.obj" with "mesh.mtl") and
// an empty "tex.png", so that inputs referring to them reach those paths too.
// A loaded scene is finalized and checked, and its camera and render settings
// are validated. Penumbra Errors are the expected way to fail; anything else
// (a crash, a sanitizer report, another exception, a broken invariant) is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/camera.h"
#include "core/error.h"
#include "core/render_settings.h"
#include "fuzz_support.h"

namespace {

constexpr std::string_view kMesh =
    "mtllib mesh.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "vn 0 0 1\n"
    "usemtl gem\n"
    "f 1/1/1 2/2/1 3/3/1 4/4/1\n"
    "usemtl glow\n"
    "f 1 2 5\nf 2 3 5\n";
constexpr std::string_view kMtl =
    "newmtl gem\nKd 0.2 0.4 0.8\nKs 0.5 0.5 0.5\nNs 80\nillum 3\nmap_Kd tex.png\n"
    "newmtl glow\nKd 0 0 0\nKe 4 4 4\n";

const penumbra::fuzz::ScratchDir& scratch() {
    static const penumbra::fuzz::ScratchDir dir;  // libFuzzer gives no context pointer: one per process
    static const bool ready = [] {
        dir.write("mesh.obj", kMesh);
        dir.write("mesh.mtl", kMtl);
        dir.write("tex.png", "");
        return true;
    }();
    (void)ready;
    return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace penumbra;
    const fuzz::ScratchDir& dir = scratch();
    const std::filesystem::path path =
        dir.write("scene.json", std::string_view(reinterpret_cast<const char*>(data), size));
    const Logger log = fuzz::silentLogger();
    for (bool strict : {false, true}) {
        try {
            LoadedScene loaded = loadJsonScene(path, fuzz::confinedTo(dir, strict), log);
            loaded.scene.finalize(log);
            fuzz::checkScene(loaded.scene);
            RenderSettings settings;
            loaded.settings.applyTo(settings);
            // The loader promises that a patch it returns always validates.
            try {
                validateSettings(settings);
            } catch (const Error&) {
                fuzz::violated("render settings from a loaded scene do not validate");
            }
            if (loaded.camera) {
                try {
                    validateCamera(*loaded.camera);
                } catch (const Error&) {
                    fuzz::violated("a camera from a loaded scene does not validate");
                }
            }
        } catch (const Error&) {
            if (!strict) break;  // strict mode rejects at least what lenient mode does
        }
    }
    return 0;
}
