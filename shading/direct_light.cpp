#include "shading/direct_light.h"

#include <algorithm>
#include <cmath>

#include "core/emission.h"
#include "core/lane_clones.h"
#include "core/scratch_array.h"
#include "lights/environment_light.h"
#include "lights/light_selection.h"
#include "shading/bsdf/bsdf.h"
#include "shading/light_windows.h"
#include "shading/mis.h"
#include "shading/shadow_lanes.h"
#include "shading/shadow_queue.h"

namespace penumbra {

namespace {

constexpr int kLaneWidth = ShadowLanes::kWidth;
static_assert(kLaneWidth == OwenSobol2D::kLanes && kLaneWidth == LightLanes::kWidth);
static_assert(DirectLight::kMaxPoints <= size_t(kLaneWidth), "a call's points fit one packet");

// The fewest BSDF samples per shading point for which LightWindows drops the
// samples that can meet no light: building the windows costs about as much
// as making and testing five samples (docs/rendering.md, "MIS").
constexpr uint32_t kMinWindowedBsdfSamples = 6;

// Solid angle (sr) from which a light counts as large for a Lambertian point.
constexpr float kLargeLightSolidAngle = 1.f;

// The solid angle (sr) from which a light counts as large for a glossy point
// (takesBsdfSamples); out of line, so that the Lambertian points' code (the
// textbook scenes' hot path) stays small.
[[gnu::noinline]] float glossyLargeLightSolidAngle(const ShadingPoint& sp) {
    return kLargeLightSolidAngle / bsdfPiPeakPdf(sp);
}

// Whether each of the first n shading points also takes BSDF samples under
// MIS (into take[l], 1 or 0; returns whether any does): where some light
// that may subtend a large solid angle, for the point's BSDF, may also light
// the point (an environment always does); never when the only lights are
// points and directions, which no ray can hit. Decided over the lanes as
// arrays (the textbook scenes take it at every point).
//
// Large is measured against the peak of the BSDF's sampling pdf. A light of
// solid angle omega sampled uniformly over it has a pdf near 1/omega; where
// 1/omega exceeds pi times the BSDF pdf's maximum, the power heuristic gives
// the BSDF samples that meet the light at most 1/(1 + pi^2) of the weight,
// so the estimate is the light samples' with or without them, and a BSDF
// sample would cost a direction, a test against the emitters and mostly
// nothing found. A large light that cannot light the point (Light::mayReach)
// gives its BSDF samples nothing to find. docs/rendering.md ("MIS") has the
// rule in full and its measurements.
[[gnu::always_inline]] inline bool takesBsdfSamples(const ShadingPoint* const* sps, const LanePoints& at, int n,
                                                    const LightSet& lights, int32_t (&take)[kLaneWidth]) {
    const bool all = lights.environment() != nullptr;  // an environment subtends 4 pi
    for (int l = 0; l < n; ++l) take[l] = all;
    if (all) return n > 0;
    if (lights.areaLightCount() == 0) return false;  // point and directional lights: nothing a ray can hit
    alignas(64) float omega[kLaneWidth];
    for (int l = 0; l < n; ++l)
        omega[l] = sps[l]->glossy ? glossyLargeLightSolidAngle(*sps[l]) : kLargeLightSolidAngle;
    int32_t any = 0;
    for (size_t j = 0; j < lights.areaLightCount(); ++j) {
        alignas(64) int32_t exceed[kLaneWidth], reach[kLaneWidth];
        if (!lights.mayExceedSolidAngleLanes(j, at, omega, n, exceed)) continue;
        lights[j].mayReachLanes(at, n, reach);
        for (int l = 0; l < n; ++l) {
            take[l] |= exceed[l] & reach[l];
            any |= take[l];
        }
    }
    return any != 0;
}

// The light samples of the first m lanes of `at`, lane c's being sample ks[c]
// of the n that camera sample indices[c] draws from the sequence of keys[c]
// (where want[c]), traced as one packet: the unoccluded samples' weights into
// added[c] (Rgb{} for the others). Returns the shadow rays traced.
uint32_t traceLightLanes(const Light& light, const ShadowLanes& at, const uint64_t (&keys)[kLaneWidth],
                         const uint32_t (&indices)[kLaneWidth], uint32_t n, const uint32_t (&ks)[kLaneWidth],
                         const int32_t* want, int m, const Accelerator& accel, Rgb* added) {
    // Every lane's point, also where it is not needed: one loop, no branches.
    alignas(64) float ux[kLaneWidth], uy[kLaneWidth];
    OwenSobol2D::pointLanes(keys, indices, n, ks, ux, uy);
    LightLanes samples;
    light.sampleLanes(at.points(), ux, uy, want, m, samples);
    return at.trace(samples, m, float(n), accel, added);
}

// Queues light sample ls of point q: its weight by shadowSampleWeight (scale,
// lightPdf, misCount, nLight as there), its ray towards the sampled point (or
// along its direction, for lights at infinity).
void queueLightSample(ShadowQueue& queue, size_t q, const ShadingPoint& sp, const LightSample& ls, float scale,
                      float lightPdf, float misCount, float nLight) {
    Rgb weight;
    if (!shadowSampleWeight(sp, ls, scale, lightPdf, misCount, nLight, weight)) return;
    queue.add(q, std::isinf(ls.distance) ? spawnRay(sp.p, sp.ng, ls.wi) : spawnRayTo(sp.p, sp.ng, ls.point), weight);
}

}  // namespace

// The state of one estimate() call: its points, as lanes too, which of them
// take BSDF samples, and their sums.
// (Arrays that are written before they are read are left uninitialised: a
// call is made for every batch.)
struct DirectLight::Call {
    // BSDF samples under MIS: half as many as light samples (at least one).
    // A BSDF sample costs about twice a light sample (a closest-hit ray, the
    // lobe's sampling and the light's pdf); where the lobe is sharp, half as
    // many still carry the highlight, and the power heuristic weighs each
    // strategy by its count.
    Call(const Points& p, Rgb* sums, RayCounts& rc, int depth, size_t lights, uint32_t samples)
        : points(p), sum(sums), counts(rc), dims(depth, lights), n(samples), nBsdf((samples + 1) / 2),
          invN(1.f / float(samples)) {}

    const Points& points;
    Rgb* sum;  // per point: the estimate so far
    RayCounts& counts;
    VertexDimensions dims;  // the points' sample dimensions (their bounce depth's)
    uint32_t n;             // light samples per point (per light; in all with picked lights)
    uint32_t nBsdf;         // BsdfSamples::Own: BSDF samples per point that takes them
    float invN;
    LanePoints at;                  // the points and geometric normals as lanes
    float misCount[kMaxPoints];     // the BSDF samples a point's light samples are weighed against (0: none)
    bool ownBsdfSamples = false;    // some point takes BSDF samples of its own
    ShadowLanes lanes;  // the points as the lanes of a packet: the one-sample strategy's
};

DirectLight::DirectLight(const Scene& scene, const Accelerator& accel, const LightSet& lights,
                         const Options& options)
    : scene_(scene), accel_(accel), lights_(lights), lightSamples_(static_cast<uint32_t>(options.lightSamples)),
      bsdf_(options.areaSamples ? BsdfSamples::None : options.bsdf), areaSamples_(options.areaSamples),
      picker_(lightPicker(lights, options.selection)) {
    for (size_t j = 0; j < lights.size(); ++j) {
        sampledLights_ |= !lights[j].isDelta();
        deltaLights_ |= lights[j].isDelta();
    }
    environmentByBsdf_ = lights.environment() && !lights.environment()->hasImage() && bsdf_ != BsdfSamples::None;
    environmentCompensated_ = lights.environment() && lights.environment()->hasImage() && bsdf_ != BsdfSamples::None;
    findClearTargets(scene);
}

void DirectLight::findClearTargets(const Scene& scene) {
    clearTargets_.resize(lights_.size());
    if (!accel_.shapeBounds().available()) return;
    for (size_t j = 0; j < lights_.areaLightCount(); ++j) {
        const std::span<const PrimRef> prims = lights_.emitterPrims(j);
        if (prims.size() != 1) continue;
        const PrimRef r = prims[0];
        ClearTarget t;
        t.self = r;
        Bounds3f box;
        if (r.kind == ShapeKind::Rectangle) {
            const Rectangle& q = scene.rectangles[r.object];
            box = bounds(q);
            t.planePoint = q.p0;
            t.planeNormal = cross(q.a, q.b);
        } else if (r.kind == ShapeKind::Disk) {
            const Disk& d = scene.disks[r.object];
            box = bounds(d);
            t.planePoint = d.center;
            t.planeNormal = d.normal;
        } else {
            continue;
        }
        // Sampled points may round a little outside the shape's box.
        const float pad = 2e-6f * std::max(1.f, std::max(maxAbsComponent(box.lo), maxAbsComponent(box.hi)));
        box = Bounds3f{box.lo - Vec3f(pad), box.hi + Vec3f(pad)};
        t.targets = ShapeBounds::Targets{box, box.center(), 0.5f * length(box.diagonal()) * (1.f + 1e-5f)};
        const float len = length(t.planeNormal);
        if (!(len > 0.f) || !isFinite(t.planeNormal) || !isFinite(box.lo) || !isFinite(box.hi)) continue;
        t.planeNormal = t.planeNormal / len;
        clearTargets_[j] = t;
    }
}

bool DirectLight::shadowsClear(size_t j, const Vec3f& p, const Vec3f& ng) const {
    if (!clearTargets_[j]) return false;
    const ClearTarget& t = *clearTargets_[j];
    // The light's bounding sphere on the side ng faces, clearly: each
    // sample's ray then leaves from p + ng * rayOffsetScale(p) (spawnRayTo,
    // ShadowLanes::trace).
    const Vec3f toLight = t.targets.center - p;
    const float side = dot(toLight, ng) - t.targets.radius;
    if (!(side > 1e-4f * std::max(1.f, maxAbsComponent(toLight)))) return false;
    const Vec3f o = p + ng * rayOffsetScale(p);
    // The origin clearly off the light's plane: no segment runs along the light.
    if (!(std::fabs(dot(o - t.planePoint, t.planeNormal)) > 1e-4f * std::max(1.f, maxAbsComponent(o)))) return false;
    return accel_.shapeBounds().segmentsClear(o, t.targets, t.self);
}

float DirectLight::bsdfSampleWeight(size_t j, float lightPdf, float nBsdf, float bsdfPdf, const Vec3f& p,
                                    const Vec3f& n) const {
    if (!takesLightSamples(j)) return 1.f;
    if (picker_) lightPdf *= picker_->probability(j, p, n);
    return powerHeuristic(nBsdf, bsdfPdf, float(lightSamples_), lightPdf);
}

float DirectLight::emitterHitWeight(const Hit& hit, float nBsdf, float bsdfPdf, const Vec3f& p, const Vec3f& n) const {
    const std::optional<size_t> j = lights_.lightOf(hit);
    if (!j) return 1.f;  // emission no light sample can find
    return bsdfSampleWeight(*j, lights_[*j].pdf(p, hit), nBsdf, bsdfPdf, p, n);
}

const Light& DirectLight::sampledLight(size_t j) const {
    return environmentCompensated_ && j + 1 == lights_.size() ? lights_.environment()->misSampled() : lights_[j];
}

DirectLight::Escape DirectLight::escape(const Vec3f& dir, float nBsdf, float bsdfPdf, const Vec3f& p,
                                        const Vec3f& n) const {
    const EnvironmentLight* env = lights_.environment();
    if (!env) return {scene_.background, 1.f};
    const EnvironmentLight::Lookup e = env->lookup(dir);
    if (e.L.isBlack()) return {e.L, 1.f};
    const float lightPdf = environmentCompensated_ ? e.misPdf : e.pdf;
    return {e.L, bsdfSampleWeight(lights_.size() - 1, lightPdf, nBsdf, bsdfPdf, p, n)};
}

Rgb DirectLight::escapedRadiance(const Vec3f& dir) const {
    const EnvironmentLight* env = lights_.environment();
    return env ? env->radiance(dir) : scene_.background;
}

// (Inline, as is sampleLight: both run in estimate's lane clones, once per call and light.)
[[gnu::always_inline]] inline void DirectLight::decideBsdfSamples(Call& c) const {
    const size_t n = c.points.n;
    if (bsdf_ == BsdfSamples::Caller) {
        std::copy_n(c.points.bsdfCount, n, c.misCount);
        return;
    }
    std::fill_n(c.misCount, n, 0.f);
    if (bsdf_ != BsdfSamples::Own || !sampledLights_) return;
    alignas(64) int32_t take[kLaneWidth];
    c.ownBsdfSamples = takesBsdfSamples(c.points.sp, c.at, int(n), lights_, take);
    for (size_t q = 0; q < n; ++q) c.misCount[q] = take[q] ? float(c.nBsdf) : 0.f;
}

[[gnu::always_inline]] inline void DirectLight::sampleLight(size_t j, Call& c) const {
    const Light& light = lights_[j];
    if (light.isDelta()) return sampleDeltaLight(light, c);
    if (areaSamples_) return sampleByArea(j, c);
    if (c.n == 1) return sampleOnePerPoint(j, c);
    if (c.n < uint32_t(kLaneWidth)) return samplePairs(j, c);
    sampleManyPerPoint(j, c);
}

PENUMBRA_LANE_CLONES void DirectLight::estimate(const Points& points, int depth, Rgb* direct,
                                                RayCounts& counts) const {
    const size_t nLights = lights_.size();
    const size_t n = points.n;
    std::fill_n(direct, n, Rgb{});
    if (nLights == 0) return;
    const uint32_t samples = lightSamples_;
    Call c(points, direct, counts, depth, nLights, samples);
    if (sampledLights_ || deltaLights_)
        for (size_t q = 0; q < n; ++q) c.at.set(int(q), points.sp[q]->p, points.sp[q]->ng);
    decideBsdfSamples(c);
    if (picker_) {
        samplePickedLights(c);
    } else {
        // The points as the lanes of one packet: for one sample of each light per point, and for point lights.
        if ((sampledLights_ && samples == 1 && !areaSamples_) || deltaLights_) {
            c.lanes.setPoints(c.at);
            for (size_t q = 0; q < n; ++q) c.lanes.setShading(int(q), *points.sp[q], c.misCount[q]);
        }
        for (size_t j = 0; j < nLights; ++j)
            if (takesLightSamples(j)) sampleLight(j, c);
    }
    if (c.ownBsdfSamples) sampleBsdf(c);
}

// The strategies that queue one sample at a time: each point's samples
// (sampleAt(q, sp, key, queue)) go through one shadow queue, and their sum
// times `scale` is added to the point's estimate.
template <class SampleAt>
void DirectLight::queueSamples(Call& c, float scale, SampleAt sampleAt) const {
    const size_t count = c.points.n;
    ScratchArray<Rgb, kMaxPoints> acc;
    ShadowQueue queue(accel_, c.counts.shadow, acc.data());
    for (size_t q = 0; q < count; ++q) {
        acc[q] = Rgb{};
        sampleAt(q, *c.points.sp[q], c.points.key[q], queue);
    }
    queue.flush();
    for (size_t q = 0; q < count; ++q) c.sum[q] += acc[q] * scale;
}

// A point or directional light: one exact sample per point, the points as the
// lanes of one packet (no sample numbers: the light has one point).
PENUMBRA_LANE_CLONES void DirectLight::sampleDeltaLight(const Light& light, Call& c) const {
    const int n = int(c.points.n);
    alignas(64) int32_t want[kLaneWidth];
    alignas(64) float half[kLaneWidth];
    std::fill_n(want, kLaneWidth, 1);
    std::fill_n(half, kLaneWidth, 0.5f);
    LightLanes samples;
    light.sampleLanes(c.lanes.points(), half, half, want, n, samples);
    ScratchArray<Rgb, kMaxPoints> added;
    c.counts.shadow += c.lanes.trace(samples, n, float(c.n), accel_, added.data());
    for (int q = 0; q < n; ++q) c.sum[q] += added[q];
}

// One sample per point: every step over the points as the lanes of a packet.
PENUMBRA_LANE_CLONES void DirectLight::sampleOnePerPoint(size_t j, Call& c) const {
    const Light& light = sampledLight(j);
    const size_t n = c.points.n;
    const uint32_t dim = c.dims.light(j);
    alignas(64) int32_t reach[kLaneWidth];
    alignas(64) uint64_t keys[kLaneWidth];
    alignas(64) uint32_t indices[kLaneWidth];
    alignas(64) const uint32_t first[kLaneWidth] = {};
    light.mayReachLanes(c.at, int(n), reach);
    for (size_t q = 0; q < size_t(kLaneWidth); ++q) {
        keys[q] = q < n ? dimensionKey(c.points.key[q], dim) : 0;
        indices[q] = q < n ? c.points.key[q].index : 0;
    }
    ScratchArray<Rgb, kMaxPoints> added;
    c.counts.shadow +=
        traceLightLanes(light, c.lanes, keys, indices, 1, first, reach, int(n), accel_, added.data());
    const float invN = c.invN;
    for (size_t q = 0; q < n; ++q) c.sum[q] += added[q] * invN;
}

// 2 to 15 samples per point: the lanes of a packet are (point, sample) pairs,
// point by point and each point's samples in order, so that a point's sum
// takes its samples in sample order whatever the batch holds.
PENUMBRA_LANE_CLONES void DirectLight::samplePairs(size_t j, Call& c) const {
    const Light& light = sampledLight(j);
    const uint32_t dim = c.dims.light(j), n = c.n;
    const size_t count = c.points.n;
    ShadowLanes pairs;
    alignas(64) uint64_t keys[kLaneWidth] = {};
    alignas(64) uint32_t indices[kLaneWidth] = {}, sampleOf[kLaneWidth] = {};
    alignas(64) int32_t want[kLaneWidth];
    uint8_t owner[kLaneWidth];
    ScratchArray<Rgb, kMaxPoints> acc;
    int m = 0;
    const auto tracePairs = [&] {
        ScratchArray<Rgb, kLaneWidth> added;
        c.counts.shadow +=
            traceLightLanes(light, pairs, keys, indices, n, sampleOf, want, m, accel_, added.data());
        for (int l = 0; l < m; ++l) acc[owner[l]] += added[l];
        m = 0;
    };
    // Points whose every sample would be discarded take no lanes.
    alignas(64) int32_t reach[kLaneWidth];
    light.mayReachLanes(c.at, int(count), reach);
    for (size_t q = 0; q < count; ++q) {
        acc[q] = Rgb{};
        if (!reach[q]) continue;
        const uint64_t key = dimensionKey(c.points.key[q], dim);
        const uint32_t index = c.points.key[q].index;
        const ShadingPoint& sp = *c.points.sp[q];
        const float misCount = c.misCount[q];
        for (uint32_t k = 0; k < n; ++k) {
            pairs.setLane(m, sp, misCount);
            keys[m] = key;
            indices[m] = index;
            sampleOf[m] = k;
            want[m] = 1;
            owner[m] = static_cast<uint8_t>(q);
            if (++m == kLaneWidth) tracePairs();
        }
    }
    if (m > 0) tracePairs();
    const float invN = c.invN;
    for (size_t q = 0; q < count; ++q) c.sum[q] += acc[q] * invN;
}

// 16 and more samples per point: a point's samples, 16 at a time as the lanes
// of a packet, in sample order.
PENUMBRA_LANE_CLONES void DirectLight::sampleManyPerPoint(size_t j, Call& c) const {
    const Light& light = sampledLight(j);
    const uint32_t dim = c.dims.light(j), n = c.n;
    const float invN = c.invN;
    constexpr uint32_t W = uint32_t(kLaneWidth);
    ShadowLanes lanes;
    for (size_t q = 0; q < c.points.n; ++q) {
        const ShadingPoint& sp = *c.points.sp[q];
        const SampleKey& key = c.points.key[q];
        Rgb acc;
        if (light.mayReach(sp.p, sp.ng)) {  // else every sample would be discarded
            const OwenSobol2D seq = dimensionSequence(key, dim);
            // Where nothing can lie between the point and the light, its rays need no query.
            const bool clear = shadowsClear(j, sp.p, sp.ng);
            lanes.setAll(sp, c.misCount[q]);
            for (uint32_t k0 = 0; k0 < n; k0 += W) {
                const uint32_t m = std::min(n - k0, W);
                alignas(64) float ux[W], uy[W];
                seq.samplePointLanes(key.index, n, k0, ux, uy);
                LightLanes samples;
                light.sampleManyLanes(sp.p, ux, uy, int(m), samples);
                ScratchArray<Rgb, W> added;
                c.counts.shadow += lanes.trace(samples, int(m), float(n), accel_, added.data(), clear);
                for (uint32_t l = 0; l < m; ++l) acc += added[l];
            }
        }
        c.sum[q] += acc * invN;
    }
}

// Points uniform in the light's area (Light::sampleArea), without MIS: the
// estimator before solid-angle sampling, kept for comparisons.
void DirectLight::sampleByArea(size_t j, Call& c) const {
    const Light& light = lights_[j];
    const uint32_t dim = c.dims.light(j), n = c.n;
    queueSamples(c, c.invN, [&](size_t q, const ShadingPoint& sp, const SampleKey& key, ShadowQueue& queue) {
        if (!light.mayReach(sp.p, sp.ng)) return;  // every sample would be discarded
        const OwenSobol2D seq = dimensionSequence(key, dim);
        for (uint32_t k = 0; k < n; ++k)
            if (auto ls = light.sampleArea(sp.p, seq.point(key.index * n + k)))
                queueLightSample(queue, q, sp, *ls, 1.f, ls->pdf, 0.f, float(n));
    });
}

// Picked lights (LightPicker): n samples per point in all, each picks one
// light with its point's x and samples it with the rest of the point.
void DirectLight::samplePickedLights(Call& c) const {
    const uint32_t dim = c.dims.pickedLights(), n = c.n;
    queueSamples(c, c.invN, [&](size_t q, const ShadingPoint& sp, const SampleKey& key, ShadowQueue& queue) {
        const OwenSobol2D seq = dimensionSequence(key, dim);
        for (uint32_t k = 0; k < n; ++k) {
            const Vec2f u = seq.point(key.index * n + k);
            const LightPicker::Pick pick = picker_->pick(u.x, sp.p, sp.ng);
            const Light& light = sampledLight(pick.index);
            if (!(pick.probability > 0.f) || !takesLightSamples(pick.index) || !light.mayReach(sp.p, sp.ng)) continue;
            const Vec2f v{pick.u, u.y};
            const std::optional<LightSample> ls = areaSamples_ ? light.sampleArea(sp.p, v) : light.sample(sp.p, v);
            if (ls)
                queueLightSample(queue, q, sp, *ls, 1.f / pick.probability, ls->pdf * pick.probability,
                                 c.misCount[q], float(n));
        }
    });
}

// BSDF-sampled rays of a batch's shading points, traced 16 at a time as
// packets. A ray that reaches the emitting side of a light adds f cos / pdf *
// Le times its MIS weight against the light samples of that light (an
// escaped ray: the environment's radiance); the sums are kept apart from the
// light samples' and filled in queue order, so determinism holds as there.
// These rays only estimate direct light: no path continues along them, so
// nothing the integrators add for the rays they trace is counted twice.
//
// Where the lights have few primitives (LightSet::emittersTestable), a ray is
// first tested against them alone: one that meets no light (most of them,
// under small lights) adds nothing and is not traced at all, and one that
// meets a light needs only an occlusion query up to it, not a closest hit
// and its completion. Else every ray takes a closest-hit query.
class DirectLight::BsdfQueue {
public:
    BsdfQueue(const DirectLight& owner, RayCounts& counts, Rgb* sums, float nBsdf)
        : owner_(owner), lights_(owner.lights_), counts_(counts), sums_(sums), nBsdf_(nBsdf),
          emittersFirst_(owner.lights_.emittersTestable()), occlusion_(owner.accel_, counts.brdf, sums) {}

    /// The sample in direction wi (from sampler.direction) at sp: f cos and
    /// the pdf are only evaluated where the ray may reach a light (a sample
    /// with a zero pdf adds nothing, as samplePhong drops it).
    void add(size_t lane, const ShadingPoint& sp, const BsdfSampler& sampler, const Vec3f& wi) {
        if (dot(wi, sp.ng) <= 0.f) return;  // below the geometric surface
        const Ray ray = spawnRay(sp.p, sp.ng, wi);
        if (!emittersFirst_) return addClosestHitQuery(lane, sp, sampler, ray);
        Ray shadow = ray;
        Rgb added;
        const std::optional<LightSet::EmitterHit> e = lights_.firstEmitterHit(ray);
        if (!e && !lights_.environment()) return;  // nothing to reach
        const BsdfSample s = sampler.evaluate(wi);
        if (!(s.pdf > 0.f)) return;
        const Rgb weight = s.fCos * (1.f / s.pdf);
        if (e) {
            const Hit hit = owner_.scene_.completeHit(ray, e->ref, e->hit.t, e->hit.u, e->hit.v);
            const std::optional<Rgb> L = emitted(sp.p, sp.ng, ray.d, hit, e->light, weight, s.pdf);
            if (!L) return;
            added = *L;
            // Up to the light, stopping short of it as a shadow ray to a point on it does.
            shadow.tfar = std::max(0.f, e->hit.t - rayOffsetScale(hit.p));
        } else {
            added = fromEnvironment(sp.p, sp.ng, ray.d, weight, s.pdf);
        }
        occlusion_.add(lane, shadow, added);
    }

    void flush() {
        if (emittersFirst_) return occlusion_.flush();
        if (pending_ == 0) return;
        counts_.brdf += pending_;
        owner_.accel_.intersectBatch(std::span<const Ray>(rays_.data(), pending_),
                                     std::span<std::optional<Hit>>(hits_.data(), pending_));
        for (uint32_t i = 0; i < pending_; ++i) {
            if (!hits_[i]) {
                // Escaped: it reaches the environment light (the set's last light), if any.
                if (lights_.environment())
                    sums_[lanes_[i]] += fromEnvironment(origins_[i], normals_[i], rays_[i].d, weights_[i], pdfs_[i]);
                continue;
            }
            const std::optional<size_t> light = lights_.lightOf(*hits_[i]);
            if (!light) continue;  // no light (emissive or not): light samples never see it either
            if (auto L = emitted(origins_[i], normals_[i], rays_[i].d, *hits_[i], *light, weights_[i], pdfs_[i]))
                sums_[lanes_[i]] += *L;
        }
        pending_ = 0;
    }

private:
    void addClosestHitQuery(size_t lane, const ShadingPoint& sp, const BsdfSampler& sampler, const Ray& ray) {
        const BsdfSample s = sampler.evaluate(ray.d);
        if (!(s.pdf > 0.f)) return;
        rays_[pending_] = ray;
        origins_[pending_] = sp.p;
        normals_[pending_] = sp.ng;
        weights_[pending_] = s.fCos * (1.f / s.pdf);
        pdfs_[pending_] = s.pdf;
        lanes_[pending_] = static_cast<uint8_t>(lane);
        if (++pending_ == kPacket) flush();
    }

    // What a ray from p (geometric normal n) in direction d adds where it
    // meets light `light` at hit (weight f cos / pdf, bsdfPdf its BSDF pdf);
    // nullopt on the side that does not emit.
    std::optional<Rgb> emitted(const Vec3f& p, const Vec3f& n, const Vec3f& d, const Hit& hit, size_t light,
                               const Rgb& weight, float bsdfPdf) const {
        const Material& m = owner_.scene_.material(hit.material);
        if (!m.isEmissive() || !(dot(d, hit.ng) < 0.f || m.twoSidedEmission)) return std::nullopt;
        return weight * emittedRadiance(owner_.scene_, lights_.textures(), m, hit) * owner_.bsdfSampleWeight(light, lights_[light].pdf(p, hit), nBsdf_, bsdfPdf, p, n);
    }

    // What an escaped ray in direction d adds (the environment is the set's last light).
    Rgb fromEnvironment(const Vec3f& p, const Vec3f& n, const Vec3f& d, const Rgb& weight, float bsdfPdf) const {
        const Escape e = owner_.escape(d, nBsdf_, bsdfPdf, p, n);
        return weight * e.L * e.weight;
    }

    static constexpr uint32_t kPacket = 16;
    const DirectLight& owner_;
    const LightSet& lights_;
    RayCounts& counts_;
    Rgb* sums_;
    float nBsdf_;
    bool emittersFirst_;
    ShadowQueue occlusion_;  // emitters first: the rays up to the light each meets
    // Else the closest-hit queries: the rays, where they start (point and normal), f cos / pdf and the pdf.
    ScratchArray<Ray, kPacket> rays_;
    EmptyOptionals<Hit, kPacket> hits_;
    ScratchArray<Vec3f, kPacket> origins_, normals_;
    ScratchArray<Rgb, kPacket> weights_;
    float pdfs_[kPacket];
    uint8_t lanes_[kPacket];
    uint32_t pending_ = 0;
};

// BSDF samples: nBsdf per point that takes them, shared by all lights; each
// lands on at most one.
PENUMBRA_LANE_CLONES void DirectLight::sampleBsdf(Call& c) const {
    ScratchArray<Rgb, kMaxPoints> found;
    for (size_t q = 0; q < c.points.n; ++q) found[q] = Rgb{};
    BsdfQueue queue(*this, c.counts, found.data(), float(c.nBsdf));
    // Where only the lights' own surfaces count (no environment) and they
    // are few, samples that can meet no light are dropped before their
    // direction is made: they would add nothing and trace no ray. The
    // windows cost, per shading point and light, an asin and an atan2
    // per lobe and two pows for the cos^e lobe, so only where enough
    // samples share them.
    const bool windowed =
        c.nBsdf >= kMinWindowedBsdfSamples && lights_.emittersTestable() && !lights_.environment();
    const uint32_t dim = c.dims.bsdf();
    constexpr uint32_t W = uint32_t(OwenSobol2D::kLanes);
    static_assert(int(W) == LightWindows::kLanes);
    for (size_t q = 0; q < c.points.n; ++q) {
        if (!(c.misCount[q] > 0.f)) continue;
        const ShadingPoint& sp = *c.points.sp[q];
        const SampleKey& key = c.points.key[q];
        const OwenSobol2D seq = dimensionSequence(key, dim);
        const BsdfSampler sampler(sp);
        std::optional<LightWindows> windows;
        if (windowed && sampler.phong()) windows.emplace(*sampler.phong(), lights_, sp.p);
        // 16 points at a time as lanes (OwenSobol2D::samplePointLanes), the same points as samplePoints.
        for (uint32_t k0 = 0; k0 < c.nBsdf; k0 += W) {
            const uint32_t m = std::min(c.nBsdf - k0, W);
            alignas(64) float ux[W], uy[W];
            seq.samplePointLanes(key.index, c.nBsdf, k0, ux, uy);
            alignas(64) int32_t may[W];
            if (windows) windows->mayReachLanes(ux, uy, may);
            for (uint32_t k = 0; k < m; ++k) {
                if (windows && !may[k]) continue;
                if (const std::optional<Vec3f> wi = sampler.direction(Vec2f{ux[k], uy[k]})) queue.add(q, sp, sampler, *wi);
            }
        }
    }
    queue.flush();
    for (size_t q = 0; q < c.points.n; ++q) c.sum[q] += found[q] * (1.f / float(c.nBsdf));
}

}  // namespace penumbra
