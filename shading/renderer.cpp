#include "shading/renderer.h"

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <chrono>
#include <cmath>
#include <mutex>

#include "core/error.h"
#include "core/multi_jitter.h"
#include "core/parallel.h"
#include "core/texture_cache.h"

namespace penumbra {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Flush-to-zero / denormals-are-zero for the duration of a tile, as Embree
// recommends for its traversal; restored afterwards so host threads are unchanged.
class DenormalGuard {
public:
    DenormalGuard() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | 0x8040u); }
    ~DenormalGuard() { _mm_setcsr(saved_); }
    DenormalGuard(const DenormalGuard&) = delete;
    DenormalGuard& operator=(const DenormalGuard&) = delete;

private:
    unsigned saved_;
};

}  // namespace

PreparedScene::PreparedScene(Scene scene, const PrepareOptions& options, const Logger& log) : scene_(std::move(scene)) {
    auto t0 = Clock::now();
    fixups_ = scene_.finalize(log);
    accel_ = makeAccelerator(options.accelerator, scene_, options.quality);
    lights_ = std::make_unique<LightSet>(scene_);
    if (!scene_.textures.empty()) textures_ = std::make_unique<TextureCache>(scene_.textures, log);
    buildSeconds_ = secondsSince(t0);
}

PreparedScene::~PreparedScene() = default;

Film makeFilm(const RenderSettings& s) {
    CropWindow w = s.crop ? *s.crop : CropWindow{0, 0, s.width, s.height};
    return Film(s.width, s.height, w, s.aovs);
}

RenderStats renderPass(const PreparedScene& prepared, const CameraDesc& cameraDesc, const RenderSettings& settings,
                       Film& film, uint32_t firstSample, uint32_t sampleCount, const RenderControl& control) {
    validateSettings(settings);
    const CropWindow window = settings.crop ? *settings.crop : CropWindow{0, 0, settings.width, settings.height};
    if (film.fullWidth() != settings.width || film.fullHeight() != settings.height || !(film.window() == window))
        throw Error(ErrorCode::InvalidArgument, "film does not match the render settings (size or crop window)");
    if (uint64_t(firstSample) + sampleCount > uint64_t(settings.spp))
        throw Error(ErrorCode::InvalidArgument, "sample range exceeds spp");
    if (film.sampleCount() != firstSample)
        throw Error(ErrorCode::InvalidArgument, "film holds " + std::to_string(film.sampleCount()) +
                                                    " samples per pixel; the pass must start there");

    const Camera camera(cameraDesc, settings.width, settings.height);
    Integrator integrator(prepared.scene(), prepared.accelerator(), prepared.lights(), prepared.textures(), settings);
    integrator.setPixelSpread(2.f * std::tan(0.5f * cameraDesc.vfovDegrees * kPi / 180.f) / float(settings.height));
    const int tile = settings.tileSize;
    const int tilesX = (window.x1 - window.x0 + tile - 1) / tile;
    const int tilesY = (window.y1 - window.y0 + tile - 1) / tile;
    const size_t tileCount = size_t(tilesX) * size_t(tilesY);
    const uint32_t spp = static_cast<uint32_t>(settings.spp);
    const bool useLens = cameraDesc.aperture > 0.f;

    std::mutex mergeMutex;
    RayCounts total;
    size_t tilesDone = 0;
    std::atomic<bool> stopped{false};
    const uint64_t invalidBefore = prepared.accelerator().invalidRayCount();
    auto t0 = Clock::now();

    parallelFor(tileCount, settings.threads, [&](size_t t) {
        DenormalGuard ftz;
        const int x0 = window.x0 + int(t % size_t(tilesX)) * tile;
        const int y0 = window.y0 + int(t / size_t(tilesX)) * tile;
        const int x1 = std::min(x0 + tile, window.x1), y1 = std::min(y0 + tile, window.y1);
        RayCounts counts;
        for (int y = y0; y < y1; ++y) {
            if (control.cancel && control.cancel->load(std::memory_order_relaxed)) {
                stopped = true;
                return;
            }
            for (int x = x0; x < x1; ++x) {
                const uint64_t pixel = uint64_t(y) * uint64_t(settings.width) + uint64_t(x);
                const MultiJitterSet pixelSet(spp, mjPattern(settings.seed, pixel, 0, kPixelDimension));
                const MultiJitterSet lensSet(spp, mjPattern(settings.seed, pixel, 0, kLensDimension));
                const size_t fi = film.index(x, y);
                for (uint32_t s = firstSample; s < firstSample + sampleCount; ++s) {
                    const Vec2f u = pixelSet.sample(s);
                    const Vec2f uLens = useLens ? lensSet.sample(s) : Vec2f{0.5f, 0.5f};
                    const Ray ray = camera.generateRay(float(x) + u.x, float(y) + u.y, uLens);
                    FirstHit first;
                    const Rgb L = integrator.Li(ray, SampleKey{settings.seed, pixel, s}, counts, &first);
                    film.addRadiance(fi, L);
                    if (film.hasAovs()) film.addAov(fi, first.albedo, first.normal, first.depth);
                }
            }
        }
        std::lock_guard<std::mutex> lock(mergeMutex);
        total += counts;
        ++tilesDone;
        if (control.progress) control.progress(tilesDone, tileCount);
    });

    RenderStats stats;
    stats.renderSeconds = secondsSince(t0);
    stats.rays = total;
    stats.invalidRays = prepared.accelerator().invalidRayCount() - invalidBefore;
    stats.threads = settings.threads > 0 ? settings.threads : hardwareThreads();
    stats.cancelled = stopped.load();
    stats.mraysPerSecond = stats.renderSeconds > 0 ? double(total.total()) / stats.renderSeconds * 1e-6 : 0.0;
    if (!stats.cancelled) film.setSampleCount(firstSample + sampleCount);
    stats.samplesPerPixel = film.sampleCount();
    return stats;
}

RenderStats render(const PreparedScene& prepared, const CameraDesc& camera, const RenderSettings& settings, Film& film,
                   const RenderControl& control) {
    return renderPass(prepared, camera, settings, film, film.sampleCount(), uint32_t(settings.spp) - film.sampleCount(),
                      control);
}

}  // namespace penumbra
