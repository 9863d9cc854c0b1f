// The set-up both commands share, from the command line to a prepared scene:
// load (with the command line's load options), refuse outputs over inputs,
// settings and camera from the scene and the command line (checked), the
// light options, then prepare. penumbra runs it once; penumbra-mpi on every
// rank, so that every rank renders the same scene with rank 0's settings.
#pragma once

#include <penumbra/penumbra.hpp>

#include "cli_options.h"

namespace penumbra::cli {

/// A loaded scene with what the command line makes of it.
struct LoadedScene {
    pnb::Scene scene;  ///< with --ambient, --background and --env applied
    pnb::RenderSettings settings;
    pnb::Camera camera;
};

/// Loads o.scene through `renderer` and gives its settings and camera with
/// the command line's values, the light options applied. Refuses (pnb::Error)
/// an output that is a file the scene reads; a bad command-line value is a
/// UsageError (option_checks.h). The `lead` process (the one that writes the
/// image and speaks for the command) also refuses an image whose framebuffer
/// and output would need more than half its memory, and says once, as
/// `program`, when the scene reads files outside its folder.
LoadedScene loadForRender(const Options& o, const pnb::Renderer& renderer, const char* program, bool lead);

/// Prepares the scene with --accel and --build-quality; refuses one with
/// nothing to render (no shape, no valid triangle, no environment).
pnb::PreparedScene prepareForRender(const Options& o, const pnb::Renderer& renderer, pnb::Scene scene);

}  // namespace penumbra::cli
