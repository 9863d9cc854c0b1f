// penumbra-bench: Embree against the naive intersector and against raw Embree,
// on ray sets generated once per scene and replayed identically.
//   penumbra-bench [--sizes 1e2,1e3,...] [--obj FILE]... [--quick] [--threads N]
//                  [--rays N] [--naive-max-rays N] [--json FILE] [--plot FILE.png] [--seed S]
// Exit code 0 on success; 1 with a one-line error; 2 for usage errors; 3 when
// the accelerators disagree on more than 0.01% of the rays.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <new>

#include "bench_options.h"
#include "bench_report.h"
#include "bench_results.h"
#include "core/error.h"
#include "core/parallel.h"

namespace penumbra::bench {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kAgreementFailed = 3;
// Triangle tests a naive frame may take (beyond it the frame is skipped).
constexpr double kNaiveFrameBudget = 6e7;

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

bool onlyTriangles(const Scene& s) {
    return s.spheres.empty() && s.planes.empty() && s.boxes.empty() && s.rectangles.empty() && s.disks.empty();
}

void checkOutputFolder(const std::filesystem::path& file, const char* option) {
    if (file.empty()) return;
    const auto dir = file.parent_path().empty() ? std::filesystem::path(".") : file.parent_path();
    if (!std::filesystem::is_directory(dir))
        throw Error(ErrorCode::IoError, std::string(option) + " " + file.string() + ": folder '" + dir.string() +
                                            "' does not exist");
}

// Best of `reps` fresh builds; `build` returns the object so it is destroyed
// outside the timed part.
template <class Build>
auto bestBuild(int reps, Build build, double& bestSeconds) {
    bestSeconds = kInfinity;
    decltype(build()) kept;
    for (int i = 0; i < reps; ++i) {
        const auto t0 = Clock::now();
        auto made = build();
        bestSeconds = std::min(bestSeconds, secondsSince(t0));
        kept = std::move(made);
    }
    return kept;
}

// The raw harness's scenes (where the scene holds triangles only), robust and not.
struct RawScenes {
    std::unique_ptr<RawEmbreeScene> robust, fast;
};

// The builds, each the best of o.repetitions fresh ones, timed on their own
// (the prepared scene's accelerator answers the rays).
RawScenes measureBuilds(SceneResult& r, const Scene& scene, const Accelerator& embree, const BenchOptions& o) {
    r.embree.present = true;
    r.embreeThin.present = true;
    bestBuild(o.repetitions, [&] { return makeEmbreeAccelerator(scene); }, r.embree.buildSeconds);
    r.embree.memoryBytes = embree.memoryBytes();
    r.naive.present = true;
    RawScenes raw;
    if (!r.triangleOnly || scene.meshes.empty()) {
        r.raw.note = "not measured: the scene has analytic shapes (the raw ceiling holds triangles only)";
        return raw;
    }
    raw.robust = bestBuild(o.repetitions, [&] { return std::make_unique<RawEmbreeScene>(scene); }, r.raw.buildSeconds);
    r.raw.present = true;
    r.raw.deviceSeconds = raw.robust->deviceSeconds();
    r.raw.memoryBytes = raw.robust->memoryBytes();
    r.raw.frame.note = "the raw harness renders no frames";
    raw.fast = bestBuild(
        o.repetitions, [&] { return std::make_unique<RawEmbreeScene>(scene, RawEmbreeOptions{BuildQuality::High, false}); },
        r.rawFast.buildSeconds);
    r.rawFast.present = true;
    r.rawFast.memoryBytes = raw.fast->memoryBytes();
    r.rawFast.frame.note = r.raw.frame.note;
    return raw;
}

// One ray kind's set through every contender: rates and agreement into r.
void measureKind(SceneResult& r, RayKind kind, const std::vector<Ray>& rays, const Accelerator& embree,
                 const Accelerator& naive, const RawScenes& raw, size_t naiveRays, const BenchOptions& o, int threads) {
    const size_t k = size_t(kind);
    const bool occlusion = isOcclusion(kind);
    r.setRays[k] = rays.size();

    // The renderer, raw Embree and its packets answer the whole set,
    // interleaved so that load from elsewhere falls on all of them alike.
    // Closest-hit sets also time the renderer's thin query alone
    // (intersectPrim, no Scene::completeHit) to split its overhead.
    std::vector<std::unique_ptr<RayLoop>> loops;
    // The renderer traces camera rays (4x4 pixel blocks) and light samples
    // as packets and mirror rays one by one; the loop does the same.
    loops.push_back(acceleratorLoop(embree, rays, occlusion, kind == RayKind::Incoherent ? 1 : 16));
    const size_t primAt = loops.size();
    // Shadow sets: the accelerator's occluded() one ray at a time, the
    // pure query the frame/query ratio charges where no raw harness exists.
    loops.push_back(occlusion ? acceleratorLoop(embree, rays, true, 1) : thinQueryLoop(embree, rays));
    const size_t rawAt = loops.size();
    std::vector<int> widths;
    if (raw.robust) {
        widths.push_back(1);
        if (kind != RayKind::Incoherent) widths.insert(widths.end(), {8, 16});
        for (int w : widths) loops.push_back(rawLoop(*raw.robust, rays, occlusion, w));
        loops.push_back(rawLoop(*raw.fast, rays, occlusion, 1));
    }
    std::vector<RayLoop*> timed;
    for (auto& l : loops) timed.push_back(l.get());
    const auto rates = measureInterleaved(timed, rays.size(), threads, o.repetitions, true);
    r.embree.kinds[k] = rates[0];
    r.embreeThin.kinds[k] = rates[primAt];
    const Answers reference = loops[0]->answers();
    std::vector<size_t> all(rays.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = i;
    for (size_t i = 0; i < widths.size(); ++i) {
        const int w = widths[i];
        const std::string what = std::string(rayKindName(kind)) + (w == 1 ? "" : " x" + std::to_string(w));
        r.rawVsEmbree[k] += compareAnswers(reference, loops[rawAt + i]->answers(), all, occlusion, what.c_str());
        if (w == 1)
            r.raw.kinds[k] = rates[rawAt + i];
        else
            r.packets.push_back(PacketFigures{w, kind, raw.robust->nativePacket(w), rates[rawAt + i]});
    }
    if (raw.fast) {
        r.rawFast.kinds[k] = rates.back();
        r.rawFastVsEmbree[k] = compareAnswers(reference, loops.back()->answers(), all, occlusion, rayKindName(kind));
    }

    // The naive loop answers an evenly spread subset, once (its time is
    // long and steady enough that repetitions add nothing).
    const std::vector<size_t> subset = spreadSubset(rays.size(), naiveRays);
    std::vector<Ray> subsetRays;
    subsetRays.reserve(subset.size());
    for (size_t i : subset) subsetRays.push_back(rays[i]);
    const auto naiveLoop = acceleratorLoop(naive, subsetRays, occlusion);
    r.naive.kinds[k] = measureInterleaved({naiveLoop.get()}, subsetRays.size(), threads, 1, false)[0];
    r.naiveVsEmbree[k] = compareAnswers(reference, naiveLoop->answers(), subset, occlusion, rayKindName(kind));
}

// Whole frames: Embree's always, the naive loop's where its triangle tests fit the budget.
void measureFrames(SceneResult& r, const PreparedScene& prepared, const CameraDesc& camera, const RenderSettings& st,
                   const BenchOptions& o, int threads, const Logger& log) {
    r.embree.frame = measureFrame(prepared, camera, st, threads, o.repetitions);
    const double naiveTests = double(r.embree.frame.rays.total()) * double(std::max<size_t>(1, r.primitives));
    if (naiveTests <= kNaiveFrameBudget) {
        const PreparedScene naivePrepared(Scene(prepared.scene()), PrepareOptions{AcceleratorKind::Naive, BuildQuality::High},
                                          log);
        r.naive.frame = measureFrame(naivePrepared, camera, st, threads, 1);
    } else {
        char note[128];
        std::snprintf(note, sizeof note, "frame skipped: about %.1e triangle tests", naiveTests);
        r.naive.frame.note = note;
    }
}

SceneResult runScene(BenchScene bench, const BenchOptions& o, int threads, const Logger& log) {
    SceneResult r;
    r.name = bench.name;
    r.family = bench.family;
    const CameraDesc camera = bench.camera;
    const PreparedScene prepared(std::move(bench.scene), PrepareOptions{AcceleratorKind::Embree, BuildQuality::High}, log);
    const Scene& scene = prepared.scene();
    r.prepareSeconds = prepared.buildSeconds();
    r.triangles = scene.triangleCount();
    r.primitives = scene.primitiveCount();
    r.lights = prepared.lights().size();
    r.triangleOnly = onlyTriangles(scene);
    const Accelerator& embree = prepared.accelerator();
    const RawScenes raw = measureBuilds(r, scene, embree, o);
    const auto naive = makeNaiveAccelerator(scene);

    const RaySets sets = makeRaySets(embree, prepared.lights(), camera, o.rays, o.seed, threads);
    r.imageSide = sets.imageSide;
    r.cameraHits = sets.cameraHits;
    r.mirrorRays = sets.mirrorRays;
    r.randomRays = sets.randomRays;
    const double perRay = double(std::max<size_t>(1, r.primitives));
    const size_t naiveRays = std::clamp<size_t>(size_t(o.naiveBudget / perRay), 16, std::max<size_t>(16, o.naiveMaxRays));
    for (RayKind kind : kRayKinds) measureKind(r, kind, sets.of(kind), embree, *naive, raw, naiveRays, o, threads);

    RenderSettings st;
    st.width = o.frameWidth;
    st.height = o.frameHeight;
    st.spp = o.frameSpp;
    st.lightSamples = bench.lightSamples.value_or(o.frameLightSamples);
    st.maxDepth = bench.maxDepth.value_or(o.frameMaxDepth);
    st.seed = o.seed;
    st.aovs = false;
    measureFrames(r, prepared, camera, st, o, threads, log);
    return r;
}

int run(const BenchOptions& o) {
    const auto t0 = Clock::now();
    checkOutputFolder(o.json, "--json");
    checkOutputFolder(o.plot, "--plot");
    Logger log;
    log.setMinLevel(LogLevel::Warning);
    const int threads = o.threads > 0 ? o.threads : hardwareThreads();

    // Scenes are made one at a time so the largest never share memory.
    std::vector<std::function<BenchScene()>> makers;
    for (size_t n : o.sizes) makers.push_back([n] { return proceduralScene(n); });
    if (o.mixed) makers.push_back([&o] { return mixedScene(o.quick ? 1000 : 10000); });
    if (!o.defaultScene.empty()) makers.push_back([&] { return defaultScene(o.defaultScene, log); });
    for (const auto& obj : o.objs) makers.push_back([&] { return objInRoom(obj, log); });
    for (const auto& file : o.scenes) makers.push_back([&] { return fileScene(file, log); });

    std::vector<SceneResult> results;
    for (const auto& make : makers) {
        const auto ts = Clock::now();
        results.push_back(runScene(make(), o, threads, log));
        std::fprintf(stderr, "penumbra-bench: %s (%zu triangles) done in %.1f s\n", results.back().name.c_str(),
                     results.back().triangles, secondsSince(ts));
    }

    RunInfo info = describeMachine(threads);
    info.totalSeconds = secondsSince(t0);
    std::printf("\n");
    printReport(stdout, results, o, info);
    if (!o.json.empty()) {
        std::ofstream out(o.json);
        out << toJson(results, o, info).dump(2) << "\n";
        if (!out) throw Error(ErrorCode::IoError, o.json.string() + ": cannot write");
    }
    if (!o.plot.empty()) {
        const std::string problem = writePlot(o.plot, results, info);
        if (!problem.empty()) std::fprintf(stderr, "penumbra-bench: warning: %s\n", problem.c_str());
    }
    std::printf("total %.1f s\n", secondsSince(t0));
    return summarizeAgreement(results).passed() ? 0 : kAgreementFailed;
}

}  // namespace
}  // namespace penumbra::bench

int main(int argc, char** argv) {
    using namespace penumbra;
    try {
        auto parsed = bench::parseBenchCommandLine(argc, argv);
        if (!parsed.options) return parsed.exitCode;
        return bench::run(*parsed.options);
    } catch (const Error& e) {
        std::fprintf(stderr, "penumbra-bench: error: %s\n", e.what());
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "penumbra-bench: error: out of memory\n");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra-bench: error: %s\n", e.what());
    }
    return 1;
}
