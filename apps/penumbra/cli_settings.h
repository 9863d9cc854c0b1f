// What the command-line options do to the scene's settings, camera and light:
// shared by penumbra and penumbra-mpi, so both render the same image.
#pragma once

#include <penumbra/penumbra.hpp>

#include "cli_options.h"

namespace penumbra::cli {

/// The scene file's settings (`fromScene`), overridden by the command line.
pnb::RenderSettings settingsFrom(const Options& o, pnb::RenderSettings fromScene);

/// --eye, --look-at, --up, --fov, --aperture, --focus-distance.
void applyCameraOptions(const Options& o, pnb::Camera& c);

/// --ambient, --background and --env (replacing the scene's environment), through pnb::Scene, which holds
/// the colours to the same limits as a scene file's values (a UsageError naming the option) and opens an
/// --env image (a pnb::Error naming the file: a file problem, not a usage error).
void applyLightOptions(const Options& o, pnb::Scene& scene);

}  // namespace penumbra::cli
