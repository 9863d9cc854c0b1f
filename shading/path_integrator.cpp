#include "shading/path_integrator.h"

#include <algorithm>
#include <cmath>

#include "core/lane_clones.h"
#include "core/scratch_array.h"
#include "lights/light_selection.h"

namespace penumbra {

struct PathVertexLane {
    Ray ray;
    const Hit* hit = nullptr;  // the ray's closest hit (in the batch's hit arrays); null: it escaped
    ShadingPoint sp;
    Rgb L;
    Rgb throughput{1.f};
    float pathLength = 0.f;
    SampleKey key{};
    // How the ray being traced was chosen, for the MIS weight of an emitter it hits.
    bool specular = true;  // a delta bounce (or the camera ray): emission counts in full
    float bsdfPdf = 0.f;   // solid-angle pdf of the bounce otherwise, its lobe's probability included
    Vec3f prevP, prevN;    // where the bounce left from, and the geometric normal there
    int rays = 1;          // rays traced along the path (statistics)
    BsdfLobes lobes;       // at the current vertex
};

static_assert(Integrator::kMaxBatch <= size_t(OwenSobol2D::kLanes), "a batch's bounces fit one set of lanes");

PathIntegrator::PathIntegrator(const IntegratorInputs& in)
    : Integrator(in.accel), lights_(in.lights), settings_(in.settings), surfaces_(in.scene, in.textures, in.pixelSpread),
      direct_(in.scene, in.accel, in.lights,
              DirectLight::Options{in.settings.lightSamples, resolvedLightSelection(in.settings, in.lights.size()),
                                   DirectLight::BsdfSamples::Caller, false}) {}

Rgb PathIntegrator::escaped(const PathVertexLane& lane) const {
    if (lane.specular) return direct_.escapedRadiance(lane.ray.d);
    // The environment is a light of the set (its last): next-event estimation
    // samples it too.
    const DirectLight::Escape e = direct_.escape(lane.ray.d, 1.f, lane.bsdfPdf, lane.prevP, lane.prevN);
    return e.L * e.weight;
}

void PathIntegrator::shadeVertices(std::span<PathVertexLane> lanes, std::span<uint8_t> active, int depth,
                                   std::span<FirstHit> firstHits) const {
    for (size_t i = 0; i < lanes.size(); ++i) {
        if (!active[i]) continue;
        PathVertexLane& lane = lanes[i];
        if (!lane.hit) {
            lane.L += lane.throughput * escaped(lane);
            active[i] = 0;
            continue;
        }
        const Hit& hit = *lane.hit;
        lane.pathLength += hit.t;
        surfaces_.shade(hit, lane.ray, lane.pathLength, lane.sp);
        if (lane.sp.emits()) {
            const float w =
                lane.specular ? 1.f : direct_.emitterHitWeight(hit, 1.f, lane.bsdfPdf, lane.prevP, lane.prevN);
            lane.L += lane.throughput * surfaces_.emission(hit, lane.sp) * w;
        }
        if (depth == 0 && !firstHits.empty()) firstHits[i] = FirstHit{lane.sp.kd, lane.sp.ns, hit.t};
        // The path's length limit: --max-depth scattering events (1 = direct light only).
        lane.lobes = depth < settings_.maxDepth ? bsdfLobes(lane.sp) : BsdfLobes{};
        if (!lane.lobes.any()) active[i] = 0;
    }
}

// Inline: scatterBatch's loop over the lanes is its only caller.
[[gnu::always_inline]] inline bool PathIntegrator::scatter(PathVertexLane& lane, int depth,
                                                           const std::optional<BsdfBounce>& b, Ray& next,
                                                           RayCounts& counts) const {
    const ShadingPoint& sp = lane.sp;
    if (!b) return false;
    ++(b->transmitted ? counts.transmission : b->delta ? counts.reflection : counts.indirect);
    lane.throughput *= b->weight;
    lane.specular = b->delta;
    lane.bsdfPdf = b->pdf;
    if (lane.throughput.isBlack() || !lane.throughput.isFinite()) return false;
    // Russian roulette: past a few bounces a path whose throughput has fallen
    // below kRouletteThroughput survives with probability throughput / that,
    // and carries the lost share when it does. Paths of higher throughput go
    // on: ending them, however rarely, gives the survivors a weight far above
    // what the others carry, the largest noise of a grey scene under a sky.
    if (depth + 1 >= kRouletteDepth) {
        const float most = lane.throughput.maxComponent();
        if (most < kRouletteThroughput) {
            const float survive = most / kRouletteThroughput;
            if (!(branchNumbers(lane.key, depth, 0).survive < survive)) return false;
            lane.throughput *= 1.f / survive;
        }
    }
    lane.prevP = sp.p;
    lane.prevN = sp.ng;
    // spawnRay's ray, stored float by float from registers: GCC builds a
    // Ray on the stack and copies it in pieces that straddle its stores, a
    // load that store forwarding cannot serve (a stall per bounce).
    const Ray ray = spawnRay(sp.p, sp.ng, b->wi);
    const float parts[8] = {ray.o.x, ray.o.y, ray.o.z, ray.d.x, ray.d.y, ray.d.z, ray.tnear, ray.tfar};
    for (Ray* to : {&lane.ray, &next})
        to->o.x = parts[0], to->o.y = parts[1], to->o.z = parts[2], to->d.x = parts[3], to->d.y = parts[4],
        to->d.z = parts[5], to->tnear = parts[6], to->tfar = parts[7];
    ++lane.rays;
    return true;
}

PENUMBRA_LANE_CLONES size_t PathIntegrator::scatterBatch(std::span<PathVertexLane> lanes, std::span<uint8_t> active,
                                                         int depth, std::span<const SampleKey> keys, Ray* next,
                                                         uint8_t* nextLane, RayCounts& counts) const {
    constexpr int N = LambertLanes::kLanes;
    static_assert(Integrator::kMaxBatch <= size_t(N) && N == OwenSobol2D::kLanes);
    const size_t n = lanes.size();
    // One point per camera sample: the pixel's bounces are stratified too.
    alignas(64) float ux[N], uy[N];
    dimensionPointLanes(keys.data(), n, VertexDimensions(depth, lights_.size()).bsdf(), ux, uy);
    // The Lambertian bounce's direction of every lane, as sampleBsdf makes
    // it, in one loop over the lanes (unused where the lane bounces otherwise).
    alignas(64) float nx[N], ny[N], nz[N], smooth[N];
    for (int c = 0; c < N; ++c) {
        const bool some = size_t(c) < n && active[c];
        const Vec3f ns = some ? lanes[c].sp.ns : Vec3f{0.f, 0.f, 1.f};
        nx[c] = ns.x, ny[c] = ns.y, nz[c] = ns.z;
        smooth[c] = some ? lanes[c].lobes.smooth : 1.f;
    }
    LambertLanes lambert;
    lambertLanes(nx, ny, nz, ux, uy, smooth, lambert);
    size_t nNext = 0;
    for (size_t i = 0; i < n; ++i) {
        if (!active[i]) continue;
        PathVertexLane& lane = lanes[i];
        const Vec2f u{ux[i], uy[i]};
        const std::optional<BsdfBounce> b = bouncesLambert(lane.sp, lane.lobes, u)
                                                ? lambertBounce(lane.sp, lane.lobes.smooth, lambert.at(int(i)))
                                                : sampleBsdf(lane.sp, lane.lobes, u);
        if (!scatter(lane, depth, b, next[nNext], counts)) {
            active[i] = 0;
            continue;
        }
        nextLane[nNext++] = static_cast<uint8_t>(i);
    }
    return nNext;
}

void PathIntegrator::radianceBatch(std::span<const Ray> cameraRays, std::span<const std::optional<Hit>> hits,
                                   std::span<const SampleKey> keys, std::span<Rgb> radiance,
                                   std::span<FirstHit> firstHits, RayCounts& counts) const {
    const size_t n = std::min(cameraRays.size(), kMaxBatch);
    PathVertexLane lanes[kMaxBatch];
    uint8_t active[kMaxBatch];
    for (size_t i = 0; i < n; ++i) {
        lanes[i].ray = cameraRays[i];
        lanes[i].hit = hits[i] ? &*hits[i] : nullptr;
        lanes[i].key = keys[i];
        active[i] = 1;
        if (!firstHits.empty()) firstHits[i] = FirstHit{};
    }
    counts.camera += n;
    const std::span<PathVertexLane> batch(lanes, n);
    // The hits of each bounce; a lane's hit is read before the next bounce's overwrite it.
    EmptyOptionals<Hit, kMaxBatch> nextHits;
    // The bounces' rays (made once: Ray's initialisers cost a memset per depth).
    Ray next[kMaxBatch];
    uint8_t nextLane[kMaxBatch];
    for (int depth = 0;; ++depth) {
        shadeVertices(batch, std::span<uint8_t>(active, n), depth, firstHits);
        // Next-event estimation where the smooth lobes may reflect light, weighed against the bounce below.
        const auto lit = [&](size_t i) {
            const float smooth = active[i] ? lanes[i].lobes.smooth : 0.f;  // an inactive lane's is not read
            return DirectLight::LitLane{smooth > 0.f, smooth};
        };
        direct_.addTo(batch, lit, depth, counts);

        // The bounces of the lanes that go on, traced together.
        const size_t nNext = scatterBatch(batch, std::span<uint8_t>(active, n), depth, keys, next, nextLane, counts);
        if (nNext == 0) break;
        accel_.intersectBatch(std::span<const Ray>(next, nNext), std::span<std::optional<Hit>>(nextHits.data(), nNext));
        for (size_t c = 0; c < nNext; ++c) lanes[nextLane[c]].hit = nextHits[c] ? &*nextHits[c] : nullptr;
    }
    for (size_t i = 0; i < n; ++i) {
        counts.pathLengthSum += uint64_t(lanes[i].rays);
        counts.pathLengthMax = std::max(counts.pathLengthMax, uint32_t(lanes[i].rays));
        if (lanes[i].L.isFinite()) {
            radiance[i] = lanes[i].L;
        } else {
            ++counts.nonFinite;
            radiance[i] = Rgb{};
        }
    }
}

}  // namespace penumbra
