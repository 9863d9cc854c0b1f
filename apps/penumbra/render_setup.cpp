#include "render_setup.h"

#include <unistd.h>

#include <string>

#include "cli_settings.h"
#include "option_checks.h"
#include "outputs.h"

namespace penumbra::cli {
namespace {

using pnb::Error;
using pnb::ErrorCode;

uint64_t physicalMemoryBytes() {
    long pages = ::sysconf(_SC_PHYS_PAGES), size = ::sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? uint64_t(pages) * uint64_t(size) : 0;
}

/// Bytes the largest buffers of a render hold at once: the framebuffer, plus
/// the float copy writeImage makes of it (10 channels for an EXR with AOVs, else 3).
uint64_t peakImageBytes(const pnb::RenderSettings& s, bool exrWithAovs) {
    const pnb::CropWindow w = pnb::renderWindow(s);
    const int64_t pixels = int64_t(w.x1 - w.x0) * (w.y1 - w.y0);
    const uint64_t outputPerPixel = (exrWithAovs ? 10 : 3) * sizeof(float) + (s.aovs && !exrWithAovs ? 7 * sizeof(float) : 0);
    return pnb::Framebuffer::bytesNeeded(s) + uint64_t(pixels) * outputPerPixel;
}

void checkImageMemory(const Options& o, const pnb::RenderSettings& s) {
    const uint64_t imageBytes = peakImageBytes(s, isExr(o.output) && o.aovs);
    const uint64_t ram = physicalMemoryBytes();
    if (ram && imageBytes > ram / 2)
        throw Error(ErrorCode::OutOfMemory, "a " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                                                " image needs " + std::to_string(imageBytes >> 20) +
                                                " MiB for its framebuffer and output, more than half of this machine's memory");
}

}  // namespace

LoadedScene loadForRender(const Options& o, const pnb::Renderer& renderer, const char* program, bool lead) {
    SceneReads reads;
    LoadedScene loaded{renderer.loadScene(o.scene.string(), loadOptionsFor(o, reads)), {}, {}};
    checkSceneReads(o, reads, lead ? program : nullptr);
    loaded.settings = checkedSettings(o, loaded.scene);
    if (lead) checkImageMemory(o, loaded.settings);
    loaded.camera = checkedCamera(o, loaded.scene, loaded.settings);
    applyLightOptions(o, loaded.scene);
    return loaded;
}

pnb::PreparedScene prepareForRender(const Options& o, const pnb::Renderer& renderer, pnb::Scene scene) {
    pnb::PrepareOptions options;
    options.accelerator = o.accel;
    options.quality = o.buildQuality;
    const bool sky = scene.hasEnvironment();  // an environment alone is an image (of the sky)
    pnb::PreparedScene prepared = renderer.prepare(std::move(scene), options);
    if (prepared.primitiveCount() == 0 && !sky)
        throw Error(ErrorCode::InvalidScene,
                    o.scene.string() + ": nothing to render (no shapes, no mesh with a valid triangle, no environment)");
    return prepared;
}

}  // namespace penumbra::cli
