#include "shading/path_integrator.h"

#include <algorithm>
#include <cmath>

#include "core/scratch_array.h"
#include "lights/environment_light.h"
#include "lights/light_selection.h"
#include "shading/bsdf/dielectric.h"
#include "shading/mis.h"
#include "shading/bsdf/phong.h"
#include "shading/bsdf/phong_sampling.h"

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
    float bsdfPdf = 0.f;   // solid-angle pdf of the bounce otherwise
    Vec3f prevP, prevN;    // where the bounce left from, and the geometric normal there
    int rays = 1;          // rays traced along the path (statistics)
    // Lobe probabilities at the current vertex: Phong (diffuse + glossy), mirror, glass.
    float pPhong = 0.f, pMirror = 0.f, pGlass = 0.f;
};

namespace {

// The per-bounce sample dimensions of a path vertex: one per light (its light
// samples), the power-selection points and picks, the BRDF direction, and the
// lobe choice with the Russian roulette decision.
struct PathDimensions {
    uint32_t base, lights;
    uint32_t light(size_t j) const { return base + uint32_t(j); }
    uint32_t powerPoint() const { return base + lights; }
    uint32_t powerPick() const { return base + lights + 1; }
    uint32_t direction() const { return base + lights + 2; }
    uint32_t lobeAndRoulette() const { return base + lights + 3; }
};

PathDimensions dimensionsAt(int depth, size_t nLights) {
    const uint32_t stride = uint32_t(nLights) + 4;
    return {kFirstLightDimension + uint32_t(depth) * stride, uint32_t(nLights)};
}

// Shadow rays of a batch's vertices, traced 16 at a time as packets; each
// carries its final (MIS-weighted) contribution and its lane. flush() adds the
// unoccluded ones in the order they were queued (each lane's own sample
// order), so a lane's sum does not depend on the rest of the batch.
class ShadowPackets {
public:
    ShadowPackets(const Accelerator& accel, RayCounts& counts, Rgb* sums) : accel_(accel), counts_(counts), sums_(sums) {}

    void add(size_t lane, const Ray& ray, const Rgb& weight) {
        rays_[pending_] = ray;
        weights_[pending_] = weight;
        lanes_[pending_] = static_cast<uint8_t>(lane);
        if (++pending_ == kPacket) flush();
    }

    void flush() {
        if (pending_ == 0) return;
        accel_.occludedBatch(std::span<const Ray>(rays_, pending_), std::span<uint8_t>(blocked_, pending_));
        counts_.shadow += pending_;
        for (uint32_t i = 0; i < pending_; ++i)
            if (!blocked_[i]) sums_[lanes_[i]] += weights_[i];
        pending_ = 0;
    }

private:
    static constexpr uint32_t kPacket = 16;
    const Accelerator& accel_;
    RayCounts& counts_;
    Rgb* sums_;
    Ray rays_[kPacket];
    Rgb weights_[kPacket];
    uint8_t lanes_[kPacket];
    uint8_t blocked_[kPacket];
    uint32_t pending_ = 0;
};

}  // namespace

PathIntegrator::PathIntegrator(const IntegratorInputs& in)
    : Integrator(in.accel), scene_(in.scene), lights_(in.lights), settings_(in.settings),
      surfaces_(in.scene, in.textures, in.pixelSpread), picker_(lightPicker(in.lights, in.settings)) {}

Rgb PathIntegrator::escaped(const PathVertexLane& lane) const {
    const EnvironmentLight* env = lights_.environment();
    if (!env) return scene_.background;
    const Rgb L = env->radiance(lane.ray.d);
    if (lane.specular || L.isBlack()) return L;
    // The environment is a light of the set (its last): next-event estimation
    // samples it too, so a BRDF-sampled ray that escapes is weighed against
    // the light strategy's density for the same direction.
    float lightPdf = env->pdf(lane.ray.d);
    if (picker_) lightPdf *= picker_->probability(lights_.size() - 1, lane.prevP, lane.prevN);
    return L * powerHeuristic(1.f, lane.bsdfPdf, float(settings_.lightSamples), lightPdf);
}

float PathIntegrator::scatterPdf(const PathVertexLane& lane, const Vec3f& wi) const {
    if (!(lane.pPhong > 0.f)) return 0.f;
    return lane.pPhong * phongPdf(*lane.sp.material, lane.sp.kd, lane.sp.ns, lane.sp.wo, wi);
}

float PathIntegrator::emitterHitWeight(const Vec3f& prevP, const Vec3f& prevN, float bsdfPdf, const Hit& hit) const {
    const std::optional<size_t> j = lights_.lightOf(hit);
    if (!j) return 1.f;  // emission no light sample can find
    // The light strategy's density for this direction: n samples of this light
    // (all lights), or n samples in total that pick it (LightPicker).
    float lightPdf = lights_[*j].pdf(prevP, hit);
    if (picker_) lightPdf *= picker_->probability(*j, prevP, prevN);
    return powerHeuristic(1.f, bsdfPdf, float(settings_.lightSamples), lightPdf);
}

void PathIntegrator::addDirectLight(std::span<PathVertexLane> lanes, std::span<const uint8_t> active, int depth,
                                    RayCounts& counts) const {
    const size_t nLights = lights_.size();
    if (nLights == 0) return;
    const size_t nLanes = lanes.size();
    uint8_t lit[kMaxBatch];
    size_t nLit = 0;
    for (size_t i = 0; i < nLanes; ++i)
        if (active[i] && lanes[i].pPhong > 0.f) lit[nLit++] = static_cast<uint8_t>(i);
    if (nLit == 0) return;

    const uint32_t n = static_cast<uint32_t>(settings_.lightSamples);
    const float invN = 1.f / float(n);
    const PathDimensions dims = dimensionsAt(depth, nLights);
    Rgb sum[kMaxBatch];
    ShadowPackets packets(accel_, counts, sum);

    // One light sample: f cos L / pdf times `scale` (1/n for one of n samples),
    // MIS-weighted against the BRDF sampling of the same direction; lightPdf
    // is the density of the whole light strategy (n samples, times the pick
    // probability with power selection). Delta lights cannot be hit by a
    // bounce, so their samples keep their full weight.
    auto addSample = [&](size_t lane, const LightSample& ls, float pickProbability, float scale) {
        const PathVertexLane& v = lanes[lane];
        const ShadingPoint& sp = v.sp;
        if (dot(ls.wi, sp.ng) <= 0.f) return;
        const Rgb f = phongResponse(*sp.material, sp.kd, sp.ns, sp.wo, ls.wi, ls.delta);
        if (f.isBlack()) return;
        const float w = ls.delta ? 1.f : powerHeuristic(float(n), pickProbability * ls.pdf, 1.f, scatterPdf(v, ls.wi));
        if (!(w > 0.f)) return;
        const Ray ray = std::isinf(ls.distance) ? spawnRay(sp.p, sp.ng, ls.wi) : spawnRayTo(sp.p, sp.ng, ls.point);
        packets.add(lane, ray, v.throughput * f * ls.L * (w * scale / (pickProbability * ls.pdf)));
    };

    if (!picker_) {
        for (size_t j = 0; j < nLights; ++j) {
            const Light& light = lights_[j];
            for (size_t q = 0; q < nLit; ++q) {
                const PathVertexLane& v = lanes[lit[q]];
                if (light.isDelta()) {
                    if (auto ls = light.sample(v.sp.p, Vec2f{0.5f, 0.5f})) addSample(lit[q], *ls, 1.f, 1.f);
                    continue;
                }
                if (!light.mayReach(v.sp.p, v.sp.ng)) continue;  // every sample would be discarded
                const OwenSobol2D seq = dimensionSequence(v.key, dims.light(j));
                if (n == 1) {  // no set-up to share: skip the chunk arrays
                    if (auto ls = light.sample(v.sp.p, seq.point(v.key.index))) addSample(lit[q], *ls, 1.f, 1.f);
                    continue;
                }
                // In chunks, so that a light's per-shading-point set-up is shared.
                constexpr uint32_t kChunk = 64;  // up to 8 x 8 samples share one set-up (Light::sampleMany)
                for (uint32_t k0 = 0; k0 < n; k0 += kChunk) {
                    const uint32_t m = std::min(n - k0, kChunk);
                    Vec2f u[kChunk];
                    std::optional<LightSample> ls[kChunk];
                    seq.samplePoints(v.key.index, n, k0, m, u);  // without the shuffle where n = 2^k
                    light.sampleMany(v.sp.p, std::span<const Vec2f>(u, m), std::span(ls, m));
                    for (uint32_t k = 0; k < m; ++k)
                        if (ls[k]) addSample(lit[q], *ls[k], 1.f, invN);
                }
            }
        }
    } else {
        // n samples in total, each picking one light.
        for (size_t q = 0; q < nLit; ++q) {
            const PathVertexLane& v = lanes[lit[q]];
            const OwenSobol2D seq = dimensionSequence(v.key, dims.powerPoint());
            const OwenSobol2D pickSeq = dimensionSequence(v.key, dims.powerPick());
            for (uint32_t k = 0; k < n; ++k) {
                const uint32_t index = v.key.index * n + k;
                const LightPicker::Pick pick = picker_->pick(pickSeq.point(index).x, v.sp.p, v.sp.ng);
                if (!(pick.probability > 0.f) || !lights_[pick.index].mayReach(v.sp.p, v.sp.ng)) continue;
                if (auto ls = lights_[pick.index].sample(v.sp.p, seq.point(index))) addSample(lit[q], *ls, pick.probability, invN);
            }
        }
    }
    packets.flush();
    for (size_t q = 0; q < nLit; ++q) lanes[lit[q]].L += sum[lit[q]];
}

bool PathIntegrator::scatter(PathVertexLane& lane, int depth, RayCounts& counts) const {
    const ShadingPoint& sp = lane.sp;
    const Material& m = *sp.material;
    const PathDimensions dims = dimensionsAt(depth, lights_.size());
    // One point per camera sample: the pixel's bounces are stratified too.
    const Vec2f uLobe = dimensionSequence(lane.key, dims.lobeAndRoulette()).point(lane.key.index);
    const Vec2f uDir = dimensionSequence(lane.key, dims.direction()).point(lane.key.index);

    Vec3f wi;
    Rgb weight;
    if (uLobe.x < lane.pPhong) {
        const auto s = samplePhong(m, sp.kd, sp.ns, sp.wo, uDir);
        if (!s || !(s->pdf > 0.f) || dot(s->wi, sp.ng) <= 0.f) return false;
        wi = s->wi;
        weight = s->fCos * (1.f / (lane.pPhong * s->pdf));
        lane.specular = false;
        lane.bsdfPdf = lane.pPhong * s->pdf;
        ++counts.indirect;
    } else if (uLobe.x < lane.pPhong + lane.pMirror) {
        Vec3f r = reflect(-sp.wo, sp.ns);
        if (dot(r, sp.ng) <= 0.f) r = reflect(-sp.wo, sp.ng);
        wi = normalize(r);
        weight = Rgb(m.kr) * (1.f / lane.pMirror);
        lane.specular = true;
        ++counts.reflection;
    } else {
        const bool front = dot(sp.wo, lane.hit->ng) > 0.f;
        const float eta = front ? m.ior : 1.f / m.ior;
        // The lobe choice's leftover range, rescaled, picks reflection or refraction.
        const float u = std::min((uLobe.x - lane.pPhong - lane.pMirror) / lane.pGlass, 0x1.fffffep-1f);
        const DielectricSample s = sampleDielectric(sp.wo, sp.ns, sp.ng, eta, Rgb(m.kt), u);
        wi = s.wi;
        weight = s.weight * (1.f / lane.pGlass);
        lane.specular = true;
        ++(s.transmitted ? counts.transmission : counts.reflection);
    }
    lane.throughput *= weight;
    if (lane.throughput.isBlack() || !lane.throughput.isFinite()) return false;
    // Russian roulette: past a few bounces a path survives with a probability
    // that follows its throughput, and carries the lost share when it does.
    if (depth + 1 >= kRouletteDepth) {
        const float survive = std::min(0.95f, lane.throughput.maxComponent());
        if (!(uLobe.y < survive)) return false;
        lane.throughput *= 1.f / survive;
    }
    lane.prevP = sp.p;
    lane.prevN = sp.ng;
    lane.ray = spawnRay(sp.p, sp.ng, wi);
    ++lane.rays;
    return true;
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
    for (int depth = 0;; ++depth) {
        // Emission (MIS-weighted after a non-specular bounce) and the vertex of every lane still going.
        for (size_t i = 0; i < n; ++i) {
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
            const Material& m = *lane.sp.material;
            if (m.isEmissive() && (dot(lane.sp.wo, hit.ng) > 0.f || m.twoSidedEmission)) {
                const float w = lane.specular ? 1.f : emitterHitWeight(lane.prevP, lane.prevN, lane.bsdfPdf, hit);
                lane.L += lane.throughput * m.ke * w;
            }
            if (depth == 0 && !firstHits.empty()) firstHits[i] = FirstHit{lane.sp.kd, lane.sp.ns, hit.t};
            // The path's length limit: --max-depth scattering events (1 = direct light only).
            if (depth >= settings_.maxDepth) {
                active[i] = 0;
                continue;
            }
            // Lobe probabilities: in proportion to each lobe's reflectance (glass reflects
            // and transmits up to 1), the Phong part as one lobe sampled by samplePhong.
            const float phong = lane.sp.reflectsLight() ? Rgb(lane.sp.kd).average() + Rgb(m.ks).average() : 0.f;
            const float mirror = m.isDielectric() ? 0.f : Rgb(m.kr).average();
            const float glass = m.isDielectric() ? 1.f : 0.f;
            const float total = phong + mirror + glass;
            if (!(total > 0.f)) {
                active[i] = 0;
                continue;
            }
            lane.pPhong = phong / total;
            lane.pMirror = mirror / total;
            lane.pGlass = glass / total;
        }
        addDirectLight(batch, std::span<const uint8_t>(active, n), depth, counts);

        // The bounces of the lanes that go on, traced together.
        Ray next[kMaxBatch];
        uint8_t nextLane[kMaxBatch];
        size_t nNext = 0;
        for (size_t i = 0; i < n; ++i) {
            if (!active[i]) continue;
            if (!scatter(lanes[i], depth, counts)) {
                active[i] = 0;
                continue;
            }
            next[nNext] = lanes[i].ray;
            nextLane[nNext++] = static_cast<uint8_t>(i);
        }
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
