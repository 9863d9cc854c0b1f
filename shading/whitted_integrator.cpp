#include "shading/whitted_integrator.h"

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "core/lane_clones.h"
#include "core/scratch_array.h"
#include "lights/light_selection.h"
#include "shading/bsdf/dielectric.h"
#include "shading/bsdf/metal_roughness.h"
#include "shading/bsdf/mirror.h"

namespace penumbra {

WhittedIntegrator::WhittedIntegrator(const IntegratorInputs& in)
    : Integrator(in.accel), scene_(in.scene), settings_(in.settings),
      surfaces_(in.scene, in.textures, in.pixelSpread, kMirrorRoughness),
      direct_(in.scene, in.accel, in.lights,
              DirectLight::Options{in.settings.lightSamples, resolvedLightSelection(in.settings, in.lights.size()),
                                   in.settings.directLight == DirectLightSampling::Mis ? DirectLight::BsdfSamples::Own
                                                                                       : DirectLight::BsdfSamples::None,
                                   in.internal.areaLightSamples}) {
    for (const Material& m : in.scene.materials) {
        continues_ |= m.isMirror() || m.isDielectric() || m.kind == MaterialKind::MetalRoughness;
        splits_ |= m.isDielectric();
    }
    continues_ &= settings_.maxDepth > 0;
    splits_ &= continues_;
}

namespace {

// The reflectance of a mirror bounce: kr, or a polished metal-roughness
// surface's specular lobe, which the bounce stands in for.
Rgb mirrorWeight(const ShadingPoint& sp) {
    return sp.mirrorSpecular ? metalRoughnessMirrorWeight(sp) : Rgb(sp.material->kr);
}

}  // namespace

/// A ray one lane still has to trace (the transmitted branch of a dielectric).
struct PendingRay {
    Ray ray;
    Rgb throughput;
    float pathLength;
    int depth;
    uint32_t branch;
};

// One camera sample's path through a batch. Plain values, so that a batch's
// lanes are scratch storage: shadeBatch writes every field before reading it,
// and 16 lanes are not zeroed for every batch.
struct PathLane {
    Ray ray;
    const Hit* hit;                     // the ray's closest hit (in the batch's hit arrays); null: it escaped
    ShadingPoint sp;                    // written by SurfaceShading::shade where the ray hit
    // Each colour shares 16 bytes with a scalar set beside it: where a colour
    // and its neighbour were set together, the compiler merged their stores,
    // and a colour's first read then spanned two of them and waited for them
    // to reach the cache (no store forwarding).
    Rgb L;
    float pathLength;
    Rgb throughput;
    int depth;                          // bounces before the ray being traced
    SampleKey key;
    uint32_t branch;                    // which branch of the camera sample's tree of rays (branchNumbers)
    int longest;                        // rays along the deepest branch so far (path-length statistics)
    std::vector<PendingRay>* pending;   // transmitted rays still to trace (dielectrics), last first; null
                                        // where no lane can split (WhittedIntegrator::splits_)
    uint8_t reflects;                   // sp.reflectsLight() where the ray hit, 0 where it escaped: set for
                                        // every lane, so that the lit lanes are chosen without a branch
};

namespace {

// Each lane's radiance (zero where it is not finite) and the batch's path
// statistics. The counts are summed here and stored once: updated in memory
// lane by lane, each lane's update waited for the one before it. Out of line:
// forced inline into shadeBatch's clones, Figure 24.6 rendered 5% slower.
void writeRadiance(std::span<const PathLane> lanes, std::span<Rgb> radiance, RayCounts& counts) {
    uint64_t lengthSum = 0, nonFinite = 0;
    uint32_t lengthMax = counts.pathLengthMax;
    for (size_t i = 0; i < lanes.size(); ++i) {
        lengthSum += uint64_t(lanes[i].longest);
        lengthMax = std::max(lengthMax, uint32_t(lanes[i].longest));
        // Component by component: L was just written so, and a copy of it
        // as a whole (8 + 4 bytes) could not take the values from those
        // stores (store forwarding) and waited for them to reach the cache.
        const float r = lanes[i].L.r, g = lanes[i].L.g, b = lanes[i].L.b;
        const bool finite = Rgb{r, g, b}.isFinite();
        nonFinite += finite ? 0 : 1;
        radiance[i].r = finite ? r : 0.f;
        radiance[i].g = finite ? g : 0.f;
        radiance[i].b = finite ? b : 0.f;
    }
    counts.pathLengthSum += lengthSum;
    counts.pathLengthMax = lengthMax;
    counts.nonFinite += nonFinite;
}

}  // namespace

PENUMBRA_LANE_CLONES void WhittedIntegrator::addDirectLight(std::span<PathLane> lanes, std::span<const uint8_t> active,
                                                            int depth, RayCounts& counts) const {
    // Light samples where some light can reach the viewer (not at a black or pure mirror material).
    const auto lit = [&](size_t i) { return DirectLight::LitLane{bool(active[i] & lanes[i].reflects), 0.f}; };
    direct_.addTo(lanes, lit, depth, counts);
}

void WhittedIntegrator::radianceBatch(std::span<const Ray> cameraRays, std::span<const std::optional<Hit>> hits,
                                      std::span<const SampleKey> keys, std::span<Rgb> radiance,
                                      std::span<FirstHit> firstHits, RayCounts& counts) const {
    shadeBatch(cameraRays, hits, keys, radiance, firstHits, counts);
}

PENUMBRA_LANE_CLONES void WhittedIntegrator::shadeBatch(std::span<const Ray> cameraRays,
                                                        std::span<const std::optional<Hit>> hits,
                                                        std::span<const SampleKey> keys, std::span<Rgb> radiance,
                                                        std::span<FirstHit> firstHits, RayCounts& counts) const {
    const size_t n = std::min(cameraRays.size(), kMaxBatch);
    ScratchArray<PathLane, kMaxBatch> lanes;
    // The lanes' stacks of pending rays, only where a lane can split: 16 vectors
    // made and destroyed for every batch would cost more than most batches' shading.
    Deferred<std::array<std::vector<PendingRay>, kMaxBatch>> pending;
    if (splits_) pending.emplace();
    uint8_t active[kMaxBatch];
    for (size_t i = 0; i < n; ++i) {
        PathLane& lane = lanes[i];
        lane.ray = cameraRays[i];
        lane.hit = hits[i] ? &*hits[i] : nullptr;
        lane.L = Rgb{};
        lane.pathLength = 0.f;
        lane.throughput = Rgb{1.f};
        lane.depth = 0;
        // Field by field, as the caller wrote them: one 16-byte load could not
        // take the values from those narrower stores still in flight.
        lane.key.pixelKey = keys[i].pixelKey;
        lane.key.index = keys[i].index;
        lane.branch = 0;
        lane.longest = 0;
        lane.pending = splits_ ? &(*pending.get())[i] : nullptr;
        active[i] = 1;
        if (!firstHits.empty()) firstHits[i] = FirstHit{};
    }
    counts.camera += n;
    const std::span<PathLane> batch(lanes.data(), n);
    // The hits of each bounce; a lane's hit is read before the next bounce's overwrite it.
    EmptyOptionals<Hit, kMaxBatch> bounce;
    for (bool first = true;; first = false) {
        // Emission, ambient and the shading point of every lane still going.
        for (size_t i = 0; i < n; ++i) {
            if (!active[i]) continue;
            PathLane& lane = lanes[i];
            lane.longest = std::max(lane.longest, lane.depth + 1);
            if (!lane.hit) {
                lane.L += lane.throughput * direct_.escapedRadiance(lane.ray.d);
                lane.reflects = 0;
                active[i] = 0;
                continue;
            }
            const Hit& hit = *lane.hit;
            lane.pathLength += hit.t;
            surfaces_.shade(hit, lane.ray, lane.pathLength, lane.sp);
            lane.reflects = lane.sp.reflectsLight();
            const Material& m = *lane.sp.material;
            if (lane.sp.emits()) lane.L += lane.throughput * surfaces_.emission(hit, lane.sp);
            if (first && !firstHits.empty()) firstHits[i] = FirstHit{lane.sp.kd, lane.sp.ns, hit.t};
            lane.L += lane.throughput * (m.ka * scene_.ambient);
        }
        addDirectLightByDepth(batch, std::span<uint8_t>(active, n), counts);
        if (!continues_) break;  // no lane could go on (continueLane), nor have a pending ray

        // Mirror and transmitted rays of the lanes that continue, traced together.
        ScratchArray<Ray, kMaxBatch> next;  // written before read: not initialised per bounce
        uint8_t nextLane[kMaxBatch];
        int32_t leaving[kMaxBatch];  // the accelerator's hints: the convex mesh each ray leaves, or -1
        const bool hinted = accel_.takesLeavingHints();
        size_t nNext = 0;
        for (size_t i = 0; i < n; ++i) {
            PathLane& lane = lanes[i];
            // A lane whose branch ends (miss, diffuse surface, depth limit) takes its next pending ray.
            const bool continues = active[i] && continueLane(lane, next[nNext], counts);
            active[i] = continues || resumePending(lane, next[nNext]);
            // continueLane's rays leave the lane's shading point, and leave
            // a convex mesh where they run above its surface.
            leaving[nNext] = continues && hinted && dot(next[nNext].d, lane.sp.ng) > 0.f ? lane.sp.convexMesh : -1;
            if (active[i]) nextLane[nNext++] = static_cast<uint8_t>(i);
        }
        if (nNext == 0) break;
        traceNext(next.data(), nNext, leaving, bounce.data());
        // The lanes take their rays only now: copied just after continueLane wrote
        // them, field by field, a whole Ray could not be loaded from those stores
        // in flight (no store forwarding) and waited for them to reach the cache.
        for (size_t c = 0; c < nNext; ++c) {
            PathLane& lane = lanes[nextLane[c]];
            lane.ray = next[c];
            lane.hit = bounce[c] ? &*bounce[c] : nullptr;
        }
    }
    writeRadiance(std::span<const PathLane>(lanes.data(), n), radiance, counts);
}

[[gnu::noinline]] void WhittedIntegrator::traceNext(const Ray* rays, size_t n, const int32_t* leaving,
                                                    std::optional<Hit>* hits) const {
    // The mirror rays of one pixel block off the same surfaces mostly run
    // together: Embree may trace them as one frustum (coherent).
    accel_.intersectBatch(std::span(rays, n), std::span(hits, n), true, std::span(leaving, n));
}

void WhittedIntegrator::addDirectLightByDepth(std::span<PathLane> lanes, std::span<uint8_t> active, RayCounts& counts) const {
    // Light samples are numbered by bounce depth, and the lanes of a batch may be at different
    // depths once dielectrics split them: one call per depth present, in increasing order. Without
    // dielectrics every lane is at the same depth and this is a single call.
    const size_t n = lanes.size();
    // Without a mirror or glass to go on from, every lane is at depth 0.
    if (!continues_) {
        addDirectLight(lanes, active, 0, counts);
        return;
    }
    // The common case first: every active lane at one depth, one call.
    int depth = -1;
    bool mixed = false;
    for (size_t i = 0; i < n; ++i) {
        if (!active[i]) continue;
        if (depth < 0) depth = lanes[i].depth;
        mixed |= lanes[i].depth != depth;
    }
    if (depth < 0) return;
    if (!mixed) {
        addDirectLight(lanes, active, depth, counts);
        return;
    }
    uint8_t mask[kMaxBatch];
    depth = -1;
    for (;;) {
        int nextDepth = std::numeric_limits<int>::max();
        for (size_t i = 0; i < n; ++i)
            if (active[i] && lanes[i].depth > depth) nextDepth = std::min(nextDepth, lanes[i].depth);
        if (nextDepth == std::numeric_limits<int>::max()) return;
        depth = nextDepth;
        for (size_t i = 0; i < n; ++i) mask[i] = active[i] && lanes[i].depth == depth;
        addDirectLight(lanes, std::span<const uint8_t>(mask, n), depth, counts);
    }
}

[[gnu::always_inline]] inline bool WhittedIntegrator::continueLane(PathLane& lane, Ray& next, RayCounts& counts) const {
    const Material& m = *lane.sp.material;
    if (lane.depth >= settings_.maxDepth) return false;
    if (lane.depth >= kExactDepth) return continueSampled(lane, next, counts);
    if (m.isDielectric()) {
        // Whitted 1980: the mirror ray and the transmitted ray, weighted by Fresnel. The lane follows
        // the mirror ray and keeps the transmitted one pending (its own stack, depth first), so a
        // lane still traces one ray per step and the batch stays one packet. The branches are
        // numbered as the nodes of a binary tree (children 2b + 1 and 2b + 2).
        const float eta = lane.sp.front ? m.ior : 1.f / m.ior;
        const DielectricSplit split = splitDielectric(lane.sp.wo, lane.sp.ns, lane.sp.ng, eta, Rgb(m.kt));
        const Rgb tt = lane.throughput * split.transmittedWeight;
        if (split.transmitted && !tt.isBlack()) {
            lane.pending->push_back(PendingRay{spawnRay(lane.sp.p, lane.sp.ng, *split.transmitted), tt,
                                               lane.pathLength, lane.depth + 1, 2 * lane.branch + 2});
            ++counts.transmission;
        }
        lane.throughput *= split.reflectedWeight;
        if (lane.throughput.isBlack()) return false;
        next = spawnRay(lane.sp.p, lane.sp.ng, split.reflected);
        ++lane.depth;
        lane.branch = 2 * lane.branch + 1;
        ++counts.reflection;
        return true;
    }
    if (!lane.sp.mirrors()) return false;
    lane.throughput *= mirrorWeight(lane.sp);
    if (lane.throughput.isBlack()) return false;
    next = spawnRay(lane.sp.p, lane.sp.ng, mirrorDirection(lane.sp.wo, lane.sp.ns, lane.sp.ng));
    ++lane.depth;
    ++counts.reflection;
    return true;
}

bool WhittedIntegrator::continueSampled(PathLane& lane, Ray& next, RayCounts& counts) const {
    const Material& m = *lane.sp.material;
    const BranchNumbers u = branchNumbers(lane.key, lane.depth + 1, lane.branch);
    Vec3f wi;
    bool transmitted = false;
    if (m.isDielectric()) {
        // One of the two rays, picked in proportion to its Fresnel weight (its weight over that probability).
        const float eta = lane.sp.front ? m.ior : 1.f / m.ior;
        const DielectricSample s = sampleDielectric(lane.sp.wo, lane.sp.ns, lane.sp.ng, eta, Rgb(m.kt), u.pick);
        lane.throughput *= s.weight;
        wi = s.wi;
        transmitted = s.transmitted;
    } else if (lane.sp.mirrors()) {
        lane.throughput *= mirrorWeight(lane.sp);
        wi = mirrorDirection(lane.sp.wo, lane.sp.ns, lane.sp.ng);
    } else {
        return false;
    }
    if (lane.throughput.isBlack()) return false;
    // Russian roulette: a branch of low throughput survives with a probability
    // in proportion to it, and then carries the threshold.
    const float most = lane.throughput.maxComponent();
    if (most < kRouletteThroughput) {
        const float survive = most / kRouletteThroughput;
        if (!(u.survive < survive)) return false;
        lane.throughput *= 1.f / survive;
    }
    next = spawnRay(lane.sp.p, lane.sp.ng, wi);
    ++lane.depth;
    ++(transmitted ? counts.transmission : counts.reflection);
    return true;
}

bool WhittedIntegrator::resumePending(PathLane& lane, Ray& next) const {
    if (!lane.pending || lane.pending->empty()) return false;
    const PendingRay& p = lane.pending->back();
    next = p.ray;
    lane.throughput = p.throughput;
    lane.pathLength = p.pathLength;
    lane.depth = p.depth;
    lane.branch = p.branch;
    lane.pending->pop_back();
    return true;
}

}  // namespace penumbra
