// penumbra: the command-line renderer.
//   penumbra SCENE.{json,obj,ply,stl,gltf,glb,fbx,dae,...} -o OUT.{exr,hdr,pfm,png,jpg,tif} [options]
// Exit code 0 on success; 1 with a one-line error naming the file and the
// problem otherwise; 2 for command-line usage errors and bad option values
// (one line ending "(see --help)"); 130 when interrupted.
//
// An ordinary host of the public C++ API (<penumbra/penumbra.hpp>): it loads,
// prepares and renders through pnb::Renderer like any embedding program.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <new>
#include <optional>
#include <nlohmann/json.hpp>
#include <penumbra/penumbra.hpp>
#include <set>
#include <vector>

#include "cli_options.h"
#include "cli_settings.h"
#include "option_checks.h"
#include "outputs.h"
#include "progress_reporter.h"

namespace penumbra::cli {
namespace {

namespace fs = std::filesystem;
using pnb::Error;
using pnb::ErrorCode;

// The one piece of process-wide state: set by SIGINT/SIGTERM, polled by the
// render loop (an application concern; the library itself has none).
std::atomic<bool> gInterrupted{false};
extern "C" void onSignal(int) { gInterrupted.store(true); }

uint64_t physicalMemoryBytes() {
    long pages = ::sysconf(_SC_PHYS_PAGES), size = ::sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? uint64_t(pages) * uint64_t(size) : 0;
}

double peakMemoryMiB() {
    rusage ru{};
    ::getrusage(RUSAGE_SELF, &ru);
    return double(ru.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

// Written in full or reported: a short write (a full disk, /dev/full) is an error.
void writeStatsJson(const fs::path& path, const Options& o, const pnb::RenderSettings& s,
                    const pnb::PreparedScene& prepared, const pnb::RenderStats& st, double totalSeconds) {
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
    writeStatistics(path, j.dump(2) + "\n");
}

/// Bytes the largest buffers of a render hold at once: the framebuffer, plus
/// the float copy writeImage makes of it (10 channels for an EXR with AOVs, else 3).
uint64_t peakImageBytes(const pnb::RenderSettings& s, bool exrWithAovs) {
    const int64_t pixels = s.crop ? int64_t(s.crop->x1 - s.crop->x0) * (s.crop->y1 - s.crop->y0)
                                  : int64_t(s.width) * s.height;
    const uint64_t outputPerPixel = (exrWithAovs ? 10 : 3) * sizeof(float) + (s.aovs && !exrWithAovs ? 7 * sizeof(float) : 0);
    return pnb::Framebuffer::bytesNeeded(s) + uint64_t(pixels) * outputPerPixel;
}

// `step` names what runs now, as the message for running out of memory (which
// says nothing about where).
int runSteps(const Options& o, std::string& step) {
    const auto t0 = std::chrono::steady_clock::now();
    // OpenImageIO loads in a helper process while the scene loads and renders
    // (a PFM alone needs no image library). Started first, while this
    // process has one thread.
    std::optional<pnb::ImageEncoder> encoder;
    if (needsImageLibrary(o)) encoder.emplace();
    precheckOptions(o);

    pnb::Renderer renderer;  // warnings and errors to stderr
    SceneReads reads;
    const pnb::LoadOptions loadOptions = loadOptionsFor(o, reads);
    step = o.scene.string() + ": out of memory while loading the scene";
    pnb::Scene scene = renderer.loadScene(o.scene.string(), loadOptions);
    checkSceneReads(o, reads, "penumbra");

    const pnb::RenderSettings settings = checkedSettings(o, scene);
    const uint64_t imageBytes = peakImageBytes(settings, isExr(o.output) && o.aovs);
    const uint64_t ram = physicalMemoryBytes();
    if (ram && imageBytes > ram / 2)
        throw Error(ErrorCode::OutOfMemory, "a " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                                                " image needs " + std::to_string(imageBytes >> 20) +
                                                " MiB for its framebuffer and output, more than half of this machine's memory");

    const pnb::Camera camera = checkedCamera(o, scene, settings);
    asUsage([&] { applyLightOptions(o, scene); });

    pnb::PrepareOptions prep;
    prep.accelerator = o.accel;
    prep.quality = buildQualityOf(o);
    step = o.scene.string() + ": out of memory while preparing the scene (acceleration structure, lights, textures)";
    const bool sky = scene.hasEnvironment();  // an environment alone is an image (of the sky)
    const pnb::PreparedScene prepared = renderer.prepare(std::move(scene), prep);
    if (prepared.primitiveCount() == 0 && !sky)
        throw Error(ErrorCode::InvalidScene,
                    o.scene.string() + ": nothing to render (no shapes, no mesh with a valid triangle, no environment)");

    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    ProgressReporter progress(o.quiet);
    pnb::RenderControl control;
    control.cancel = &gInterrupted;
    control.tileProgress = [&](size_t done, size_t total) { progress.update(done, total); };
    step = "out of memory while rendering a " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
           " image";
    pnb::Framebuffer image(settings);
    pnb::RenderStats stats;
    try {
        stats = renderer.render(prepared, camera, settings, image, control);
    } catch (const Error& e) {
        progress.finish();
        if (e.code() != ErrorCode::Cancelled) throw;
        std::fprintf(stderr, "penumbra: interrupted; no image written\n");
        return 130;
    }
    progress.finish();
    warnIfEmptyImage(o, image, stats, prepared.primitiveCount() > 0, "penumbra");

    pnb::ImageOptions wo;
    wo.exposure = o.exposure;
    wo.aovs = o.aovs;
    if (encoder) wo.encoder = &*encoder;
    step = o.output.string() + ": out of memory while writing the image";
    image.writeImage(o.output.string(), wo);
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!o.statsJson.empty()) writeStatsJson(o.statsJson, o, settings, prepared, stats, total);

    if (!o.quiet) {
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
                    image.height(), settings.spp, total);
    }
    return 0;
}

int run(const Options& o) {
    std::string step = "out of memory while checking the options";
    try {
        return runSteps(o, step);
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
        auto parsed = cli::parseCommandLine(argc, argv);
        if (!parsed.options) return parsed.exitCode;
        return cli::run(*parsed.options);
    } catch (const cli::UsageError& e) {
        return cli::reportUsageError(e.what());
    } catch (const pnb::Error& e) {
        std::fprintf(stderr, "penumbra: error: %s\n", e.what());
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "penumbra: error: out of memory\n");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra: error: %s\n", e.what());
    }
    return 1;
}
