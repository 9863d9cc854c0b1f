// Which bad option values are usage errors (exit code 2) and when they are
// found: before any work where the scene is not needed, after loading where it
// is (a crop outside the scene's image, a camera made invalid by --fov). Shared
// by penumbra and penumbra-mpi, so that both refuse a command line alike.
#pragma once

#include <penumbra/penumbra.hpp>

#include "cli_options.h"

namespace penumbra::cli {

/// Runs `check`; its pnb::Error becomes a UsageError: what it checks is a
/// command-line value (on top of values known to be valid).
template <class F>
void asUsage(F&& check) {
    try {
        check();
    } catch (const pnb::Error& e) {
        throw UsageError(e.what());
    }
}

/// Everything that can be checked without reading the scene: the settings,
/// the camera when --eye and --look-at give it, the light colours, the image
/// format of -o (UsageError); the scene file exists, the --env image opens,
/// the outputs can be written (pnb::Error).
void precheckOptions(const Options& o);

/// The loaded scene's settings overridden by the command line. The scene's own
/// were checked when it loaded, so a failure is the command line's (UsageError).
pnb::RenderSettings checkedSettings(const Options& o, const pnb::Scene& scene);

/// The scene's camera, framed for the image, with the command line's camera
/// options. An invalid camera of the scene's own (an absurd extent) is the
/// scene's error (pnb::Error naming it, unless the options replace it); an
/// invalid result otherwise is the command line's (UsageError).
pnb::Camera checkedCamera(const Options& o, const pnb::Scene& scene, const pnb::RenderSettings& settings);

}  // namespace penumbra::cli
