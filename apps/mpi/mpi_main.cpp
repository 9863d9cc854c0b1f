// penumbra-mpi: one frame rendered by the ranks of an MPI job.
//   mpirun -np N penumbra-mpi SCENE.{json,obj,ply,gltf,...} -o OUT.{exr,...} [penumbra's options]
// Every rank loads the scene through the public API; rank 0 hands out tiles
// as workers finish them, pastes the returned framebuffers into the frame and
// writes the image: the same image, bit for bit, as `penumbra` with the same
// options, for any number of ranks. Exit codes as penumbra's; a failing rank
// ends the job with one error line from rank 0 and no image written.
#include <mpi.h>
#include <sys/resource.h>
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <penumbra/penumbra.hpp>
#include <string>
#include <vector>

#include "cli_options.h"
#include "coordinator.h"
#include "job.h"
#include "option_checks.h"
#include "outputs.h"
#include "progress_reporter.h"
#include "render_setup.h"
#include "worker.h"

namespace penumbra::mpi {
namespace {

namespace fs = std::filesystem;
using cli::Options;
using pnb::Error;
using pnb::ErrorCode;

double peakMemoryMiB() {
    rusage ru{};
    ::getrusage(RUSAGE_SELF, &ru);
    return double(ru.ru_maxrss) / 1024.0;
}

/// Runs `f` with stdout and stderr sent to /dev/null: ranks other than 0 parse
/// the same command line, and only rank 0 may say what is wrong with it.
template <class F>
auto silenced(F&& f) -> decltype(f()) {
    std::fflush(stdout);
    std::fflush(stderr);
    const int out = ::dup(1), err = ::dup(2), null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    auto restore = [&] {
        std::fflush(stdout);
        std::fflush(stderr);
        ::dup2(out, 1);
        ::dup2(err, 2);
        ::close(out);
        ::close(err);
        ::close(null);
    };
    try {
        auto r = f();
        restore();
        return r;
    } catch (...) {
        restore();
        throw;
    }
}

/// What setting up gave this rank.
struct Setup {
    SetupReport report;
    std::optional<Job> job;          // rank 0: the settings and camera every rank renders with
    pnb::PreparedScene prepared;     // ranks that render
};

Setup setUp(const Options& o, pnb::Renderer& renderer, int rank, int size) {
    Setup setup;
    setup.report.host = processorName();
    try {
        if (rank == 0) cli::precheckOptions(o);  // what needs no scene, before loading it
        cli::LoadedScene loaded = cli::loadForRender(o, renderer, "penumbra-mpi", rank == 0);
        setup.report.primitives = std::int64_t(loaded.scene.primitiveCount());
        setup.report.triangles = std::int64_t(loaded.scene.triangleCount());
        setup.report.materials = std::int64_t(loaded.scene.materialCount());
        if (rank == 0) setup.job = Job{loaded.settings, loaded.camera};
        if (rank != 0 || size == 1) {
            if (rank == 1) renderer.setLog({}, pnb::LogLevel::Warning);  // scene repairs, said once
            setup.prepared = cli::prepareForRender(o, renderer, std::move(loaded.scene));
            setup.report.lights = std::int64_t(setup.prepared.lightCount());
            setup.report.buildSeconds = setup.prepared.buildSeconds();
            setup.report.accelerator = setup.prepared.accelerator();
        }
    } catch (const cli::UsageError& e) {
        setup.report.error = e.what();
        setup.report.usageError = true;
    } catch (const std::bad_alloc&) {
        setup.report.error = o.scene.string() + ": out of memory while loading or preparing the scene";
    } catch (const std::exception& e) {
        setup.report.error = e.what();
    }
    return setup;
}

/// What stops the job: a message (empty when all is well) and whether it is a
/// usage error (a bad option value: exit code 2 and "(see --help)", as penumbra's).
struct Problem {
    std::string message;
    bool usage = false;
};

/// Rank 0: the first problem of any rank (its own first).
Problem firstProblem(const std::vector<SetupReport>& reports, const Options& o) {
    if (!reports[0].error.empty()) return {reports[0].error, reports[0].usageError};
    for (size_t r = 1; r < reports.size(); ++r)
        if (!reports[r].error.empty())
            return {rankName(int(r), reports[r].host) + ": " + reports[r].error, reports[r].usageError};
    for (size_t r = 1; r < reports.size(); ++r) {
        const SetupReport &a = reports[0], &b = reports[r];
        if (a.primitives != b.primitives || a.triangles != b.triangles || a.materials != b.materials)
            return {rankName(int(r), b.host) + ": " + o.scene.string() + " holds " + std::to_string(b.primitives) +
                    " primitives, " + std::to_string(b.triangles) + " triangles and " + std::to_string(b.materials) +
                    " materials there, but " + std::to_string(a.primitives) + ", " + std::to_string(a.triangles) +
                    " and " + std::to_string(a.materials) + " on rank 0: every rank must read the same scene"};
    }
    return {};
}

std::string statisticsJson(const Options& o, const pnb::RenderSettings& s, const SetupReport& scene, int ranks,
                           const FrameResult& f, double totalSeconds) {
    nlohmann::json j = cli::statisticsHeader(o, s, scene.accelerator);
    j["ranks"] = ranks;
    j["tiles"] = f.tileCount;
    j["tiles_per_rank"] = f.tilesPerRank;
    j["triangles"] = scene.triangles;
    j["primitives"] = scene.primitives;
    j["lights"] = scene.lights;
    j["build_seconds"] = scene.buildSeconds;
    j["render_seconds"] = f.wallSeconds;
    j["rank_render_seconds"] = f.totals.renderSeconds;
    j["total_seconds"] = totalSeconds;
    const WorkerTotals& t = f.totals;
    j["rays"] = {{"camera", t.cameraRays},
                 {"shadow", t.shadowRays},
                 {"reflection", t.reflectionRays},
                 {"transmission", t.transmissionRays},
                 {"brdf", t.brdfRays},
                 {"indirect", t.indirectRays},
                 {"total", t.totalRays()},
                 {"invalid", t.invalidRays}};
    j["path_length"] = {{"mean", t.cameraRays ? double(t.pathLengthSum) / double(t.cameraRays) : 0.0},
                        {"max", t.pathLengthMax}};
    j["nonfinite_samples_dropped"] = t.nonFiniteSamples;
    j["peak_memory_mib_rank0"] = peakMemoryMiB();
    return j.dump(2) + "\n";
}

void printSummary(const Options& o, const SetupReport& scene, int size, const FrameResult& frame, int spp,
                  double total) {
    const WorkerTotals& t = frame.totals;
    const double rays = double(t.totalRays());
    std::string perRank;
    for (int r = (size == 1 ? 0 : 1); r < size; ++r)
        perRank += (perRank.empty() ? "" : ", ") + std::to_string(frame.tilesPerRank[size_t(r)]);
    std::fprintf(stderr,
                 "penumbra-mpi: %lld primitives (%lld triangles), %lld lights, accelerator %s; build %.3f s\n"
                 "penumbra-mpi: render %.3f s on %d rank(s): %zu tiles, per worker rank %s\n"
                 "penumbra-mpi: rays: %llu camera, %llu shadow, %llu reflection (%.2f Mrays/s)\n",
                 (long long)scene.primitives, (long long)scene.triangles, (long long)scene.lights,
                 scene.accelerator.c_str(), scene.buildSeconds, frame.wallSeconds, size, frame.tileCount,
                 perRank.c_str(), (unsigned long long)t.cameraRays, (unsigned long long)t.shadowRays,
                 (unsigned long long)t.reflectionRays, frame.wallSeconds > 0 ? rays / frame.wallSeconds / 1e6 : 0.0);
    if (t.nonFiniteSamples || t.invalidRays)
        std::fprintf(stderr, "penumbra-mpi: dropped %llu non-finite samples, %llu invalid rays\n",
                     (unsigned long long)t.nonFiniteSamples, (unsigned long long)t.invalidRays);
    std::printf("penumbra-mpi: wrote %s (%dx%d, %d spp) in %.2f s\n", o.output.string().c_str(), frame.image.width(),
                frame.image.height(), spp, total);
}

/// Every rank parses the same command line; only rank 0 speaks about it.
cli::ParseResult parseOnEveryRank(int argc, char** argv, int rank) {
    try {
        return rank == 0 ? cli::parseCommandLine(argc, argv, "penumbra-mpi")
                         : silenced([&] { return cli::parseCommandLine(argc, argv, "penumbra-mpi"); });
    } catch (const std::exception& e) {
        if (rank == 0) std::fprintf(stderr, "penumbra-mpi: error: %s\n", e.what());
        return {std::nullopt, 1};
    }
}

/// Rank 0 (which has every rank's report): the job every rank renders, or the
/// exit code of the first problem any rank had (printed here). Every rank
/// returns the decision. Collective.
Decision decide(const std::vector<SetupReport>& reports, const Setup& setup, const Options& o, int rank) {
    Decision decided;
    if (rank == 0) {
        const Problem problem = firstProblem(reports, o);
        if (problem.message.empty()) {
            decided.job = setup.job;
        } else if (problem.usage) {
            decided.exitCode = cli::reportUsageError(problem.message, "penumbra-mpi");
        } else {
            std::fprintf(stderr, "penumbra-mpi: error: %s\n", problem.message.c_str());
            decided.exitCode = 1;
        }
    }
    return broadcastDecision(decided, rank);
}

/// Rank 0 alone renders the frame itself.
FrameResult renderAlone(const pnb::Renderer& renderer, const pnb::PreparedScene& prepared, const Job& job,
                        cli::ProgressReporter& progress) {
    FrameResult frame;
    pnb::RenderControl control;
    control.tileProgress = [&](size_t done, size_t total) { progress.update(done, total); };
    frame.image = pnb::Framebuffer(job.settings);
    const auto r0 = std::chrono::steady_clock::now();
    const pnb::RenderStats st = renderer.render(prepared, job.camera, job.settings, frame.image, control);
    frame.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count();
    frame.totals = totalsOf(st);
    frame.tilesPerRank = {1};
    frame.tileCount = 1;
    return frame;
}

int run(int argc, char** argv, int rank, int size) {
    const auto t0 = std::chrono::steady_clock::now();
    const cli::ParseResult parsed = parseOnEveryRank(argc, argv, rank);
    if (!parsed.options) return parsed.exitCode;
    const Options& o = *parsed.options;

    // Rank 0 and the renderers other than rank 1 keep quiet about the scene:
    // rank 0 reports what matters once.
    pnb::Renderer renderer;
    if (rank >= 1) renderer.setLog([](pnb::LogLevel, std::string_view) {}, pnb::LogLevel::Error);
    Setup setup = setUp(o, renderer, rank, size);
    const std::vector<SetupReport> reports = gatherReports(setup.report, rank, size);
    const Decision decision = decide(reports, setup, o, rank);
    if (!decision.job) return decision.exitCode;
    const Job& job = *decision.job;
    if (rank != 0) {
        runWorker(renderer, setup.prepared, job, rank, setup.report.host);
        return 0;
    }

    cli::ProgressReporter progress(o.quiet);
    const FrameResult frame =
        size == 1 ? renderAlone(renderer, setup.prepared, job, progress)
                  : runCoordinator(job, size, [&](size_t done, size_t total) { progress.update(done, total); });
    progress.finish();
    auto secondsSinceStart = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    const double total = secondsSinceStart();
    // Every rank read the same scene (firstProblem checked it); rank 1 prepared it when there are workers.
    const SetupReport& scene = size == 1 ? reports[0] : reports[1];
    cli::writeOutputs(o, frame.image, [&] { return statisticsJson(o, job.settings, scene, size, frame, total); });
    if (!o.quiet) printSummary(o, scene, size, frame, job.settings.spp, secondsSinceStart());
    return 0;
}

}  // namespace
}  // namespace penumbra::mpi

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    int code = 1;
    try {
        code = penumbra::mpi::run(argc, argv, rank, size);
    } catch (const std::exception& e) {
        // Past the setup only rank 0 can fail here (writing the image); the
        // workers have finished.
        std::fprintf(stderr, "penumbra-mpi: error: %s\n", e.what());
        code = 1;
    }
    MPI_Finalize();
    return code;
}
