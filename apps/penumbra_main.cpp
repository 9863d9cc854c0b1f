// penumbra: the command-line renderer.
//   penumbra SCENE.{obj,json} -o OUT.{exr,hdr,pfm,png,jpg,tif} [options]
// Exit code 0 on success; 1 with a one-line error naming the file and the
// problem otherwise; 2 for command-line usage errors; 130 when interrupted.
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <new>
#include <set>
#include <nlohmann/json.hpp>

#include "cli_options.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/scene_loader.h"
#include "progress_reporter.h"
#include "shading/renderer.h"

namespace penumbra::cli {
namespace {

// The one piece of process-wide state: set by SIGINT/SIGTERM, polled by the
// render loop (an application concern; the library itself has none).
std::atomic<bool> gInterrupted{false};
extern "C" void onSignal(int) { gInterrupted.store(true); }

constexpr const char* kSoftware = "Penumbra 0.1.0";

uint64_t physicalMemoryBytes() {
    long pages = ::sysconf(_SC_PHYS_PAGES), size = ::sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? uint64_t(pages) * uint64_t(size) : 0;
}

double peakMemoryMiB() {
    rusage ru{};
    ::getrusage(RUSAGE_SELF, &ru);
    return double(ru.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

RenderSettings settingsFrom(const Options& o, const SettingsPatch& scenePatch) {
    RenderSettings s;
    scenePatch.applyTo(s);
    SettingsPatch cli;
    cli.width = o.width;
    cli.height = o.height;
    cli.spp = o.spp;
    cli.lightSamples = o.lightSamples;
    cli.maxDepth = o.maxDepth;
    cli.threads = o.threads;
    cli.tileSize = o.tileSize;
    cli.seed = o.seed;
    if (o.lightSelection) cli.lightSelection = *o.lightSelection == "power" ? LightSelection::Power : LightSelection::All;
    cli.applyTo(s);
    s.crop = o.crop;
    s.aovs = o.aovs;
    return s;
}

void applyCameraOptions(const Options& o, CameraDesc& c) {
    if (o.eye) c.eye = *o.eye;
    if (o.lookAt) c.lookAt = *o.lookAt;
    if (o.up) c.up = *o.up;
    if (o.fov) c.vfovDegrees = *o.fov;
    if (o.aperture) c.aperture = *o.aperture;
    if (o.focusDistance) c.focusDistance = *o.focusDistance;
}

// Everything that can be checked without reading the scene, checked before any work.
void precheck(const Options& o) {
    checkWritable(o.output);
    if (!o.statsJson.empty()) {
        auto dir = o.statsJson.parent_path().empty() ? std::filesystem::path(".") : o.statsJson.parent_path();
        if (!std::filesystem::is_directory(dir))
            throw Error(ErrorCode::IoError, o.statsJson.string() + ": folder '" + dir.string() + "' does not exist");
    }
    RenderSettings s = settingsFrom(o, {});
    s.crop.reset();  // the crop is checked against the final size later
    validateSettings(s);
    if (o.eye && o.lookAt) {
        CameraDesc c;
        applyCameraOptions(o, c);
        validateCamera(c);
    }
    std::error_code ec;
    // symlink_status: a symlink loop or a FIFO exists, and the loader says what it is.
    if (std::filesystem::symlink_status(o.scene, ec).type() == std::filesystem::file_type::not_found)
        throw Error(ErrorCode::FileNotFound, o.scene.string() + ": no such file");
}

void writeStatsJson(const std::filesystem::path& path, const Options& o, const RenderSettings& s,
                    const PreparedScene& prepared, const RenderStats& st, double totalSeconds) {
    nlohmann::json j;
    j["scene"] = o.scene.string();
    j["output"] = o.output.string();
    j["accelerator"] = prepared.accelerator().name();
    j["width"] = s.width;
    j["height"] = s.height;
    j["spp"] = s.spp;
    j["light_samples"] = s.lightSamples;
    j["max_depth"] = s.maxDepth;
    j["seed"] = s.seed;
    j["threads"] = st.threads;
    j["triangles"] = prepared.scene().triangleCount();
    j["primitives"] = prepared.scene().primitiveCount();
    j["lights"] = prepared.lights().size();
    j["build_seconds"] = prepared.buildSeconds();
    j["render_seconds"] = st.renderSeconds;
    j["total_seconds"] = totalSeconds;
    j["rays"] = {{"camera", st.rays.camera},
                 {"shadow", st.rays.shadow},
                 {"reflection", st.rays.reflection},
                 {"total", st.rays.total()},
                 {"invalid", st.invalidRays}};
    j["nonfinite_samples_dropped"] = st.rays.nonFinite;
    j["mrays_per_second"] = st.mraysPerSecond;
    j["peak_memory_mib"] = peakMemoryMiB();
    std::ofstream out(path);
    out << j.dump(2) << "\n";
    if (!out) throw Error(ErrorCode::IoError, path.string() + ": cannot write statistics");
}

/// Bytes the largest buffers of a render hold at once: the film, plus the
/// float copy writeImage makes of it (10 channels for an EXR with AOVs, else 3).
uint64_t peakImageBytes(const RenderSettings& s, bool exrWithAovs) {
    const int64_t pixels = s.crop ? int64_t(s.crop->x1 - s.crop->x0) * (s.crop->y1 - s.crop->y0)
                                  : int64_t(s.width) * s.height;
    const uint64_t outputPerPixel = (exrWithAovs ? 10 : 3) * sizeof(float) + (s.aovs && !exrWithAovs ? 7 * sizeof(float) : 0);
    return Film::bytesNeeded(pixels, s.aovs) + uint64_t(pixels) * outputPerPixel;
}

// `step` names what runs now, as the message for std::bad_alloc (which says nothing about where).
int runSteps(const Options& o, std::string& step) {
    const auto t0 = std::chrono::steady_clock::now();
    precheck(o);

    Logger log;
    log.setMinLevel(LogLevel::Warning);
    LoadOptions loadOptions;
    loadOptions.strict = o.strict;
    // The CLI reads whatever the scene names, but says so when that is outside the scene's folder.
    std::set<std::filesystem::path> outside;
    loadOptions.noticeRoots = {o.scene.parent_path().empty() ? std::filesystem::path(".") : o.scene.parent_path()};
    loadOptions.onReadOutside = [&](const std::filesystem::path& f) { outside.insert(f); };
    step = o.scene.string() + ": out of memory while loading the scene";
    LoadedScene loaded = loadScene(o.scene, loadOptions, log);
    if (!outside.empty())
        log.warn(o.scene.string() + ": reads " + std::to_string(outside.size()) +
                 " file(s) outside the scene's folder, first " + outside.begin()->string());

    RenderSettings settings = settingsFrom(o, loaded.settings);
    validateSettings(settings);
    const uint64_t imageBytes = peakImageBytes(settings, imageFormatFromPath(o.output) == ImageFormat::Exr && o.aovs);
    const uint64_t ram = physicalMemoryBytes();
    if (ram && imageBytes > ram / 2)
        throw Error(ErrorCode::OutOfMemory, "a " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                                                " image needs " + std::to_string(imageBytes >> 20) +
                                                " MiB for its framebuffer and output, more than half of this machine's memory");

    CameraDesc camera;
    if (loaded.camera) {
        camera = *loaded.camera;
    } else {
        float fov = o.fov.value_or(40.f);
        camera = frameBounds(loaded.scene.bounds(), fov, float(settings.width) / float(settings.height));
    }
    applyCameraOptions(o, camera);
    validateCamera(camera);
    if (o.ambient) loaded.scene.ambient = *o.ambient;
    if (o.background) loaded.scene.background = *o.background;

    PrepareOptions prep;
    prep.accelerator = o.accel;
    prep.quality = o.buildQuality == "low" ? BuildQuality::Low
                   : o.buildQuality == "medium" ? BuildQuality::Medium
                                                : BuildQuality::High;
    step = o.scene.string() + ": out of memory while preparing the scene (acceleration structure, lights, textures)";
    PreparedScene prepared(std::move(loaded.scene), prep, log);

    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    ProgressReporter progress(o.quiet);
    RenderControl control;
    control.cancel = &gInterrupted;
    control.progress = [&](size_t done, size_t total) { progress.update(done, total); };
    step = "out of memory while rendering a " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
           " image";
    Film film = makeFilm(settings);
    RenderStats stats = render(prepared, camera, settings, film, control);
    progress.finish();
    if (stats.cancelled) {
        std::fprintf(stderr, "penumbra: interrupted; no image written\n");
        return 130;
    }

    ImageWriteOptions wo;
    wo.exposure = o.exposure;
    wo.aovs = o.aovs;
    wo.metadata = ImageMetadata{settings.spp, settings.seed, stats.renderSeconds, kSoftware};
    step = o.output.string() + ": out of memory while writing the image";
    writeImage(o.output, film, wo);
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!o.statsJson.empty()) writeStatsJson(o.statsJson, o, settings, prepared, stats, total);

    if (!o.quiet) {
        const auto& r = stats.rays;
        std::fprintf(stderr,
                     "penumbra: %zu primitives (%zu triangles), %zu lights, accelerator %s\n"
                     "penumbra: build %.3f s, render %.3f s on %d threads\n"
                     "penumbra: rays: %llu camera, %llu shadow, %llu reflection (%.2f Mrays/s); peak memory %.0f MiB\n",
                     prepared.scene().primitiveCount(), prepared.scene().triangleCount(), prepared.lights().size(),
                     prepared.accelerator().name().c_str(), prepared.buildSeconds(), stats.renderSeconds, stats.threads,
                     (unsigned long long)r.camera, (unsigned long long)r.shadow, (unsigned long long)r.reflection,
                     stats.mraysPerSecond, peakMemoryMiB());
        if (r.nonFinite || stats.invalidRays)
            std::fprintf(stderr, "penumbra: dropped %llu non-finite samples, %llu invalid rays\n",
                         (unsigned long long)r.nonFinite, (unsigned long long)stats.invalidRays);
        std::printf("penumbra: wrote %s (%dx%d, %d spp) in %.2f s\n", o.output.string().c_str(), film.width(),
                    film.height(), settings.spp, total);
    }
    return 0;
}

int run(const Options& o) {
    std::string step = "out of memory while checking the options";
    try {
        return runSteps(o, step);
    } catch (const std::bad_alloc&) {
        throw Error(ErrorCode::OutOfMemory, step);
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
    } catch (const Error& e) {
        std::fprintf(stderr, "penumbra: error: %s\n", e.what());
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "penumbra: error: out of memory\n");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra: error: %s\n", e.what());
    }
    return 1;
}
