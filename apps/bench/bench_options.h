// The penumbra-bench command line (CLI11).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::bench {

/// Everything the command line says, with --quick already applied.
struct BenchOptions {
    std::vector<size_t> sizes;                 // triangle counts of the procedural scenes
    std::vector<std::filesystem::path> objs;   // extra OBJ files, each placed in a room
    std::vector<std::filesystem::path> scenes; // JSON scene files, as they stand
    std::filesystem::path defaultScene;        // the Cornell box; empty = left out
    bool mixed = true;                         // the scene with analytic shapes
    bool quick = false;
    int threads = 0;                           // the "all threads" count (0 = all cores)
    size_t rays = 0;                           // camera rays per scene
    size_t naiveMaxRays = 0;                   // cap on the naive subset per ray kind
    double naiveBudget = 0.0;                  // triangle tests per naive run (bounds its time)
    int repetitions = 0;                       // timed runs after the warm-up; the best counts
    int frameWidth = 0, frameHeight = 0, frameSpp = 0, frameLightSamples = 0, frameMaxDepth = 0;
    std::filesystem::path json;
    std::filesystem::path plot;
    uint64_t seed = 1;
    std::string commandLine;                   // for the report
};

/// Parses argv. Returns the options, or the exit code when parsing ended the
/// program (help: 0; usage error: 2).
struct BenchParseResult {
    std::optional<BenchOptions> options;
    int exitCode = 0;
};
BenchParseResult parseBenchCommandLine(int argc, char** argv);

/// "100,1e3,10000" -> {100, 1000, 10000}; throws Error(InvalidArgument) naming --sizes.
std::vector<size_t> parseSizes(const std::string& text);

}  // namespace penumbra::bench
