#include "shading/renderer.h"

#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>
#include <span>

#include "core/denormals.h"
#include "core/error.h"
#include "core/io/input_file.h"
#include "core/multi_jitter.h"
#include "core/parallel.h"
#include "core/texture_cache.h"

namespace penumbra {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

PreparedScene::PreparedScene(Scene scene, const PrepareOptions& options, const Logger& log) : scene_(std::move(scene)) {
    auto t0 = Clock::now();
    fixups_ = scene_.finalize(log);
    accel_ = makeAccelerator(options.accelerator, scene_, options.quality);
    lights_ = std::make_unique<LightSet>(scene_);
    if (!scene_.textures.empty()) {
        // Textures are read from the files the loader opened right after its path check, never
        // reopened by name (a file swapped in since then is not read).
        std::vector<int> textureFds;
        for (const auto& file : scene_.textureFiles) textureFds.push_back(file ? file->fd() : -1);
        textures_ = std::make_unique<TextureCache>(scene_.textures, log, textureFds);
    }
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
        // Camera rays go out as packets: the rays of one sample index over a
        // block of up to 4x4 pixels are coherent. Each pixel still receives
        // its samples in sample order, so films do not depend on the grouping.
        constexpr int kBlock = 4;
        Ray rays[kBlock * kBlock];
        std::optional<Hit> hits[kBlock * kBlock];
        for (int by = y0; by < y1; by += kBlock) {
            if (control.cancel && control.cancel->load(std::memory_order_relaxed)) {
                stopped = true;
                return;
            }
            for (int bx = x0; bx < x1; bx += kBlock) {
                const int bw = std::min(kBlock, x1 - bx), bh = std::min(kBlock, y1 - by);
                const int count = bw * bh;
                uint64_t pixel[kBlock * kBlock];
                size_t filmIndex[kBlock * kBlock];
                std::optional<MultiJitterSet> pixelSet[kBlock * kBlock], lensSet[kBlock * kBlock];
                for (int i = 0; i < count; ++i) {
                    const int x = bx + i % bw, y = by + i / bw;
                    pixel[i] = uint64_t(y) * uint64_t(settings.width) + uint64_t(x);
                    filmIndex[i] = film.index(x, y);
                    pixelSet[i].emplace(spp, mjPattern(settings.seed, pixel[i], 0, kPixelDimension));
                    if (useLens) lensSet[i].emplace(spp, mjPattern(settings.seed, pixel[i], 0, kLensDimension));
                }
                for (uint32_t s = firstSample; s < firstSample + sampleCount; ++s) {
                    for (int i = 0; i < count; ++i) {
                        const Vec2f u = pixelSet[i]->sample(s);
                        const Vec2f uLens = useLens ? lensSet[i]->sample(s) : Vec2f{0.5f, 0.5f};
                        rays[i] = camera.generateRay(float(bx + i % bw) + u.x, float(by + i / bw) + u.y, uLens);
                    }
                    prepared.accelerator().intersectBatch(std::span<const Ray>(rays, size_t(count)),
                                                          std::span<std::optional<Hit>>(hits, size_t(count)));
                    for (int i = 0; i < count; ++i) {
                        FirstHit first;
                        const Rgb L = integrator.Li(rays[i], hits[i], SampleKey{settings.seed, pixel[i], s}, counts, &first);
                        film.addRadiance(filmIndex[i], L);
                        if (film.hasAovs()) film.addAov(filmIndex[i], first.albedo, first.normal, first.depth);
                    }
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
