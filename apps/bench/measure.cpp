#include "measure.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <span>
#include <sstream>

#include "core/denormals.h"
#include "core/parallel.h"

namespace penumbra::bench {
namespace {

using Clock = std::chrono::steady_clock;

// Large enough that the per-chunk task costs nothing next to the rays, small
// enough that two threads stay balanced; a multiple of 16 for packets.
constexpr size_t kChunk = 256;

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

void forChunks(size_t count, int threads, const std::function<void(size_t, size_t)>& body) {
    // Small sets (the naive subsets) get smaller chunks so every thread has work.
    size_t chunk = std::clamp<size_t>(count / 64, 1, kChunk);
    if (chunk >= 16) chunk -= chunk % 16;
    parallelFor((count + chunk - 1) / chunk, threads, [&](size_t c) {
        DenormalGuard ftz;
        body(c * chunk, std::min(count, (c + 1) * chunk));
    });
}

namespace {

class AcceleratorLoop final : public RayLoop {
public:
    AcceleratorLoop(const Accelerator& accel, const std::vector<Ray>& rays, bool occlusion, int batch)
        : accel_(accel), rays_(rays), occlusion_(occlusion), batch_(std::max(1, batch)) {
        if (occlusion) out_.occluded.assign(rays.size(), 0);
        else out_.closest.assign(rays.size(), ClosestAnswer{});
    }
    void run(int threads) override {
        if (batch_ > 1) {
            runBatched(threads);
            return;
        }
        if (occlusion_) {
            forChunks(rays_.size(), threads, [&](size_t b, size_t e) {
                for (size_t i = b; i < e; ++i) out_.occluded[i] = accel_.occluded(rays_[i]) ? 1 : 0;
            });
        } else {
            forChunks(rays_.size(), threads, [&](size_t b, size_t e) {
                for (size_t i = b; i < e; ++i) {
                    // Field by field: a whole-struct copy of a freshly built
                    // temporary stalls on store forwarding and would charge
                    // this harness's cost to the renderer.
                    const auto h = accel_.intersect(rays_[i]);
                    ClosestAnswer& a = out_.closest[i];
                    a.hit = h.has_value();
                    if (h) {
                        a.ref = h->ref;
                        a.t = h->t;
                    }
                }
            });
        }
    }
    Answers answers() const override { return out_; }

private:
    // Groups of batch_ consecutive rays through the batch queries, as the
    // renderer traces camera blocks and a shading point's light samples.
    void runBatched(int threads) {
        forChunks(rays_.size(), threads, [&](size_t b, size_t e) {
            std::optional<Hit> hits[64];
            for (size_t i = b; i < e; i += size_t(batch_)) {
                const size_t n = std::min<size_t>({size_t(batch_), e - i, 64});
                const std::span<const Ray> group(rays_.data() + i, n);
                if (occlusion_) {
                    accel_.occludedBatch(group, std::span<uint8_t>(out_.occluded.data() + i, n));
                    continue;
                }
                accel_.intersectBatch(group, std::span<std::optional<Hit>>(hits, n));
                for (size_t j = 0; j < n; ++j) {
                    ClosestAnswer& a = out_.closest[i + j];
                    a.hit = hits[j].has_value();
                    if (hits[j]) {
                        a.ref = hits[j]->ref;
                        a.t = hits[j]->t;
                    }
                }
            }
        });
    }

    const Accelerator& accel_;
    const std::vector<Ray>& rays_;
    bool occlusion_;
    int batch_;
    Answers out_;
};

class ThinQueryLoop final : public RayLoop {
public:
    ThinQueryLoop(const Accelerator& accel, const std::vector<Ray>& rays)
        : accel_(accel), rays_(rays), out_(rays.size()) {}
    void run(int threads) override {
        forChunks(rays_.size(), threads, [&](size_t b, size_t e) {
            for (size_t i = b; i < e; ++i) {
                const auto h = accel_.intersectPrim(rays_[i]);
                ClosestAnswer& a = out_[i];
                a.hit = h.has_value();
                if (h) {
                    a.ref = h->ref;
                    a.t = h->t;
                }
            }
        });
    }
    Answers answers() const override { return Answers{out_, {}}; }

private:
    const Accelerator& accel_;
    const std::vector<Ray>& rays_;
    std::vector<ClosestAnswer> out_;
};

class RawLoop final : public RayLoop {
public:
    RawLoop(const RawEmbreeScene& raw, const std::vector<Ray>& rays, bool occlusion, int width)
        : raw_(raw), rays_(rays), occlusion_(occlusion), width_(width) {
        if (occlusion) occluded_.assign(rays.size(), 0);
        else hits_.assign(rays.size(), RawHit{kRawMiss, 0, 0.f});
    }
    void run(int threads) override {
        forChunks(rays_.size(), threads, [&](size_t b, size_t e) {
            const Ray* r = rays_.data() + b;
            if (occlusion_) {
                if (width_ == 1) raw_.occluded1(r, e - b, occluded_.data() + b);
                else raw_.occludedPackets(width_, r, e - b, occluded_.data() + b);
            } else {
                if (width_ == 1) raw_.intersect1(r, e - b, hits_.data() + b);
                else raw_.intersectPackets(width_, r, e - b, hits_.data() + b);
            }
        });
    }
    Answers answers() const override {
        Answers a;
        a.occluded = occluded_;
        a.closest.reserve(hits_.size());
        for (const RawHit& h : hits_)
            a.closest.push_back(h.mesh == kRawMiss ? ClosestAnswer{}
                                                   : ClosestAnswer{PrimRef{ShapeKind::Mesh, h.mesh, h.prim}, h.t, true});
        return a;
    }

private:
    const RawEmbreeScene& raw_;
    const std::vector<Ray>& rays_;
    bool occlusion_;
    int width_;
    std::vector<RawHit> hits_;
    std::vector<uint8_t> occluded_;
};

Timing timingOf(std::vector<double> t) {
    std::sort(t.begin(), t.end());
    return Timing{t.front(), t[t.size() / 2], int(t.size())};
}

}  // namespace

std::unique_ptr<RayLoop> acceleratorLoop(const Accelerator& accel, const std::vector<Ray>& rays, bool occlusion,
                                        int batch) {
    return std::make_unique<AcceleratorLoop>(accel, rays, occlusion, batch);
}

std::unique_ptr<RayLoop> thinQueryLoop(const Accelerator& accel, const std::vector<Ray>& rays) {
    return std::make_unique<ThinQueryLoop>(accel, rays);
}

std::unique_ptr<RayLoop> rawLoop(const RawEmbreeScene& raw, const std::vector<Ray>& rays, bool occlusion,
                                 int packetWidth) {
    return std::make_unique<RawLoop>(raw, rays, occlusion, packetWidth);
}

std::vector<RateFigures> measureInterleaved(const std::vector<RayLoop*>& loops, size_t rays, int threads, int reps,
                                            bool warmUp) {
    std::vector<RateFigures> figures(loops.size());
    for (int pass = 0; pass < 2; ++pass) {
        const int t = pass == 0 ? 1 : threads;
        if (warmUp)
            for (RayLoop* loop : loops) loop->run(t);
        std::vector<std::vector<double>> seconds(loops.size());
        for (int rep = 0; rep < std::max(1, reps); ++rep)
            for (size_t i = 0; i < loops.size(); ++i) {
                const auto t0 = Clock::now();
                loops[i]->run(t);
                seconds[i].push_back(std::chrono::duration<double>(Clock::now() - t0).count());
            }
        for (size_t i = 0; i < loops.size(); ++i) {
            figures[i].rays = rays;
            (pass == 0 ? figures[i].one : figures[i].all) = timingOf(seconds[i]);
        }
    }
    return figures;
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
    // Only the renderPass call is timed (not the film allocation). One and
    // `threads` threads alternate, after one warm-up each when reps > 1.
    auto once = [&](int t) {
        RenderSettings st = settings;
        st.threads = t;
        Film film = makeFilm(st);
        const auto t0 = Clock::now();
        const RenderStats s = renderPass(prepared, camera, st, film, 0, uint32_t(st.spp)).stats;
        const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
        f.rays = RayCounts{};
        f.rays.camera = s.cameraRays;
        f.rays.shadow = s.shadowRays;
        f.rays.reflection = s.reflectionRays;
        f.rays.nonFinite = s.nonFiniteSamples;
        f.rays.transmission = s.transmissionRays;
        f.rays.indirect = s.indirectRays;
        f.rays.brdf = s.brdfRays;
        return dt;
    };
    if (reps > 1) {
        once(1);
        once(threads);
    }
    f.seconds1 = f.secondsAll = kInfinity;
    for (int i = 0; i < std::max(1, reps); ++i) {
        f.seconds1 = std::min(f.seconds1, once(1));
        f.secondsAll = std::min(f.secondsAll, once(threads));
    }
    return f;
}

}  // namespace penumbra::bench
