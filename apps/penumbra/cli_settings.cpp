#include "cli_settings.h"

#include <string>

namespace penumbra::cli {

using pnb::Error;

pnb::RenderSettings settingsFrom(const Options& o, pnb::RenderSettings s) {
    if (o.width) s.width = *o.width;
    if (o.height) s.height = *o.height;
    if (o.spp) s.spp = *o.spp;
    if (o.lightSamples) s.lightSamples = *o.lightSamples;
    if (o.maxDepth) s.maxDepth = *o.maxDepth;
    if (o.threads) s.threads = *o.threads;
    if (o.tileSize) s.tileSize = *o.tileSize;
    if (o.seed) s.seed = *o.seed;
    if (o.lightSelection) s.lightSelection = *o.lightSelection;
    s.crop = o.crop;
    s.aovs = o.aovs;
    if (o.integrator) s.integrator = *o.integrator;
    if (o.directLight) s.directLight = *o.directLight;
    return s;
}

void applyCameraOptions(const Options& o, pnb::Camera& c) {
    if (o.eye) c.eye = *o.eye;
    if (o.lookAt) c.lookAt = *o.lookAt;
    if (o.up) c.up = *o.up;
    if (o.fov) c.vfovDegrees = *o.fov;
    if (o.aperture) c.aperture = *o.aperture;
    if (o.focusDistance) c.focusDistance = *o.focusDistance;
}

void applyLightOptions(const Options& o, pnb::Scene& scene) {
    auto named = [](const char* option, auto&& apply) {
        try {
            apply();
        } catch (const Error& e) {
            throw UsageError(std::string(option) + ": " + e.what());
        }
    };
    if (o.ambient) named("--ambient", [&] { scene.setAmbient(*o.ambient); });
    if (o.background) named("--background", [&] { scene.setBackground(*o.background); });
    if (o.envColor) named("--env", [&] { scene.setEnvironment(*o.envColor); });
    // The image's own errors name the file (opened here, decoded when the scene is prepared).
    if (o.envImage) scene.setEnvironmentImage(o.envImage->string(), o.envRotate.value_or(0.f));
}

}  // namespace penumbra::cli
