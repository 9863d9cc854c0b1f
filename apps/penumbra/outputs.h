// The files a render command writes (the image, its AOV sibling, the
// statistics): which they are, the checks made before any work, and the
// statistics file written all or nothing. Shared by penumbra and penumbra-mpi.
#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <penumbra/penumbra.hpp>

#include "cli_options.h"
#include "clobber_check.h"

namespace penumbra::cli {

/// The path names an OpenEXR file (by its extension, any case).
bool isExr(const std::filesystem::path& p);

/// Whether writing the command's images takes OpenImageIO: every format but a PFM without AOVs.
bool needsImageLibrary(const Options& o);

/// What the command writes: -o, its `<stem>.aovs.exr` sibling (AOVs with a
/// format other than EXR), --stats-json.
std::vector<OutputFile> outputsOf(const Options& o);

/// Before any work: the image path is writable in principle, the statistics'
/// folder exists, no output is the scene file, no two outputs are one file.
/// Throws pnb::Error.
void precheckOutputs(const Options& o);

/// The files loading a scene read, as the loader reported them.
struct SceneReads {
    std::set<std::filesystem::path> all, outside;  // outside: beyond the scene's folder
};

/// The commands' LoadOptions: --strict, and every file the scene names is
/// read (no restriction), each one recorded in `reads` (which must outlive the load).
pnb::LoadOptions loadOptionsFor(const Options& o, SceneReads& reads);

/// After loading: refuses an output that is a file the scene reads (MTL,
/// textures, meshes), and warns once, as `program`, about reads outside the scene's folder.
void checkSceneReads(const Options& o, const SceneReads& reads, const char* program);

/// After rendering: warns, as `program`, when the image is black or nearly
/// none of its pixels sees a surface (an automatic camera framing a
/// closed model from outside, a plane seen edge-on). `scenery`: the scene has
/// primitives (an environment alone is all background by design).
void warnIfEmptyImage(const Options& o, const pnb::Framebuffer& image, const pnb::RenderStats& stats, bool scenery,
                      const char* program);

/// The --stats-json keys both commands write first: scene, output,
/// accelerator and the settings that shape the image.
nlohmann::json statisticsHeader(const Options& o, const pnb::RenderSettings& s, const std::string& accelerator);

/// Writes `text` to `path` in full or throws pnb::Error(IoError) naming it
/// ("PATH: cannot write statistics: ..."). A regular file (or a new one) is
/// written to a temporary beside it and renamed, so a failure leaves what was
/// there; a path that is not a regular file (/dev/stdout, a FIFO) is written
/// as it is, every write checked.
void writeStatistics(const std::filesystem::path& path, const std::string& text);

}  // namespace penumbra::cli
