// The benchmark's outputs: the table on stdout, the JSON file and the plot.
#pragma once

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench_options.h"
#include "bench_results.h"

namespace penumbra::bench {

/// Where and when the run happened.
struct RunInfo {
    std::string cpu;           // model name from /proc/cpuinfo
    int hardwareThreads = 0;
    int threads = 0;           // of the multi-threaded runs
    std::string date;          // UTC, ISO 8601
    double totalSeconds = 0.0;
};

/// CPU model and the current UTC time.
RunInfo describeMachine(int threads);

/// The tables (figures, ratios, packets, agreement) as text.
void printReport(std::FILE* out, const std::vector<SceneResult>& results, const BenchOptions& options,
                 const RunInfo& info);

/// Everything measured, as JSON (layout in docs/benchmarks.md).
nlohmann::json toJson(const std::vector<SceneResult>& results, const BenchOptions& options, const RunInfo& info);

/// Writes the plot's data to `png` with extension .tsv and runs gnuplot with
/// scripts/plot_bench.gp (compiled in) to draw the PNG. Returns an empty
/// string on success, else why there is no plot (gnuplot missing or failed).
std::string writePlot(const std::filesystem::path& png, const std::vector<SceneResult>& results, const RunInfo& info);

}  // namespace penumbra::bench
