// Timing loops and the agreement check. Every accelerator answers a ray set
// through the same chunked parallel loop, so they differ only in the query.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "accel/accelerator.h"
#include "accel/bench/raw_embree.h"
#include "core/camera.h"
#include "core/render_settings.h"
#include "shading/renderer.h"

namespace penumbra::bench {

/// Seconds of the timed runs of one measurement.
struct Timing {
    double best = 0.0;
    double median = 0.0;
    int runs = 0;
};

/// Calls body(begin, end) over [0, count) in chunks of a few hundred rays with
/// `threads` threads (core/parallel.h), with flush-to-zero set as the
/// renderer's tiles have it.
void forChunks(size_t count, int threads, const std::function<void(size_t, size_t)>& body);

/// One closest-hit answer in the form the agreement check compares.
struct ClosestAnswer {
    PrimRef ref;
    float t = 0.f;
    bool hit = false;
};

/// Answers to one ray set: closest hits or occlusion flags, by ray index.
struct Answers {
    std::vector<ClosestAnswer> closest;
    std::vector<uint8_t> occluded;
};

/// Rate of one ray set with one thread and with `threads` threads.
struct RateFigures {
    size_t rays = 0;
    Timing one, all;
    double mrays1() const { return one.best > 0 ? double(rays) / one.best * 1e-6 : 0.0; }
    double mraysAll() const { return all.best > 0 ? double(rays) / all.best * 1e-6 : 0.0; }
};

/// One way of answering a whole ray set: loop(threads) answers every ray
/// with that many threads and keeps the answers (see answers()).
class RayLoop {
public:
    virtual ~RayLoop() = default;
    virtual void run(int threads) = 0;
    /// The answers of the last run, in the agreement check's form.
    virtual Answers answers() const = 0;
};

/// Closest hits through Accelerator::intersect (Scene::completeHit included,
/// as the integrator calls it) or occlusion through Accelerator::occluded;
/// with batch > 1, groups of `batch` consecutive rays through intersectBatch /
/// occludedBatch (packets), as the renderer traces camera and shadow rays.
std::unique_ptr<RayLoop> acceleratorLoop(const Accelerator& accel, const std::vector<Ray>& rays, bool occlusion,
                                        int batch = 1);

/// Closest hits through Accelerator::intersectPrim only: the thin answer,
/// without Scene::completeHit.
std::unique_ptr<RayLoop> thinQueryLoop(const Accelerator& accel, const std::vector<Ray>& rays);

/// The same through raw Embree: packetWidth 1 = rtcIntersect1/rtcOccluded1,
/// 4/8/16 = packets of consecutive rays.
std::unique_ptr<RayLoop> rawLoop(const RawEmbreeScene& raw, const std::vector<Ray>& rays, bool occlusion,
                                 int packetWidth);

/// Times loops that answer the same `rays` rays, with one thread and then
/// with `threads` threads. For each thread count every loop runs once untimed
/// (when warmUp), then `reps` rounds run every loop once in turn, so load
/// from elsewhere on the machine falls on all of them alike; the best counts.
std::vector<RateFigures> measureInterleaved(const std::vector<RayLoop*>& loops, size_t rays, int threads, int reps,
                                            bool warmUp);

/// Counts of an agreement comparison, with a few readable examples.
struct Disagreement {
    size_t compared = 0;
    size_t mismatches = 0;
    std::vector<std::string> examples;
    Disagreement& operator+=(const Disagreement& o);
    double fraction() const { return compared ? double(mismatches) / double(compared) : 0.0; }
};

/// Relative tolerance on t for closest hits that name the same primitive.
inline constexpr float kRelativeTolerance = 1e-4f;
/// Largest fraction of disagreeing rays that still passes.
inline constexpr double kMaxDisagreement = 1e-4;

/// Compares `reference` at indices[i] with `other` at i (other answered the
/// subset `indices` of the set; pass the identity for full sets). Closest
/// hits agree when both miss, or both hit the same PrimRef with t within
/// kRelativeTolerance; occlusion answers must be equal.
Disagreement compareAnswers(const Answers& reference, const Answers& other, const std::vector<size_t>& indices,
                            bool occlusion, const char* what);

/// Best frame time of renderPass with one and with `threads` threads.
struct FrameFigures {
    bool measured = false;
    std::string note;        // why it was skipped
    double seconds1 = 0.0, secondsAll = 0.0;
    RayCounts rays;          // of one frame
    double mrays1() const { return seconds1 > 0 ? double(rays.total()) / seconds1 * 1e-6 : 0.0; }
    double mraysAll() const { return secondsAll > 0 ? double(rays.total()) / secondsAll * 1e-6 : 0.0; }
};
FrameFigures measureFrame(const PreparedScene& prepared, const CameraDesc& camera, const RenderSettings& settings,
                          int threads, int reps);

}  // namespace penumbra::bench
