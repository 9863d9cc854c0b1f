// The files a render command writes (the image, its AOV sibling, the
// statistics): which they are, the checks made before any work, and the
// writing of them all or none. Shared by penumbra and penumbra-mpi.
#pragma once

#include <filesystem>
#include <functional>
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

/// What the command writes: -o, its `<stem>.aovs.exr` sibling (AOVs with a
/// format other than EXR), --stats-json; nothing for --preview without -o.
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
/// textures, meshes), and warns once, as `program` (unless null), about reads
/// outside the scene's folder.
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

/// The statistics file, complete before the image is written: a regular file
/// (or a new one) as a temporary beside it, renamed into place by commit() and
/// removed by the destructor otherwise; a path that is not a regular file
/// (/dev/stdout, a FIFO) is written at once, every write checked. Throws
/// pnb::Error(IoError) "PATH: cannot write statistics: ..." (and leaves what was there).
class StagedStatistics {
public:
    StagedStatistics(const std::filesystem::path& path, const std::string& text);
    ~StagedStatistics();
    StagedStatistics(const StagedStatistics&) = delete;
    StagedStatistics& operator=(const StagedStatistics&) = delete;
    void commit();

private:
    std::filesystem::path path_, temp_;  // temp_: empty once committed, or when written in place
};

/// Writes -o (and its AOV sibling, with --exposure and --aovs) and the
/// --stats-json text `statistics` gives, as one: the statistics are complete
/// before the image is written, and in place only after it, so a run whose
/// image or statistics fail leaves neither new file.
void writeOutputs(const Options& o, const pnb::Framebuffer& image, const std::function<std::string()>& statistics);

}  // namespace penumbra::cli
