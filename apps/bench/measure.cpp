#include "measure.h"

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "core/parallel.h"

namespace penumbra::bench {
namespace {

using Clock = std::chrono::steady_clock;

// Large enough that the per-chunk task costs nothing next to the rays, small
// enough that two threads stay balanced; a multiple of 16 for packets.
constexpr size_t kChunk = 256;

// Flush-to-zero / denormals-are-zero while a chunk runs, as in the renderer.
class DenormalGuard {
public:
    DenormalGuard() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | 0x8040u); }
    ~DenormalGuard() { _mm_setcsr(saved_); }
    DenormalGuard(const DenormalGuard&) = delete;
    DenormalGuard& operator=(const DenormalGuard&) = delete;

private:
    unsigned saved_;
};

std::string describe(const ClosestAnswer& a) {
    if (!a.hit) return "miss";
    std::ostringstream s;
    s << "kind " << int(a.ref.kind) << " object " << a.ref.object << " prim " << a.ref.prim << " t " << a.t;
    return s.str();
}

bool sameClosest(const ClosestAnswer& a, const ClosestAnswer& b) {
    if (a.hit != b.hit) return false;
    if (!a.hit) return true;
    if (!(a.ref == b.ref)) return false;
    return std::fabs(a.t - b.t) <= kRelativeTolerance * std::max(std::fabs(a.t), std::fabs(b.t));
}

}  // namespace

Timing timeRuns(int reps, bool warmUp, const std::function<void()>& run) {
    if (warmUp) run();
    std::vector<double> t;
    for (int i = 0; i < std::max(1, reps); ++i) {
        const auto t0 = Clock::now();
        run();
        t.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    }
    std::sort(t.begin(), t.end());
    return Timing{t.front(), t[t.size() / 2], int(t.size())};
}

void forChunks(size_t count, int threads, const std::function<void(size_t, size_t)>& body) {
    parallelFor((count + kChunk - 1) / kChunk, threads, [&](size_t c) {
        DenormalGuard ftz;
        body(c * kChunk, std::min(count, (c + 1) * kChunk));
    });
}

RateFigures measureAccelerator(const Accelerator& accel, const std::vector<Ray>& rays, bool occlusion, int threads,
                               int reps, bool warmUp, Answers& out) {
    RateFigures f;
    f.rays = rays.size();
    int useThreads = 1;
    std::function<void()> run;
    if (occlusion) {
        out.occluded.assign(rays.size(), 0);
        run = [&] {
            forChunks(rays.size(), useThreads, [&](size_t b, size_t e) {
                for (size_t i = b; i < e; ++i) out.occluded[i] = accel.occluded(rays[i]) ? 1 : 0;
            });
        };
    } else {
        out.closest.assign(rays.size(), ClosestAnswer{});
        run = [&] {
            forChunks(rays.size(), useThreads, [&](size_t b, size_t e) {
                for (size_t i = b; i < e; ++i) {
                    const auto h = accel.intersect(rays[i]);
                    out.closest[i] = h ? ClosestAnswer{h->ref, h->t, true} : ClosestAnswer{};
                }
            });
        };
    }
    f.one = timeRuns(reps, warmUp, run);
    useThreads = threads;
    f.all = timeRuns(reps, warmUp, run);
    return f;
}

RateFigures measureRaw(const RawEmbreeScene& raw, const std::vector<Ray>& rays, bool occlusion, int packetWidth,
                       int threads, int reps, Answers& out) {
    RateFigures f;
    f.rays = rays.size();
    std::vector<RawHit> hits(occlusion ? 0 : rays.size());
    std::vector<uint8_t> occ(occlusion ? rays.size() : 0);
    int useThreads = 1;
    auto run = [&] {
        forChunks(rays.size(), useThreads, [&](size_t b, size_t e) {
            const Ray* r = rays.data() + b;
            if (occlusion) {
                if (packetWidth == 1) raw.occluded1(r, e - b, occ.data() + b);
                else raw.occludedPackets(packetWidth, r, e - b, occ.data() + b);
            } else {
                if (packetWidth == 1) raw.intersect1(r, e - b, hits.data() + b);
                else raw.intersectPackets(packetWidth, r, e - b, hits.data() + b);
            }
        });
    };
    f.one = timeRuns(reps, true, run);
    useThreads = threads;
    f.all = timeRuns(reps, true, run);
    if (occlusion) {
        out.occluded = std::move(occ);
    } else {
        out.closest.resize(hits.size());
        for (size_t i = 0; i < hits.size(); ++i)
            out.closest[i] = hits[i].mesh == kRawMiss
                                 ? ClosestAnswer{}
                                 : ClosestAnswer{PrimRef{ShapeKind::Mesh, hits[i].mesh, hits[i].prim}, hits[i].t, true};
    }
    return f;
}

Disagreement& Disagreement::operator+=(const Disagreement& o) {
    compared += o.compared;
    mismatches += o.mismatches;
    for (const auto& e : o.examples)
        if (examples.size() < 8) examples.push_back(e);
    return *this;
}

Disagreement compareAnswers(const Answers& reference, const Answers& other, const std::vector<size_t>& indices,
                            bool occlusion, const char* what) {
    Disagreement d;
    for (size_t i = 0; i < indices.size(); ++i) {
        const size_t r = indices[i];
        bool same;
        std::string detail;
        if (occlusion) {
            same = reference.occluded[r] == other.occluded[i];
            if (!same)
                detail = std::string(reference.occluded[r] ? "occluded" : "unoccluded") + " vs " +
                         (other.occluded[i] ? "occluded" : "unoccluded");
        } else {
            same = sameClosest(reference.closest[r], other.closest[i]);
            if (!same) detail = describe(reference.closest[r]) + " vs " + describe(other.closest[i]);
        }
        ++d.compared;
        if (same) continue;
        ++d.mismatches;
        if (d.examples.size() < 4) d.examples.push_back(std::string(what) + " ray " + std::to_string(r) + ": " + detail);
    }
    return d;
}

FrameFigures measureFrame(const PreparedScene& prepared, const CameraDesc& camera, const RenderSettings& settings,
                          int threads, int reps) {
    FrameFigures f;
    f.measured = true;
    RenderSettings st = settings;
    // Only the renderPass call is timed (not the film allocation); the best
    // of `reps` runs after one warm-up when there are several.
    auto best = [&] {
        double b = kInfinity;
        for (int i = 0; i < (reps > 1 ? reps + 1 : 1); ++i) {
            Film film = makeFilm(st);
            const auto t0 = Clock::now();
            const RenderStats s = renderPass(prepared, camera, st, film, 0, uint32_t(st.spp));
            const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
            f.rays = s.rays;
            if (reps <= 1 || i > 0) b = std::min(b, dt);
        }
        return b;
    };
    st.threads = 1;
    f.seconds1 = best();
    st.threads = threads;
    f.secondsAll = best();
    return f;
}

}  // namespace penumbra::bench
