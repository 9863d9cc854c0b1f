// penumbra: the command-line renderer.
//   penumbra SCENE.{json,obj,ply,stl,gltf,glb,fbx,dae,...} -o OUT.{exr,hdr,pfm,png,jpg,tif} [options]
//   penumbra SCENE --preview [-o OUT] [options]   (a live view in the browser)
// Exit code 0 on success; 1 with a one-line error naming the file and the
// problem otherwise; 2 for command-line usage errors and bad option values
// (one line ending "(see --help)"); 130 when interrupted.
//
// An ordinary host of the public C++ API (<penumbra/penumbra.hpp>): it loads,
// prepares and renders through pnb::Renderer like any embedding program.
#include <sys/resource.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <new>
#include <nlohmann/json.hpp>
#include <optional>
#include <penumbra/penumbra.hpp>

#include "cli_options.h"
#include "option_checks.h"
#include "outputs.h"
#include "preview_render.h"
#include "preview_server.h"
#include "progress_reporter.h"
#include "render_setup.h"

namespace penumbra::cli {
namespace {

using pnb::Error;
using pnb::ErrorCode;
using Clock = std::chrono::steady_clock;

// The one piece of process-wide state: set by SIGINT/SIGTERM, polled by the
// render loop (an application concern; the library itself has none).
std::atomic<bool> gInterrupted{false};
extern "C" void onSignal(int) { gInterrupted.store(true); }

double peakMemoryMiB() {
    rusage ru{};
    ::getrusage(RUSAGE_SELF, &ru);
    return double(ru.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string statisticsJson(const Options& o, const pnb::RenderSettings& s, const pnb::PreparedScene& prepared,
                           const pnb::RenderStats& st, double totalSeconds) {
    nlohmann::json j = statisticsHeader(o, s, prepared.accelerator());
    j["threads"] = st.threads;
    j["triangles"] = prepared.triangleCount();
    j["primitives"] = prepared.primitiveCount();
    j["lights"] = prepared.lightCount();
    j["build_seconds"] = prepared.buildSeconds();
    j["render_seconds"] = st.renderSeconds;
    j["total_seconds"] = totalSeconds;
    j["rays"] = {{"camera", st.cameraRays},
                 {"shadow", st.shadowRays},
                 {"reflection", st.reflectionRays},
                 {"transmission", st.transmissionRays},
                 {"brdf", st.brdfRays},
                 {"indirect", st.indirectRays},
                 {"total", st.totalRays()},
                 {"invalid", st.invalidRays}};
    // Rays traced along each camera sample's path, camera ray included (whitted: its deepest branch).
    j["path_length"] = {{"mean", st.cameraRays ? double(st.pathLengthSum) / double(st.cameraRays) : 0.0},
                        {"max", st.pathLengthMax}};
    j["nonfinite_samples_dropped"] = st.nonFiniteSamples;
    j["mrays_per_second"] = st.mraysPerSecond;
    j["peak_memory_mib"] = peakMemoryMiB();
    j["default_light"] = prepared.defaultLightAdded();  // the scene had no light: a white environment lit it
    return j.dump(2) + "\n";
}

void printSummary(const Options& o, const pnb::PreparedScene& prepared, const pnb::RenderStats& stats,
                  const pnb::Framebuffer& image, int spp, double total) {
    std::fprintf(stderr,
                 "penumbra: %zu primitives (%zu triangles), %zu lights, accelerator %s\n"
                 "penumbra: build %.3f s, render %.3f s on %d threads\n"
                 "penumbra: rays: %llu camera, %llu shadow, %llu reflection, %llu BRDF (%.2f Mrays/s); peak memory "
                 "%.0f MiB\n",
                 prepared.primitiveCount(), prepared.triangleCount(), prepared.lightCount(),
                 prepared.accelerator().c_str(), prepared.buildSeconds(), stats.renderSeconds, stats.threads,
                 (unsigned long long)stats.cameraRays, (unsigned long long)stats.shadowRays,
                 (unsigned long long)stats.reflectionRays, (unsigned long long)stats.brdfRays, stats.mraysPerSecond,
                 peakMemoryMiB());
    if (stats.transmissionRays || stats.indirectRays)
        std::fprintf(stderr, "penumbra: rays: %llu transmission, %llu indirect; path length mean %.2f, max %u\n",
                     (unsigned long long)stats.transmissionRays, (unsigned long long)stats.indirectRays,
                     stats.cameraRays ? double(stats.pathLengthSum) / double(stats.cameraRays) : 0.0,
                     stats.pathLengthMax);
    if (stats.nonFiniteSamples || stats.invalidRays)
        std::fprintf(stderr, "penumbra: dropped %llu non-finite samples, %llu invalid rays\n",
                     (unsigned long long)stats.nonFiniteSamples, (unsigned long long)stats.invalidRays);
    std::printf("penumbra: wrote %s (%dx%d, %d spp) in %.2f s\n", o.output.string().c_str(), image.width(),
                image.height(), spp, total);
}

// The render with progress and Ctrl-C; nullopt when interrupted.
std::optional<pnb::RenderStats> renderImage(const Options& o, const pnb::Renderer& renderer,
                                            const pnb::PreparedScene& prepared, const LoadedScene& job,
                                            pnb::Framebuffer& image) {
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    ProgressReporter progress(o.quiet);
    pnb::RenderControl control;
    control.cancel = &gInterrupted;
    control.tileProgress = [&](size_t done, size_t total) { progress.update(done, total); };
    try {
        const pnb::RenderStats stats = renderer.render(prepared, job.camera, job.settings, image, control);
        progress.finish();
        // More threads than the machine runs at once are not started: say so once.
        if (o.threads && *o.threads > stats.threads)
            std::fprintf(stderr, "penumbra: warning: --threads %d: this machine runs %d threads at once; rendered on %d\n",
                         *o.threads, stats.threads, stats.threads);
        return stats;
    } catch (const Error& e) {
        progress.finish();
        if (e.code() != ErrorCode::Cancelled) throw;
        return std::nullopt;
    }
}

// The scene loaded and prepared as the command line says. `step` names what
// runs now, as the message for running out of memory (which says nothing about where).
struct PreparedJob {
    LoadedScene job;
    pnb::PreparedScene prepared;
};

PreparedJob loadAndPrepare(const Options& o, const pnb::Renderer& renderer, std::string& step) {
    step = o.scene.string() + ": out of memory while loading the scene";
    LoadedScene job = loadForRender(o, renderer, "penumbra", true);
    step = o.scene.string() + ": out of memory while preparing the scene (acceleration structure, lights, textures)";
    pnb::PreparedScene prepared = prepareForRender(o, renderer, std::move(job.scene));
    step = "out of memory while rendering a " + std::to_string(job.settings.width) + "x" +
           std::to_string(job.settings.height) + " image";
    return {std::move(job), std::move(prepared)};
}

// -o (and --stats-json) of a finished render, and the summary.
void writeAndReport(const Options& o, const PreparedJob& p, const pnb::Framebuffer& image,
                    const pnb::RenderStats& stats, Clock::time_point t0, std::string& step) {
    step = o.output.string() + ": out of memory while writing the image";
    const double total = secondsSince(t0);
    writeOutputs(o, image, [&] { return statisticsJson(o, p.job.settings, p.prepared, stats, total); });
    if (!o.quiet) printSummary(o, p.prepared, stats, image, p.job.settings.spp, secondsSince(t0));
}

int runSteps(const Options& o, std::string& step) {
    const auto t0 = Clock::now();
    precheckOptions(o);
    pnb::Renderer renderer;  // warnings and errors to stderr
    const PreparedJob p = loadAndPrepare(o, renderer, step);
    pnb::Framebuffer image(p.job.settings);
    const std::optional<pnb::RenderStats> stats = renderImage(o, renderer, p.prepared, p.job, image);
    if (!stats) {
        std::fprintf(stderr, "penumbra: interrupted; no image written\n");
        return 130;
    }
    warnIfEmptyImage(o, image, *stats, p.prepared.primitiveCount() > 0, "penumbra");
    writeAndReport(o, p, image, *stats, t0, step);
    return 0;
}

// --preview: the same set-up behind a live view in the browser (preview/),
// served from before the scene loads; every view rendered to the end is
// written as -o. Runs until Ctrl-C, or with --preview-exit until a view completes.
int runPreviewSteps(const Options& o, std::string& step) {
    const auto t0 = Clock::now();
    precheckOptions(o);
    // Ctrl-C is ours from the moment the address is printed: one pressed while
    // the scene loads ends the preview (exit 130) once loading returns.
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    preview::PreviewState state(o.scene.filename().string());
    const preview::PreviewServer server(state, o.previewPort);
    std::fprintf(stderr, "preview: http://127.0.0.1:%d/\n", server.port());
    std::fflush(stderr);
    pnb::Renderer renderer;
    const PreparedJob p = loadAndPrepare(o, renderer, step);
    state.start(p.job.settings, p.job.camera, o.exposure);
    bool written = false;
    const auto onComplete = [&](const pnb::Framebuffer& image, const pnb::Camera&, const pnb::RenderStats& stats) {
        if (!o.output.empty()) {
            const std::string rendering = step;
            writeAndReport(o, p, image, stats, t0, step);
            step = rendering;  // the render goes on with the next view
            written = true;
        }
        if (!o.quiet && !o.previewExit)
            std::fprintf(stderr, "penumbra: preview: render complete; serving its image until Ctrl-C (moving the camera "
                                 "renders again)\n");
    };
    const preview::PreviewEnd end =
        preview::renderPreview({renderer, p.prepared, p.job.settings}, state, gInterrupted, o.previewExit, onComplete);
    if (end == preview::PreviewEnd::Completed) return 0;
    if (written)
        std::fprintf(stderr, "penumbra: interrupted; %s holds the last view rendered to the end\n", o.output.string().c_str());
    else
        std::fprintf(stderr, "penumbra: interrupted; no image written\n");
    return 130;
}

int run(const Options& o) {
    std::string step = "out of memory while checking the options";
    try {
        return o.preview ? runPreviewSteps(o, step) : runSteps(o, step);
    } catch (const std::bad_alloc&) {
        throw Error(ErrorCode::OutOfMemory, step);
    } catch (const Error& e) {
        // The API reports an allocation failure as a bare "out of memory"; say where.
        if (e.code() == ErrorCode::OutOfMemory && std::string(e.what()) == "out of memory")
            throw Error(ErrorCode::OutOfMemory, step);
        throw;
    }
}

}  // namespace
}  // namespace penumbra::cli

int main(int argc, char** argv) {
    using namespace penumbra;
    try {
        auto parsed = cli::parseCommandLine(argc, argv, "penumbra", true);
        if (!parsed.options) return parsed.exitCode;
        return cli::run(*parsed.options);
    } catch (const cli::UsageError& e) {
        return cli::reportUsageError(e.what(), "penumbra");
    } catch (const pnb::Error& e) {
        std::fprintf(stderr, "penumbra: error: %s\n", e.what());
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "penumbra: error: out of memory\n");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra: error: %s\n", e.what());
    }
    return 1;
}
