#include "shading/integrator.h"

#include "core/lane_clones.h"
#include "core/scratch_array.h"
#include "core/texture_cache.h"
#include "lights/environment_light.h"
#include "shading/dielectric.h"
#include "shading/light_windows.h"
#include "shading/mis.h"
#include "shading/phong.h"
#include "shading/phong_sampling.h"
#include "shading/shadow_lanes.h"

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

namespace penumbra {

Rgb escapedRadiance(const Scene& scene, const LightSet& lights, const Vec3f& dir) {
    const EnvironmentLight* env = lights.environment();
    return env ? env->radiance(dir) : scene.background;
}

Integrator::Integrator(const Scene& scene, const Accelerator& accel, const LightSet& lights,
                       const TextureCache* textures, const RenderSettings& settings)
    : scene_(scene), accel_(accel), lights_(lights), textures_(textures), settings_(settings) {
    for (const Material& m : scene.materials) continues_ |= m.isMirror() || m.isDielectric();
    continues_ &= settings.maxDepth > 0;
    clearTargets_.resize(lights.size());
    if (!accel.shapeBounds().available()) return;
    for (size_t j = 0; j < lights.areaLightCount(); ++j) {
        const std::span<const PrimRef> prims = lights.emitterPrims(j);
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

bool Integrator::shadowsClear(size_t j, const Vec3f& p, const Vec3f& ng) const {
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

Rgb Integrator::diffuseAlbedo(const Material& m, const Hit& hit, float pathLength, const Vec3f& wo) const {
    if (m.textureIndex < 0 || !textures_) return m.kd;
    // Filter footprint in uv: the pixel's cone width at the hit (a ray cone:
    // distance travelled times the pixel's angle, stretched by the grazing
    // angle), converted to uv units with the triangle's uv-per-world scale.
    float footprint = 0.f;
    Transform place;  // an instanced mesh's triangle is measured where the instance puts it
    const TriangleMesh* meshPtr = pixelSpread_ > 0.f ? scene_.meshOf(hit.ref, &place) : nullptr;
    if (meshPtr) {
        const TriangleMesh& mesh = *meshPtr;
        if (!mesh.uvs.empty()) {
            const uint32_t* idx = &mesh.indices[3 * hit.ref.prim];
            const Vec2f &a = mesh.uvs[idx[0]], &b = mesh.uvs[idx[1]], &c = mesh.uvs[idx[2]];
            const float uvArea = std::fabs((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
            const Vec3f p0 = place.applyPoint(mesh.positions[idx[0]]), p1 = place.applyPoint(mesh.positions[idx[1]]),
                        p2 = place.applyPoint(mesh.positions[idx[2]]);
            const float worldArea = length(cross(p1 - p0, p2 - p0));
            if (worldArea > 0.f) {
                const float cosTheta = std::max(std::fabs(dot(wo, hit.ns)), 0.2f);
                footprint = pathLength * pixelSpread_ / cosTheta * std::sqrt(uvArea / worldArea);
            }
        }
    }
    return m.kd * textures_->lookup(m.textureIndex, hit.uv, footprint);
}

PENUMBRA_LANE_CLONES void Integrator::shade(const Hit& hit, const Ray& ray, float pathLength,
                                            ShadingPoint& sp) const {
    sp.material = &scene_.material(hit.material);
    sp.p = hit.p;
    sp.wo = -ray.d;
    // Shading is two-sided: flip both normals to the viewer's side.
    const bool front = dot(sp.wo, hit.ng) > 0.f;
    sp.ng = front ? hit.ng : -hit.ng;
    sp.ns = front ? hit.ns : -hit.ns;
    sp.kd = diffuseAlbedo(*sp.material, hit, pathLength, sp.wo);
    sp.glossy = sp.material->isGlossy();
}

/// A ray one lane still has to trace (the transmitted branch of a dielectric).
struct PendingRay {
    Ray ray;
    Rgb throughput;
    float pathLength;
    int depth;
};

// One camera sample's path through a batch. Plain values, so that a batch's
// lanes are scratch storage: radianceBatch writes every field before reading
// it, where zeroing 16 lanes for every batch showed in the profiles.
struct PathLane {
    Ray ray;
    const Hit* hit;                     // the ray's closest hit (in the batch's hit arrays); null: it escaped
    ShadingPoint sp;                    // written by shade() where the ray hit
    Rgb L;
    Rgb throughput;
    float pathLength;
    SampleKey key;
    int depth;                          // bounces before the ray being traced
    int longest;                        // rays along the deepest branch so far (path-length statistics)
    std::vector<PendingRay>* pending;   // transmitted rays still to trace (dielectrics), last first; null
                                        // where no lane can go on (Integrator::continues_)
};

namespace {

// Shadow rays of a batch's shading points, traced 16 at a time as packets.
// Each ray carries the weight f * L / pdf of its sample (times its MIS
// weight) and the lane it belongs to; flush() adds the weights of the
// unoccluded ones to their lanes' sums in the order they were queued, which
// is each lane's sample order, so a lane's sum does not depend on the other
// lanes in the batch.
class ShadowQueue {
public:
    /// nLight, nBrdf: light and BRDF samples per shading point (the MIS weights' counts).
    ShadowQueue(const Accelerator& accel, RayCounts& counts, Rgb* sums, float nLight = 1.f, float nBrdf = 1.f)
        : accel_(accel), counts_(counts), sums_(sums), nLight_(nLight), nBrdf_(nBrdf) {}

    /// scale, lightPdf, mis: as in shadowSampleWeight.
    void add(size_t lane, const ShadingPoint& sp, const LightSample& ls, float scale, float lightPdf, bool mis) {
        Rgb weight;
        if (!shadowSampleWeight(sp, ls, scale, lightPdf, mis, nLight_, nBrdf_, weight)) return;
        rays_[pending_] = std::isinf(ls.distance) ? spawnRay(sp.p, sp.ng, ls.wi) : spawnRayTo(sp.p, sp.ng, ls.point);
        weights_[pending_] = weight;
        lanes_[pending_] = static_cast<uint8_t>(lane);
        if (++pending_ == kPacket) flush();
    }

    void flush() {
        if (pending_ == 0) return;
        accel_.occludedBatch(std::span<const Ray>(rays_.data(), pending_), std::span<uint8_t>(blocked_, pending_));
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
    float nLight_, nBrdf_;
    ScratchArray<Ray, kPacket> rays_;
    ScratchArray<Rgb, kPacket> weights_;
    uint8_t lanes_[kPacket];
    uint8_t blocked_[kPacket];
    uint32_t pending_ = 0;
};

// BRDF-sampled rays of a batch's shading points, traced 16 at a time as
// packets. A ray that reaches the emitting side of a light adds f cos / pdf *
// Le times its power-heuristic weight against the light samples of that
// light (an escaped ray: the environment's radiance); the sums are kept apart
// from the shadow queue's and filled in queue order, so determinism holds as
// there. These rays only estimate direct light: the path does not continue
// along them, so nothing the integrator adds for camera and mirror rays is
// counted twice.
//
// Where the lights have few primitives (LightSet::emittersTestable), a ray is
// first tested against them alone: one that meets no light (most of them,
// under small lights) adds nothing and is not traced at all, and one that
// meets a light needs only an occlusion query up to it, not a closest hit
// and its completion. Else every ray takes a closest-hit query.
class BrdfQueue {
public:
    BrdfQueue(const Accelerator& accel, const Scene& scene, const LightSet& lights, bool powerSelection,
              RayCounts& counts, Rgb* sums, float nLight, float nBrdf)
        : accel_(accel), scene_(scene), lights_(lights), power_(powerSelection), counts_(counts), sums_(sums),
          nLight_(nLight), nBrdf_(nBrdf), emittersFirst_(lights.emittersTestable()) {}

    /// The sample in direction wi (from sampler.direction) at sp: f cos and
    /// the pdf are only evaluated where the ray may reach a light (a sample
    /// with a zero pdf adds nothing, as samplePhong drops it).
    void add(size_t lane, const ShadingPoint& sp, const PhongSampler& sampler, const Vec3f& wi) {
        if (dot(wi, sp.ng) <= 0.f) return;  // below the geometric surface
        const Ray ray = spawnRay(sp.p, sp.ng, wi);
        if (!emittersFirst_) {
            const PhongSample s = sampler.evaluate(wi);
            if (!(s.pdf > 0.f)) return;
            rays_[pending_] = ray;
            origins_[pending_] = sp.p;
            weights_[pending_] = s.fCos * (1.f / s.pdf);
            pdfs_[pending_] = s.pdf;
            lanes_[pending_] = static_cast<uint8_t>(lane);
            if (++pending_ == kPacket) flush();
            return;
        }
        Ray shadow = ray;
        Rgb added;
        const std::optional<LightSet::EmitterHit> e = lights_.firstEmitterHit(ray);
        if (!e && !lights_.environment()) return;  // nothing to reach
        const PhongSample s = sampler.evaluate(wi);
        if (!(s.pdf > 0.f)) return;
        const Rgb weight = s.fCos * (1.f / s.pdf);
        if (e) {
            const Hit hit = scene_.completeHit(ray, e->ref, e->hit.t, e->hit.u, e->hit.v);
            const std::optional<Rgb> L = emitted(sp.p, ray.d, hit, e->light, weight, s.pdf);
            if (!L) return;
            added = *L;
            // Up to the light, stopping short of it as a shadow ray to a point on it does.
            shadow.tfar = std::max(0.f, e->hit.t - rayOffsetScale(hit.p));
        } else {
            added = fromEnvironment(ray.d, weight, s.pdf);
        }
        rays_[pending_] = shadow;
        weights_[pending_] = added;
        lanes_[pending_] = static_cast<uint8_t>(lane);
        if (++pending_ == kPacket) flush();
    }

    void flush() {
        if (pending_ == 0) return;
        counts_.brdf += pending_;
        if (emittersFirst_) {
            accel_.occludedBatch(std::span<const Ray>(rays_.data(), pending_), std::span<uint8_t>(blocked_, pending_));
            for (uint32_t i = 0; i < pending_; ++i)
                if (!blocked_[i]) sums_[lanes_[i]] += weights_[i];
            pending_ = 0;
            return;
        }
        accel_.intersectBatch(std::span<const Ray>(rays_.data(), pending_), std::span<std::optional<Hit>>(hits_.data(), pending_));
        for (uint32_t i = 0; i < pending_; ++i) {
            if (!hits_[i]) {
                // Escaped: it reaches the environment light (the set's last light), if any.
                if (lights_.environment()) sums_[lanes_[i]] += fromEnvironment(rays_[i].d, weights_[i], pdfs_[i]);
                continue;
            }
            const std::optional<size_t> light = lights_.lightOf(*hits_[i]);
            if (!light) continue;  // no light (emissive or not): light samples never see it either
            if (auto L = emitted(origins_[i], rays_[i].d, *hits_[i], *light, weights_[i], pdfs_[i]))
                sums_[lanes_[i]] += *L;
        }
        pending_ = 0;
    }

private:
    // What a ray from p in direction d adds where it meets light `light` at
    // hit (weight f cos / pdf, brdfPdf its BRDF pdf); nullopt on the side
    // that does not emit.
    std::optional<Rgb> emitted(const Vec3f& p, const Vec3f& d, const Hit& hit, size_t light, const Rgb& weight,
                               float brdfPdf) const {
        const Material& m = scene_.material(hit.material);
        if (!m.isEmissive() || !(dot(d, hit.ng) < 0.f || m.twoSidedEmission)) return std::nullopt;
        float lightPdf = lights_[light].pdf(p, hit);
        if (power_) lightPdf *= lights_.powerProbability(light);
        return weight * Rgb(m.ke) * powerHeuristic(nBrdf_, brdfPdf, nLight_, lightPdf);
    }

    // What an escaped ray in direction d adds (the environment is the set's last light).
    Rgb fromEnvironment(const Vec3f& d, const Rgb& weight, float brdfPdf) const {
        const EnvironmentLight* env = lights_.environment();
        float lightPdf = env->pdf(d);
        if (power_) lightPdf *= lights_.powerProbability(lights_.size() - 1);
        return weight * env->radiance(d) * powerHeuristic(nBrdf_, brdfPdf, nLight_, lightPdf);
    }

    static constexpr uint32_t kPacket = 16;
    const Accelerator& accel_;
    const Scene& scene_;
    const LightSet& lights_;
    bool power_;
    RayCounts& counts_;
    Rgb* sums_;
    float nLight_, nBrdf_;
    bool emittersFirst_;
    ScratchArray<Ray, kPacket> rays_;
    EmptyOptionals<Hit, kPacket> hits_;
    ScratchArray<Vec3f, kPacket> origins_;
    ScratchArray<Rgb, kPacket> weights_;  // emitters first: what an unoccluded ray adds; else f cos / pdf
    float pdfs_[kPacket];
    uint8_t lanes_[kPacket];
    uint8_t blocked_[kPacket];
    uint32_t pending_ = 0;
};

// Light samples drawn together by Light::sampleMany: 64, so that up to 8 x 8
// samples share one spherical rectangle set-up (a set-up costs about as much
// as two samples).
constexpr uint32_t kSampleChunk = 64;

// The fewest BRDF samples per shading point for which LightWindows drops the
// samples that can meet no light: building the windows costs about as much
// as making and testing five samples. room.json (one rectangle light, a
// glossy sphere), 1 thread, rendered without windows in this share of the
// time with them: 0.946 with 1 BRDF sample per point, 0.968 with 2, 0.981
// with 3, 1.00 with 4 to 6, 1.02 with 8 (--spp 16 each) and 1.09 with 32
// (--spp 1). (Measured before the windows lost most of their trigonometric
// calls and were tested as lanes, 20b8c83 and 66739f8: the break-even may
// now lie lower.)
constexpr uint32_t kMinWindowedBrdfSamples = 6;

// Solid angle (sr) from which a light counts as large for a Lambertian point.
constexpr float kLargeLightSolidAngle = 1.f;

constexpr int kLaneWidth = ShadowLanes::kWidth;
static_assert(kLaneWidth == OwenSobol2D::kLanes && kLaneWidth == LightLanes::kWidth);

// The solid angle (sr) from which a light counts as large for a Phong point
// (takesBrdfSamples); out of line, so that the Lambertian points' code (the
// textbook scenes' hot path) stays as it was.
[[gnu::noinline]] float glossyLargeLightSolidAngle(const ShadingPoint& sp) {
    const float pd = phongDiffuseProbability(*sp.material, sp.kd);
    const float piPeak = pd + (1.f - pd) * 0.5f * (sp.material->exponent + 1.f);  // pi times the pdf's peak
    return kLargeLightSolidAngle / piPeak;
}

// Whether each of the first n shading points also takes BRDF samples under
// MIS (into take[l], 1 or 0; returns whether any does): where some light
// that may subtend a large solid angle, for the point's BRDF, may also light
// the point (an environment always does); never when the only lights are
// points and directions, which no ray can hit (the samples would all add
// nothing). sps: the shading points; at: their points and geometric
// normals, as lanes. Decided over the lanes as arrays: one point at a time,
// the decision took 4.6% of textbook_fig18_04.json's render time (where no
// point takes any; measured by skipping it), and this form gave back 3 to 4%
// of it.
//
// Large is measured against the peak of the BRDF's sampling pdf. A light of
// solid angle omega sampled uniformly over it has a pdf near 1/omega; where
// 1/omega exceeds pi times the BRDF pdf's maximum, the power heuristic gives
// the BRDF samples that meet the light at most 1/(1 + pi^2) of the weight
// (9%; as the counts enter squared, under 4.5% from two light samples per
// point on, 2.5% for even counts), so the estimate is the light samples' with or without them, and
// a BRDF sample costs a direction, a test against the emitters and mostly
// nothing found. A Lambertian point's pdf peaks at 1/pi: a large light is one
// of kLargeLightSolidAngle. A Phong point's peaks at pd/pi + (1 - pd)(e+1)/(2 pi)
// (the cosine lobe's peak and the cos^e lobe's, weighed by how often each is
// picked): the sharper its lobe, the smaller the lights for which BRDF samples
// pay. Under a large light the BRDF's variation over it is what is left, and
// BRDF samples remove it. A large light that cannot light the point
// (Light::mayReach: the point behind a one-sided emitter, or the light below
// its horizon) gives its BRDF samples nothing to find: in room.json the
// ceiling around the light took 8 BRDF samples per point that all met the
// light's back, 5% of the render's time. (Phong points took BRDF samples
// whatever the lights before this rule: in penumbra-bench's 10^4-triangle
// sphere frame, under a small square lamp, 123 of them met it, and they took
// 12% of the frame's time. docs/rendering.md has the noise measured.)
[[gnu::always_inline]] inline bool takesBrdfSamples(const ShadingPoint* const* sps, const LanePoints& at, int n,
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
                         const int32_t* want, int m, float nBrdf, const Accelerator& accel, Rgb* added) {
    // Every lane's point, also where it is not needed: one loop, no branches.
    alignas(64) float ux[kLaneWidth], uy[kLaneWidth];
    OwenSobol2D::pointLanes(keys, indices, n, ks, ux, uy);
    LightLanes samples;
    light.sampleLanes(at.points(), ux, uy, want, m, samples);
    return at.trace(samples, m, float(n), nBrdf, accel, added);
}

}  // namespace

PENUMBRA_LANE_CLONES void Integrator::addDirectLight(std::span<PathLane> lanes, std::span<const uint8_t> active,
                                                     int depth, RayCounts& counts) const {
    const size_t nLights = lights_.size();
    if (nLights == 0) return;
    const size_t nLanes = lanes.size();
    // Lanes that need light samples, in lane order.
    uint8_t lit[kMaxBatch];
    size_t nLit = 0;
    for (size_t i = 0; i < nLanes; ++i)
        if (active[i] && lanes[i].sp.reflectsLight()) lit[nLit++] = static_cast<uint8_t>(i);
    if (nLit == 0) return;

    const ShadingPoint* litSps[kMaxBatch];
    for (size_t q = 0; q < nLit; ++q) litSps[q] = &lanes[lit[q]].sp;
    // The lit lanes' points and normals alone, gathered on first use: the MIS
    // decision, the lights' mayReachLanes and the one-sample path's
    // ShadowLanes share them; area and power sampling never ask.
    LanePoints litPointsStore;
    bool litPointsSet = false;
    const auto litPoints = [&]() -> const LanePoints& {
        if (!litPointsSet) {
            for (size_t q = 0; q < nLit; ++q) litPointsStore.set(int(q), litSps[q]->p, litSps[q]->ng);
            litPointsSet = true;
        }
        return litPointsStore;
    };
    const DirectLightSampling mode = settings_.directLight;
    const bool area = mode == DirectLightSampling::Area;
    bool mis[kMaxBatch] = {};
    bool anyMis = false;
    if (mode == DirectLightSampling::Mis) {
        alignas(64) int32_t take[kMaxBatch];
        anyMis = takesBrdfSamples(litSps, litPoints(), int(nLit), lights_, take);
        for (size_t q = 0; q < nLit; ++q) mis[lit[q]] = take[q] != 0;
    }
    const auto sampleLight = [&](const Light& light, const Vec3f& p, Vec2f u) {
        return area ? light.sampleArea(p, u) : light.sample(p, u);
    };

    const uint32_t n = static_cast<uint32_t>(settings_.lightSamples);
    const float invN = 1.f / float(n);
    const uint32_t dimBase = kFirstLightDimension + uint32_t(depth) * uint32_t(nLights + 2);
    ScratchArray<Rgb, kMaxBatch> acc, sum;  // written for the lit lanes only
    for (size_t q = 0; q < nLit; ++q) sum[lit[q]] = Rgb{};
    // BRDF samples under MIS: half as many as light samples (at least one).
    // A BRDF sample costs about twice a light sample (a closest-hit ray, the
    // lobe's sampling and the light's pdf); where the lobe is sharp, half as
    // many still carry the highlight, and the power heuristic weighs each
    // strategy by its count.
    const uint32_t nBrdf = (n + 1) / 2;
    ShadowQueue queue(accel_, counts, acc.data(), float(n), float(nBrdf));

    // Sample k of lane q's n in dimension dim: point index * n + k of the
    // pixel's sequence (dimensionSequence), stratified per shading point and
    // across the pixel's camera samples.
    const bool power = settings_.lightSelection == LightSelection::Power;
    ShadowLanes shadowLanes;  // the lit lanes' shading points, gathered on first use
    bool shadowLanesSet = false;
    if (!power) {
        for (size_t j = 0; j < nLights; ++j) {
            const Light& light = lights_[j];
            const uint32_t dim = dimBase + uint32_t(j);
            for (size_t q = 0; q < nLit; ++q) acc[lit[q]] = Rgb{};
            if (light.isDelta()) {
                for (size_t q = 0; q < nLit; ++q) {
                    const ShadingPoint& sp = lanes[lit[q]].sp;
                    if (auto ls = light.sample(sp.p, Vec2f{0.5f, 0.5f})) queue.add(lit[q], sp, *ls, 1.f, 1.f, false);
                }
                queue.flush();
                for (size_t q = 0; q < nLit; ++q) sum[lit[q]] += acc[lit[q]];
                continue;
            }
            if (n == 1 && !area) {
                // One sample per lane: every step over the lanes as arrays (shading/shadow_lanes.h).
                static_assert(kMaxBatch <= size_t(ShadowLanes::kWidth), "a batch's lanes fit one packet");
                if (!shadowLanesSet) {
                    shadowLanes.setPoints(litPoints());
                    for (size_t q = 0; q < nLit; ++q) shadowLanes.setShading(int(q), *litSps[q], mis[lit[q]]);
                    shadowLanesSet = true;
                }
                alignas(64) int32_t reach[kLaneWidth];
                alignas(64) uint64_t keys[kLaneWidth];
                alignas(64) uint32_t indices[kLaneWidth];
                alignas(64) const uint32_t first[kLaneWidth] = {};
                light.mayReachLanes(litPoints(), int(nLit), reach);
                for (size_t q = 0; q < size_t(kLaneWidth); ++q) {
                    keys[q] = q < nLit ? dimensionKey(lanes[lit[q]].key, dim) : 0;
                    indices[q] = q < nLit ? lanes[lit[q]].key.index : 0;
                }
                ScratchArray<Rgb, kMaxBatch> added;
                counts.shadow += traceLightLanes(light, shadowLanes, keys, indices, 1, first, reach, int(nLit),
                                                 float(nBrdf), accel_, added.data());
                for (size_t q = 0; q < nLit; ++q) sum[lit[q]] += added[q] * invN;
                continue;
            }
            if (!area && n < uint32_t(kLaneWidth)) {
                // 2 to 15 samples per shading point: the lanes of a packet are (shading point,
                // sample) pairs, point by point and each point's samples in order, so that a
                // point's sum takes its samples in sample order whatever the batch holds.
                ShadowLanes pairs;
                alignas(64) uint64_t keys[kLaneWidth] = {};
                alignas(64) uint32_t indices[kLaneWidth] = {}, sampleOf[kLaneWidth] = {};
                alignas(64) int32_t want[kLaneWidth];
                uint8_t owner[kLaneWidth];
                int m = 0;
                const auto tracePairs = [&] {
                    ScratchArray<Rgb, kLaneWidth> added;
                    counts.shadow += traceLightLanes(light, pairs, keys, indices, n, sampleOf, want, m, float(nBrdf),
                                                     accel_, added.data());
                    for (int c = 0; c < m; ++c) acc[owner[c]] += added[c];
                    m = 0;
                };
                // Points whose every sample would be discarded take no lanes.
                alignas(64) int32_t reach[kLaneWidth];
                light.mayReachLanes(litPoints(), int(nLit), reach);
                for (size_t q = 0; q < nLit; ++q) {
                    const PathLane& lane = lanes[lit[q]];
                    if (!reach[q]) continue;
                    const uint64_t key = dimensionKey(lane.key, dim);
                    for (uint32_t k = 0; k < n; ++k) {
                        pairs.setLane(m, lane.sp, mis[lit[q]]);
                        keys[m] = key;
                        indices[m] = lane.key.index;
                        sampleOf[m] = k;
                        want[m] = 1;
                        owner[m] = lit[q];
                        if (++m == kLaneWidth) tracePairs();
                    }
                }
                if (m > 0) tracePairs();
                for (size_t q = 0; q < nLit; ++q) sum[lit[q]] += acc[lit[q]] * invN;
                continue;
            }
            if (!area && n >= uint32_t(ShadowLanes::kWidth)) {
                // A lane's n samples, 16 at a time as the lanes of ShadowLanes, in sample order.
                for (size_t q = 0; q < nLit; ++q) {
                    const PathLane& lane = lanes[lit[q]];
                    if (!light.mayReach(lane.sp.p, lane.sp.ng)) continue;  // every sample would be discarded
                    const OwenSobol2D seq = dimensionSequence(lane.key, dim);
                    // Where nothing can lie between the point and the light, its rays need no query.
                    const bool clear = shadowsClear(j, lane.sp.p, lane.sp.ng);
                    shadowLanes.setAll(lane.sp, mis[lit[q]]);
                    shadowLanesSet = false;  // no longer the lit lanes' points
                    constexpr uint32_t W = uint32_t(ShadowLanes::kWidth);
                    for (uint32_t k0 = 0; k0 < n; k0 += W) {
                        const uint32_t m = std::min(n - k0, W);
                        alignas(64) float ux[W], uy[W];
                        seq.samplePointLanes(lane.key.index, n, k0, ux, uy);
                        LightLanes samples;
                        light.sampleManyLanes(lane.sp.p, ux, uy, int(m), samples);
                        ScratchArray<Rgb, W> added;
                        counts.shadow +=
                            shadowLanes.trace(samples, int(m), float(n), float(nBrdf), accel_, added.data(), clear);
                        for (uint32_t c = 0; c < m; ++c) acc[lit[q]] += added[c];
                    }
                }
                for (size_t q = 0; q < nLit; ++q) sum[lit[q]] += acc[lit[q]] * invN;
                continue;
            }
            for (size_t q = 0; q < nLit; ++q) {
                const PathLane& lane = lanes[lit[q]];
                if (!light.mayReach(lane.sp.p, lane.sp.ng)) continue;  // every sample would be discarded
                const OwenSobol2D seq = dimensionSequence(lane.key, dim);
                if (area) {
                    for (uint32_t k = 0; k < n; ++k)
                        if (auto ls = light.sampleArea(lane.sp.p, seq.point(lane.key.index * n + k)))
                            queue.add(lit[q], lane.sp, *ls, 1.f, ls->pdf, false);
                    continue;
                }
                // In chunks, so that a light's per-shading-point set-up is shared.
                for (uint32_t k0 = 0; k0 < n; k0 += kSampleChunk) {
                    const uint32_t m = std::min(n - k0, kSampleChunk);
                    ScratchArray<Vec2f, kSampleChunk> u;
                    std::optional<LightSample> ls[kSampleChunk];
                    seq.samplePoints(lane.key.index, n, k0, m, u.data());  // without the shuffle where n = 2^k
                    light.sampleMany(lane.sp.p, std::span<const Vec2f>(u.data(), m), std::span(ls, m));
                    for (uint32_t k = 0; k < m; ++k)
                        if (ls[k]) queue.add(lit[q], lane.sp, *ls[k], 1.f, ls[k]->pdf, mis[lit[q]]);
                }
            }
            queue.flush();
            for (size_t q = 0; q < nLit; ++q) sum[lit[q]] += acc[lit[q]] * invN;
        }
    } else {
        // Power-proportional selection: n samples in total, each picks one light.
        const uint32_t dim = dimBase + uint32_t(nLights), pickDim = dim + 0x9e37u;
        for (size_t q = 0; q < nLit; ++q) {
            const PathLane& lane = lanes[lit[q]];
            acc[lit[q]] = Rgb{};
            const OwenSobol2D seq = dimensionSequence(lane.key, dim);
            const OwenSobol2D pickSeq = dimensionSequence(lane.key, pickDim);
            for (uint32_t k = 0; k < n; ++k) {
                const uint32_t index = lane.key.index * n + k;
                const LightSet::Pick pick = lights_.pickByPower(pickSeq.point(index).x);
                if (!(pick.probability > 0.f) || !lights_[pick.index].mayReach(lane.sp.p, lane.sp.ng)) continue;
                if (auto ls = sampleLight(lights_[pick.index], lane.sp.p, seq.point(index)))
                    queue.add(lit[q], lane.sp, *ls, 1.f / pick.probability, ls->pdf * pick.probability, mis[lit[q]]);
            }
        }
        queue.flush();
        for (size_t q = 0; q < nLit; ++q) sum[lit[q]] = acc[lit[q]] * invN;
    }

    // BRDF samples: n per shading point (as many as the light samples of each
    // light), shared by all lights; each lands on at most one.
    if (anyMis) {
        Rgb brdf[kMaxBatch];
        BrdfQueue brdfQueue(accel_, scene_, lights_, power, counts, brdf, float(n), float(nBrdf));
        // Where only the lights' own surfaces count (no environment) and they
        // are few, samples that can meet no light are dropped before their
        // direction is made: they would add nothing and trace no ray. The
        // windows cost, per shading point and light, an asin and an atan2
        // per lobe and two pows for the cos^e lobe, so only where enough
        // samples share them.
        const bool windowed =
            nBrdf >= kMinWindowedBrdfSamples && lights_.emittersTestable() && !lights_.environment();
        const uint32_t dim = dimBase + uint32_t(nLights) + 1;
        for (size_t q = 0; q < nLit; ++q) {
            if (!mis[lit[q]]) continue;
            const PathLane& lane = lanes[lit[q]];
            const ShadingPoint& sp = lane.sp;
            const OwenSobol2D seq = dimensionSequence(lane.key, dim);
            const PhongSampler sampler(*sp.material, sp.kd, sp.ns, sp.wo);
            std::optional<LightWindows> windows;
            if (windowed) windows.emplace(sampler, lights_, sp.p);
            // 16 points at a time as lanes (OwenSobol2D::samplePointLanes), the same points as samplePoints.
            constexpr uint32_t W = uint32_t(OwenSobol2D::kLanes);
            static_assert(int(W) == LightWindows::kLanes);
            for (uint32_t k0 = 0; k0 < nBrdf; k0 += W) {
                const uint32_t m = std::min(nBrdf - k0, W);
                alignas(64) float ux[W], uy[W];
                seq.samplePointLanes(lane.key.index, nBrdf, k0, ux, uy);
                alignas(64) int32_t may[W];
                if (windows) windows->mayReachLanes(ux, uy, may);
                for (uint32_t k = 0; k < m; ++k) {
                    if (windows && !may[k]) continue;
                    if (const std::optional<Vec3f> wi = sampler.direction(Vec2f{ux[k], uy[k]}))
                        brdfQueue.add(lit[q], sp, sampler, *wi);
                }
            }
        }
        brdfQueue.flush();
        for (size_t q = 0; q < nLit; ++q) sum[lit[q]] += brdf[lit[q]] * (1.f / float(nBrdf));
    }
    for (size_t q = 0; q < nLit; ++q) lanes[lit[q]].L += lanes[lit[q]].throughput * sum[lit[q]];
}

PENUMBRA_LANE_CLONES void Integrator::radianceBatch(std::span<const Ray> cameraRays,
                                                    std::span<const std::optional<Hit>> hits,
                                                    std::span<const SampleKey> keys, std::span<Rgb> radiance,
                                                    std::span<FirstHit> firstHits, RayCounts& counts) const {
    const size_t n = std::min(cameraRays.size(), kMaxBatch);
    ScratchArray<PathLane, kMaxBatch> lanes;
    // The lanes' stacks of pending rays, only where a lane can go on (16 vectors
    // made and destroyed for every batch showed in the textbook scene's profile).
    Deferred<std::array<std::vector<PendingRay>, kMaxBatch>> pending;
    if (continues_) pending.emplace();
    uint8_t active[kMaxBatch];
    for (size_t i = 0; i < n; ++i) {
        PathLane& lane = lanes[i];
        lane.ray = cameraRays[i];
        lane.hit = hits[i] ? &*hits[i] : nullptr;
        lane.L = Rgb{};
        lane.throughput = Rgb{1.f};
        lane.pathLength = 0.f;
        lane.key = keys[i];
        lane.depth = 0;
        lane.longest = 0;
        lane.pending = continues_ ? &(*pending.get())[i] : nullptr;
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
                lane.L += lane.throughput * escapedRadiance(scene_, lights_, lane.ray.d);
                active[i] = 0;
                continue;
            }
            const Hit& hit = *lane.hit;
            lane.pathLength += hit.t;
            shade(hit, lane.ray, lane.pathLength, lane.sp);
            const Material& m = *lane.sp.material;
            // Emission is one-sided: only the side the geometric normal faces emits.
            if (m.isEmissive() && (dot(lane.sp.wo, hit.ng) > 0.f || m.twoSidedEmission)) lane.L += lane.throughput * m.ke;
            if (first && !firstHits.empty()) firstHits[i] = FirstHit{lane.sp.kd, lane.sp.ns, hit.t};
            lane.L += lane.throughput * (m.ka * scene_.ambient);
        }
        addDirectLightByDepth(batch, std::span<uint8_t>(active, n), counts);
        if (!continues_) break;  // no lane could go on (continueLane), nor have a pending ray

        // Mirror and transmitted rays of the lanes that continue, traced together.
        ScratchArray<Ray, kMaxBatch> next;  // written before read: not initialised per bounce
        uint8_t nextLane[kMaxBatch];
        size_t nNext = 0;
        for (size_t i = 0; i < n; ++i) {
            PathLane& lane = lanes[i];
            // A lane whose branch ends (miss, diffuse surface, depth limit) takes its next pending ray.
            active[i] = (active[i] && continueLane(lane, counts)) || resumePending(lane);
            if (!active[i]) continue;
            next[nNext] = lane.ray;
            nextLane[nNext++] = static_cast<uint8_t>(i);
        }
        if (nNext == 0) break;
        accel_.intersectBatch(std::span<const Ray>(next.data(), nNext),
                              std::span<std::optional<Hit>>(bounce.data(), nNext));
        for (size_t c = 0; c < nNext; ++c) lanes[nextLane[c]].hit = bounce[c] ? &*bounce[c] : nullptr;
    }
    // The counts summed here and stored once: updated in memory lane by lane,
    // each lane's update waited for the one before it.
    uint64_t lengthSum = 0, nonFinite = 0;
    uint32_t lengthMax = counts.pathLengthMax;
    for (size_t i = 0; i < n; ++i) {
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

void Integrator::addDirectLightByDepth(std::span<PathLane> lanes, std::span<uint8_t> active, RayCounts& counts) const {
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

bool Integrator::continueLane(PathLane& lane, RayCounts& counts) const {
    const Material& m = *lane.sp.material;
    if (lane.depth >= settings_.maxDepth) return false;
    if (m.isDielectric()) {
        // Whitted 1980: the mirror ray and the transmitted ray, weighted by Fresnel. The lane follows
        // the mirror ray and keeps the transmitted one pending (its own stack, depth first), so a
        // lane still traces one ray per step and the batch stays one packet.
        const bool front = dot(lane.sp.wo, lane.hit->ng) > 0.f;
        const float eta = front ? m.ior : 1.f / m.ior;
        const DielectricSplit split = splitDielectric(lane.sp.wo, lane.sp.ns, lane.sp.ng, eta, Rgb(m.kt));
        const Rgb tt = lane.throughput * split.transmittedWeight;
        if (split.transmitted && !tt.isBlack()) {
            lane.pending->push_back(
                PendingRay{spawnRay(lane.sp.p, lane.sp.ng, *split.transmitted), tt, lane.pathLength, lane.depth + 1});
            ++counts.transmission;
        }
        lane.throughput *= split.reflectedWeight;
        if (lane.throughput.isBlack()) return false;
        lane.ray = spawnRay(lane.sp.p, lane.sp.ng, split.reflected);
        ++lane.depth;
        ++counts.reflection;
        return true;
    }
    if (!m.isMirror()) return false;
    // r = d - 2(d.n)n about the shading normal; fall back to the geometric
    // normal when smooth normals would send the ray below the surface.
    Vec3f r = reflect(lane.ray.d, lane.sp.ns);
    if (dot(r, lane.sp.ng) <= 0.f) r = reflect(lane.ray.d, lane.sp.ng);
    lane.throughput *= m.kr;
    if (lane.throughput.isBlack()) return false;
    lane.ray = spawnRay(lane.sp.p, lane.sp.ng, normalize(r));
    ++lane.depth;
    ++counts.reflection;
    return true;
}

bool Integrator::resumePending(PathLane& lane) const {
    if (lane.pending->empty()) return false;
    const PendingRay& p = lane.pending->back();
    lane.ray = p.ray;
    lane.throughput = p.throughput;
    lane.pathLength = p.pathLength;
    lane.depth = p.depth;
    lane.pending->pop_back();
    return true;
}

Rgb Integrator::Li(const Ray& cameraRay, const SampleKey& key, RayCounts& counts, FirstHit* firstHit) const {
    const std::optional<Hit> hit = accel_.intersect(cameraRay);
    Rgb L;
    FirstHit first;
    radianceBatch(std::span<const Ray>(&cameraRay, 1), std::span<const std::optional<Hit>>(&hit, 1),
                  std::span<const SampleKey>(&key, 1), std::span<Rgb>(&L, 1),
                  firstHit ? std::span<FirstHit>(&first, 1) : std::span<FirstHit>(), counts);
    if (firstHit) *firstHit = first;
    return L;
}

}  // namespace penumbra
