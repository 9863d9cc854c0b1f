#include "shading/renderer.h"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>
#include <span>

#include "core/denormals.h"
#include "core/error.h"
#include "core/io/input_file.h"
#include "core/lane_clones.h"
#include "core/scratch_array.h"
#include "core/multi_jitter.h"
#include "core/multi_jitter_lanes.h"
#include "core/parallel.h"
#include "core/rgb_image.h"
#include "core/scene_edits.h"
#include "core/texture_cache.h"
#include "lights/environment_light.h"
#include "shading/integrator.h"

namespace penumbra {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The environment's image: from the loader's open file when there is one
// (never reopened by name), else opened by path once. Unlike a texture, an
// environment that cannot be read is an error: it is the scene's light.
RgbImage readEnvironmentImage(const EnvironmentDesc& env, const Logger& log) {
    RgbImageFixups fix;
    RgbImage image = env.imageFile ? decodeRgbImage(env.image, env.imageFile->fd(), TextureBudget{}, &fix)
                                   : decodeRgbImage(env.image, TextureBudget{}, &fix);
    if (fix.nonFinite || fix.negative)
        log.warn(env.image + ": environment image has " + std::to_string(fix.nonFinite) + " non-finite and " +
                 std::to_string(fix.negative) + " negative channel values; they are taken as 0");
    return image;
}

}  // namespace

PreparedScene::PreparedScene(Scene sceneIn, const PrepareOptions& options, const Logger& log) {
    auto t0 = Clock::now();
    auto scene = std::make_shared<Scene>(std::move(sceneIn));
    fixups_ = scene->finalize(log);
    addDefaultLightIfDark(*scene, log);
    RgbImage environmentImage;
    if (scene->environment && !scene->environment->image.empty())
        environmentImage = readEnvironmentImage(*scene->environment, log);
    // Textures are read from the files the loader opened right after its path check (never
    // reopened by name: a file swapped in since then is not read) or from their bytes.
    // Before the accelerator: its alpha cutouts read them.
    if (!scene->textures.empty()) textures_ = std::make_shared<const TextureCache>(scene->textures, log);
    accel_ = makeAccelerator(options.accelerator, *scene, options.quality, textures_);
    if (const size_t n = accel_->alphaTest().opaqueShapesWithAlpha())
        log.warn(std::to_string(n) + " sphere(s), box(es), disk(s) or plane(s) have a material whose alpha cuts "
                 "out; alpha cuts out of meshes and rectangles only, so they are drawn opaque");
    scene_ = buffers_ = scene;
    buildLights(std::move(environmentImage));
    buildSeconds_ = secondsSince(t0);
}

PreparedScene::PreparedScene(const PreparedScene& base, const SceneEdits& edits, const Logger& log)
    : buffers_(base.buffers_), fixups_(base.fixups_), textures_(base.textures_) {
    auto t0 = Clock::now();
    auto scene = std::make_shared<Scene>(*base.scene_);
    if (base.defaultLightAdded_) scene->environment.reset();  // the edited scene decides anew
    applyEdits(*scene, edits);
    accel_ = base.accel_->edited(*scene, buffers_);
    addDefaultLightIfDark(*scene, log);
    scene_ = scene;
    // The file is not read again: the image base decoded (and cleaned, which a second time changes nothing).
    const EnvironmentLight* env = base.lights_->environment();
    buildLights(env && env->hasImage() && scene->environment && !scene->environment->image.empty() ? env->image()
                                                                                                     : RgbImage{});
    buildSeconds_ = secondsSince(t0);
}

// No silently black scenes: one place for every way in (CLI, JSON, API, Python, edits).
void PreparedScene::addDefaultLightIfDark(Scene& scene, const Logger& log) {
    if (!scene.defaultLight || scene.hasLight()) return;
    EnvironmentDesc white;
    white.color = Rgb(kDefaultEnvironmentRadiance);
    scene.environment = white;
    defaultLightAdded_ = true;
    log.warn("the scene has no light (no emitter, point or directional light, ambient light, environment or "
             "background): lighting it with a uniform white environment of radiance 1; give it a light or an "
             "environment (--env) to change this");
}

void PreparedScene::buildLights(RgbImage environmentImage) {
    // Emissive textures light the scene as they are seen (core/emission.h).
    lights_ = std::make_unique<LightSet>(*scene_, std::move(environmentImage), textures_.get());
}

PreparedScene::~PreparedScene() = default;

Film makeFilm(const RenderSettings& s) { return Film(s.width, s.height, pnb::renderWindow(s), s.aovs); }

namespace {

// Everything one pass shares between its tiles (read-only while they run).
struct PassContext {
    const PreparedScene& prepared;
    const Camera& camera;
    const Integrator& integrator;
    const RenderSettings& settings;
    Film& film;
    CropWindow window;
    uint32_t firstSample, sampleCount;
    bool useLens;
    const std::atomic<bool>* cancel;

    bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }
};

struct PixelRect {
    int x0, y0, x1, y1;
};

// The pixel (and lens) sample sets of a tile's blocks: every set has spp
// samples on one grid; drawn as lanes (MultiJitterLanes), whose lanes each
// block sets to its pixels, where the size allows and tables pay.
struct BlockSampleSets {
    MjGrid grid;
    bool tabulate;  // MultiJitterSet's tables, where the sets are not lanes
    std::optional<MultiJitterLanes> pixel, lens;
};

// The keys of a block's pixels (pixelSampleKey) and the patterns of their
// pixel sets, and of their lens sets where lensPatterns is not null, as loops
// over the pixels.
PENUMBRA_LANE_CLONES void blockKeys(uint64_t seed, int width, const PixelRect& b, int count, uint64_t* keys,
                                    uint32_t* pixelPatterns, uint32_t* lensPatterns) {
    const int bw = b.x1 - b.x0;
    for (int i = 0; i < count; ++i) {
        const uint64_t pixel = uint64_t(b.y0 + i / bw) * uint64_t(width) + uint64_t(b.x0 + i % bw);
        keys[i] = pixelSampleKey(seed, pixel);
    }
    for (int i = 0; i < count; ++i) pixelPatterns[i] = setPattern(keys[i], 0, kPixelDimension);
    if (lensPatterns)
        for (int i = 0; i < count; ++i) lensPatterns[i] = setPattern(keys[i], 0, kLensDimension);
}

// Camera samples of one block of up to 4x4 pixels: for each sample index the
// block's camera rays go out as one packet and are shaded as one batch. Each
// pixel still receives its samples in sample order, so films do not depend on
// the grouping. Cancellation is checked before every sample index (a batch of
// at most 16 camera samples). Returns false when cancelled.
PENUMBRA_LANE_CLONES bool renderBlock(const PassContext& c, const PixelRect& b, BlockSampleSets& sets, RayCounts& counts) {
    constexpr size_t kMax = Integrator::kMaxBatch;
    static_assert(kMax <= size_t(MultiJitterLanes::kLanes), "a block's pixels fit the lanes");
    const int bw = b.x1 - b.x0;
    const size_t count = size_t(bw) * size_t(b.y1 - b.y0);
    const uint32_t spp = static_cast<uint32_t>(c.settings.spp);
    uint64_t pixelKey[kMax];
    size_t filmIndex[kMax];
    std::optional<MultiJitterSet> pixelSet[kMax], lensSet[kMax];  // where the sets are not drawn as lanes
    float pixelX[kMax], pixelY[kMax];  // the pixels' corners on the film
    const bool asLanes = bool(sets.pixel);
    alignas(64) uint32_t pixelPattern[kMax], lensPattern[kMax];
    blockKeys(c.settings.seed, c.settings.width, b, int(count), pixelKey, pixelPattern,
              c.useLens ? lensPattern : nullptr);
    for (size_t i = 0; i < count; ++i) {
        const int x = b.x0 + int(i) % bw, y = b.y0 + int(i) / bw;
        filmIndex[i] = c.film.index(x, y);
        pixelX[i] = float(x);
        pixelY[i] = float(y);
    }
    if (asLanes) {
        sets.pixel->setLanes(pixelPattern, int(count));
        if (c.useLens) sets.lens->setLanes(lensPattern, int(count));
    } else {
        for (size_t i = 0; i < count; ++i) {
            pixelSet[i].emplace(spp, sets.grid, pixelPattern[i], sets.tabulate);
            if (c.useLens) lensSet[i].emplace(spp, sets.grid, lensPattern[i], sets.tabulate);
        }
    }
    alignas(64) float filmX[kMax], filmY[kMax];
    Vec2f lens[kMax];
    RayLanes rayLanes;  // the camera rays as the packet query reads them
    Ray rays[kMax];     // and one by one, as the integrators keep them
    EmptyOptionals<Hit, kMax> hits;
    SampleKey keys[kMax];
    Rgb radiance[kMax];
    FirstHit first[kMax];
    const bool aovs = c.film.hasAovs();
    // The block's pixel sums stay here while its samples are added, and go to
    // the film once (also when cancelled): a read and a write of the film per
    // sample cost more than the additions.
    Film::RadianceSum sum[kMax];
    for (size_t i = 0; i < count; ++i) sum[i] = c.film.radianceSum(filmIndex[i]);
    const auto storeSums = [&] {
        for (size_t i = 0; i < count; ++i) c.film.setRadianceSum(filmIndex[i], sum[i]);
    };
    for (uint32_t s = c.firstSample; s < c.firstSample + c.sampleCount; ++s) {
        if (c.cancelled()) {
            storeSums();
            return false;
        }
        if (asLanes) {
            alignas(64) float ux[kMax], uy[kMax];
            sets.pixel->sample(s, ux, uy);
            for (size_t i = 0; i < count; ++i) {
                filmX[i] = pixelX[i] + ux[i];
                filmY[i] = pixelY[i] + uy[i];
            }
            if (c.useLens) {
                sets.lens->sample(s, ux, uy);
                for (size_t i = 0; i < count; ++i) lens[i] = Vec2f{ux[i], uy[i]};
            }
        } else {
            for (size_t i = 0; i < count; ++i) {
                const Vec2f u = pixelSet[i]->sample(s);
                filmX[i] = pixelX[i] + u.x;
                filmY[i] = pixelY[i] + u.y;
                if (c.useLens) lens[i] = lensSet[i]->sample(s);
            }
        }
        for (size_t i = 0; i < count; ++i) keys[i] = SampleKey{pixelKey[i], s};
        c.camera.generateRayLanes(filmX, filmY, c.useLens ? lens : nullptr, int(count), rayLanes);
        c.prepared.accelerator().intersectLanes(rayLanes, std::span<std::optional<Hit>>(hits.data(), count), rays);
        // The share of pixels that see a surface, from one sample each: enough for the CLI's empty-image warning.
        if (s == c.firstSample)
            for (size_t i = 0; i < count; ++i) counts.pixelsHit += hits[i].has_value() ? 1 : 0;
        const std::span<FirstHit> firstHits = aovs ? std::span<FirstHit>(first, count) : std::span<FirstHit>();
        c.integrator.radianceBatch(std::span<const Ray>(rays, count),
                                   std::span<const std::optional<Hit>>(hits.data(), count),
                                   std::span<const SampleKey>(keys, count), std::span<Rgb>(radiance, count), firstHits,
                                   counts);
        for (size_t i = 0; i < count; ++i) {
            sum[i].add(radiance[i]);
            if (aovs) c.film.addAov(filmIndex[i], first[i].albedo, first[i].normal, first[i].depth);
        }
    }
    storeSums();
    return true;
}

// One tile, block by block. Returns false when cancelled.
bool renderTile(const PassContext& c, const PixelRect& tile, RayCounts& counts) {
    DenormalGuard ftz;
    constexpr int kBlock = 4;
    const uint32_t spp = static_cast<uint32_t>(c.settings.spp);
    const MjGrid grid = mjGrid(spp);
    // Tabulate the sets' permutations where the pass draws enough of their
    // samples to repay it: m + k permutation evaluations per set, against two
    // per sample drawn. Tabulated sets of a size that allows it are lanes.
    const bool tabulate = 2 * uint64_t(c.sampleCount) > uint64_t(grid.cols) + grid.rows;
    BlockSampleSets sets{grid, tabulate, std::nullopt, std::nullopt};
    if (tabulate && MultiJitterLanes::supports(spp)) {
        sets.pixel.emplace(spp);
        if (c.useLens) sets.lens.emplace(spp);
    }
    for (int by = tile.y0; by < tile.y1; by += kBlock)
        for (int bx = tile.x0; bx < tile.x1; bx += kBlock) {
            const PixelRect block{bx, by, std::min(bx + kBlock, tile.x1), std::min(by + kBlock, tile.y1)};
            if (!renderBlock(c, block, sets, counts)) return false;
        }
    return true;
}

}  // namespace

PassResult renderPass(const PreparedScene& prepared, const CameraDesc& cameraDesc, const RenderSettings& settings,
                       Film& film, uint32_t firstSample, uint32_t sampleCount, const RenderControl& control,
                       const InternalSettings& internal) {
    // The API checked the arguments (api/render.cpp, checkRender and checkPass).
    assert(film.window() == pnb::renderWindow(settings) && film.sampleCount() == firstSample &&
           uint64_t(firstSample) + sampleCount <= uint64_t(settings.spp));
    const Camera camera(cameraDesc, settings.width, settings.height);
    // The angle a texture lookup filters over: a camera sample's share of the
    // pixel, about 1/sqrt(spp) of its width, since the film's box filter already
    // averages the samples (never under 1/8 of a pixel, as pbrt-v4 bounds it).
    // The whole pixel would blur textures that the samples resolve.
    const float sampleShare = std::max(0.125f, 1.f / std::sqrt(float(settings.spp)));
    const float pixelSpread =
        sampleShare * 2.f * std::tan(0.5f * cameraDesc.vfovDegrees * kPi / 180.f) / float(settings.height);
    const std::unique_ptr<Integrator> integrator = makeIntegrator(
        {prepared.scene(), prepared.accelerator(), prepared.lights(), prepared.textures(), settings, pixelSpread, internal});
    const PassContext context{prepared, camera,      *integrator, settings, film, film.window(), firstSample,
                              sampleCount, cameraDesc.aperture > 0.f, control.cancel};

    const CropWindow& window = context.window;
    const int tile = settings.tileSize;
    const int tilesX = (window.x1 - window.x0 + tile - 1) / tile;
    const int tilesY = (window.y1 - window.y0 + tile - 1) / tile;
    const size_t tileCount = size_t(tilesX) * size_t(tilesY);

    std::mutex mergeMutex;
    RayCounts total;
    size_t tilesDone = 0;
    std::atomic<bool> stopped{false};
    const uint64_t invalidBefore = prepared.accelerator().invalidRayCount();
    auto t0 = Clock::now();
    parallelFor(tileCount, settings.threads, [&](size_t t) {
        if (stopped.load(std::memory_order_relaxed)) return;
        const int x0 = window.x0 + int(t % size_t(tilesX)) * tile;
        const int y0 = window.y0 + int(t / size_t(tilesX)) * tile;
        RayCounts counts;
        const bool finished =
            renderTile(context, PixelRect{x0, y0, std::min(x0 + tile, window.x1), std::min(y0 + tile, window.y1)}, counts);
        std::lock_guard<std::mutex> lock(mergeMutex);
        total += counts;
        if (!finished) {
            stopped = true;
            return;
        }
        ++tilesDone;
        if (control.progress) control.progress(tilesDone, tileCount);
    });

    PassResult result;
    RenderStats& stats = result.stats;
    stats.renderSeconds = secondsSince(t0);
    stats.cameraRays = total.camera;
    stats.shadowRays = total.shadow;
    stats.reflectionRays = total.reflection;
    stats.nonFiniteSamples = total.nonFinite;
    stats.transmissionRays = total.transmission;
    stats.indirectRays = total.indirect;
    stats.brdfRays = total.brdf;
    stats.pixelsHit = total.pixelsHit;
    stats.pathLengthSum = total.pathLengthSum;
    stats.pathLengthMax = total.pathLengthMax;
    stats.invalidRays = prepared.accelerator().invalidRayCount() - invalidBefore;
    stats.threads = threadsFor(settings.threads);
    result.cancelled = stopped.load();
    stats.mraysPerSecond = stats.renderSeconds > 0 ? double(total.total()) / stats.renderSeconds * 1e-6 : 0.0;
    if (!result.cancelled) film.setSampleCount(firstSample + sampleCount);
    stats.samplesPerPixel = film.sampleCount();
    return result;
}

PassResult render(const PreparedScene& prepared, const CameraDesc& camera, const RenderSettings& settings, Film& film,
                   const RenderControl& control, const InternalSettings& internal) {
    return renderPass(prepared, camera, settings, film, film.sampleCount(), uint32_t(settings.spp) - film.sampleCount(),
                      control, internal);
}

}  // namespace penumbra
