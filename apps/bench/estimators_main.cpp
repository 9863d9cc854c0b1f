// penumbra-estimators: renders a scene file with one of the direct-light
// estimators of the Whitted integrator, the comparison baseline that no
// public API offers included (uniform-area light samples,
// InternalSettings::areaLightSamples). scripts/bench_noise.py measures their
// noise with it.
//   penumbra-estimators SCENE -o OUT.pfm [--estimator mis|light|area] [--spp N]
//                       [--light-samples N] [--seed S] [--threads N]
//                       [--width W --height H] [--stats-json FILE]
// The scene file's render settings apply unless an option overrides them; a
// scene without a camera is framed as the penumbra command frames it. The
// statistics file holds render_seconds and the rays by kind, as penumbra's
// --stats-json does. Exit code 0 on success, 1 with a one-line error, 2 for
// usage errors.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/error.h"
#include "core/image_io.h"
#include "core/io/scene_loader.h"
#include "shading/renderer.h"

namespace penumbra {
namespace {

struct EstimatorOptions {
    std::string scene, output, estimator = "mis", statsJson;
    SettingsPatch overrides;  // what the command line sets over the scene file's settings
};

void writeStats(const std::string& path, const RenderStats& s) {
    const nlohmann::json j = {{"render_seconds", s.renderSeconds},
                              {"rays",
                               {{"camera", s.cameraRays},
                                {"shadow", s.shadowRays},
                                {"reflection", s.reflectionRays},
                                {"transmission", s.transmissionRays},
                                {"brdf", s.brdfRays},
                                {"total", s.totalRays()}}}};
    std::ofstream out(path);
    out << j.dump(1) << "\n";
    if (!out) throw Error(ErrorCode::IoError, path + ": cannot write the statistics");
}

void renderWithEstimator(const EstimatorOptions& o) {
    const Logger log([](LogLevel, std::string_view m) { std::fprintf(stderr, "penumbra-estimators: %.*s\n", int(m.size()), m.data()); },
                     LogLevel::Warning);
    LoadedScene loaded = loadScene(o.scene, LoadOptions{}, log);
    RenderSettings st;
    loaded.settings.applyTo(st);
    o.overrides.applyTo(st);
    st.integrator = IntegratorKind::Whitted;
    st.directLight = o.estimator == "mis" ? DirectLightSampling::Mis : DirectLightSampling::Light;
    InternalSettings internal;
    internal.areaLightSamples = o.estimator == "area";
    validateSettings(st);
    // Framed as the penumbra command frames a scene without a camera (its default field of view).
    constexpr float kFramingFovDegrees = 40.f;
    const CameraDesc camera = loaded.camera ? *loaded.camera
                                            : frameBounds(loaded.scene.bounds(), kFramingFovDegrees,
                                                          float(st.width) / float(st.height));
    const PreparedScene prepared(std::move(loaded.scene), PrepareOptions{}, log);
    Film film = makeFilm(st);
    const RenderStats stats = render(prepared, camera, st, film, {}, internal).stats;
    writeImage(o.output, film, ImageWriteOptions{});
    if (!o.statsJson.empty()) writeStats(o.statsJson, stats);
}

}  // namespace
}  // namespace penumbra

int main(int argc, char** argv) {
    penumbra::EstimatorOptions o;
    CLI::App app{"penumbra-estimators: a scene rendered with one of the direct-light estimators (scripts/bench_noise.py)"};
    app.add_option("scene", o.scene, "Scene file (JSON, OBJ, or a format Assimp reads)")->required();
    app.add_option("-o,--output", o.output, "Image to write")->required();
    app.add_option("--estimator", o.estimator,
                   "mis (light + BRDF samples), light (solid-angle light samples) or area (uniform-area light "
                   "samples, the estimator before solid-angle sampling)")
        ->check(CLI::IsMember({"mis", "light", "area"}))
        ->capture_default_str();
    app.add_option("--spp", o.overrides.spp, "Camera samples per pixel");
    app.add_option("--light-samples", o.overrides.lightSamples, "Light samples per light per shading point");
    app.add_option("--seed", o.overrides.seed, "Random seed");
    app.add_option("--threads", o.overrides.threads, "Render threads (0 = all cores)");
    app.add_option("--width", o.overrides.width, "Image width");
    app.add_option("--height", o.overrides.height, "Image height");
    app.add_option("--stats-json", o.statsJson, "Write render_seconds and the rays by kind as JSON to this file");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    try {
        penumbra::renderWithEstimator(o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra-estimators: %s\n", e.what());
        return 1;
    }
    return 0;
}
