#include "option_checks.h"

#include <filesystem>
#include <optional>
#include <string>

#include "cli_settings.h"
#include "outputs.h"

namespace penumbra::cli {

namespace fs = std::filesystem;
using pnb::Error;
using pnb::ErrorCode;

void precheckOptions(const Options& o) {
    asUsage([&] {
        pnb::RenderSettings s = settingsFrom(o, {});
        s.crop.reset();  // the crop is checked against the final size later
        pnb::validate(s);
        if (o.eye && o.lookAt) {
            pnb::Camera c;
            applyCameraOptions(o, c);
            pnb::validate(c);
        }
    });
    // The colours against the scene's limits, and the --env image opened as the
    // loaded scene will open it: a missing file, a folder or a FIFO is the same
    // file error (exit code 1) now as later.
    pnb::Scene probe;
    applyLightOptions(o, probe);
    try {
        pnb::checkImagePath(o.output.string());
    } catch (const Error& e) {
        if (e.code() == ErrorCode::InvalidArgument) throw UsageError(std::string("-o: ") + e.what());  // not an image format
        throw;
    }
    std::error_code ec;
    // symlink_status: a symlink loop or a FIFO exists, and the loader says what it is.
    if (fs::symlink_status(o.scene, ec).type() == fs::file_type::not_found)
        throw Error(ErrorCode::FileNotFound, o.scene.string() + ": no such file");
    precheckOutputs(o);
}

pnb::RenderSettings checkedSettings(const Options& o, const pnb::Scene& scene) {
    const pnb::RenderSettings settings = settingsFrom(o, scene.settings());
    asUsage([&] { pnb::validate(settings); });
    return settings;
}

pnb::Camera checkedCamera(const Options& o, const pnb::Scene& scene, const pnb::RenderSettings& settings) {
    pnb::Camera camera = scene.defaultCamera(float(settings.width) / float(settings.height), o.fov.value_or(40.f));
    std::optional<Error> sceneCamera;  // framing a scene of absurd extent can fail
    try {
        pnb::validate(camera);
    } catch (const Error& e) {
        sceneCamera = Error(e.code(), o.scene.string() + ": " + e.what());
    }
    applyCameraOptions(o, camera);
    if (sceneCamera) {
        try {
            pnb::validate(camera);
        } catch (const Error&) {
            throw *sceneCamera;
        }
    }
    // The scene's camera was valid: a failure now is the command line's.
    asUsage([&] { pnb::validate(camera); });
    return camera;
}

}  // namespace penumbra::cli
