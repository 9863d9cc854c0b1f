// The direct-light estimator of both integrators: at every shading point of
// a batch, light samples (of every light, or of lights a LightPicker picks)
// weighed by multiple importance sampling (Veach's power heuristic,
// shading/mis.h) against BSDF samples: its own, where they pay (the Whitted
// integrator), or the one the caller draws to continue a path. The one place
// that holds the rules of direct light: which strategy samples a light, the
// shadow-ray queue, the MIS weight of a light sample and of a BSDF sample
// that finds a light (an emitter hit or an escape to the environment), and
// the dimensions they draw from (VertexDimensions, shading/sample_key.h).
// docs/rendering.md ("Direct light") states the estimator.
//
// Each strategy is a member of its own: delta lights; one, a few (2 to 15)
// or many (16 and more) light samples per point, the first two over the
// batch's points as the lanes of a packet (shading/shadow_lanes.h), the last
// over one point's samples; points uniform in area (a comparison baseline);
// picked lights; BSDF samples, which skip what can meet no light
// (shading/light_windows.h). The lane-wise strategies take the Lambertian
// response from arrays and every other response through shading/bsdf/bsdf.h.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "accel/accelerator.h"
#include "accel/shape_bounds.h"
#include "core/render_settings.h"
#include "core/scene.h"
#include "core/scratch_array.h"
#include "lights/light_picker.h"
#include "lights/light_set.h"
#include "shading/ray_counts.h"
#include "shading/sample_key.h"
#include "shading/shading_point.h"

namespace penumbra {

class DirectLight {
public:
    /// Most shading points one estimate() call takes (a batch's lanes).
    static constexpr size_t kMaxPoints = 16;

    /// What the light samples' MIS weights are taken against.
    enum class BsdfSamples {
        None,    ///< nothing: light samples only (weight 1)
        Own,     ///< BSDF samples the estimator draws itself, at the points where they pay
        Caller,  ///< the one BSDF sample per point that the caller draws (a path's next bounce)
    };
    struct Options {
        int lightSamples = 1;  ///< per light and point; in all per point where lights are picked
        LightSelection selection = LightSelection::All;  ///< resolved (resolvedLightSelection): not Auto
        BsdfSamples bsdf = BsdfSamples::Own;
        bool areaSamples = false;  ///< light samples uniform in area, without MIS: the comparison baseline
    };

    DirectLight(const Scene& scene, const Accelerator& accel, const LightSet& lights, const Options& options);

    /// The shading points of one call, in lane order.
    struct Points {
        size_t n = 0;
        const ShadingPoint* sp[kMaxPoints];
        SampleKey key[kMaxPoints];
        // BsdfSamples::Caller: how MIS counts the caller's one BSDF sample at
        // the point, the probability that it samples the smooth lobes (whose
        // pdf bsdfEvaluate gives); 0 where it never does.
        float bsdfCount[kMaxPoints];
    };

    /// Writes into direct[q] the direct light leaving points.sp[q] towards
    /// its wo, for points at bounce depth `depth` (their sample dimensions).
    /// Each point's value depends on that point and its key alone.
    void estimate(const Points& points, int depth, Rgb* direct, RayCounts& counts) const;

    /// Whether a lane takes light samples, and its Points::bsdfCount.
    struct LitLane {
        bool lit;
        float bsdfCount;
    };
    /// Adds to the radiance L of each lane whose shading point `sp` (drawing
    /// with SampleKey `key`) is lit its throughput times the direct light
    /// there: lit(i) says for lane i (a LitLane).
    template <class Lane, class Lit>
    void addTo(std::span<Lane> lanes, Lit lit, int depth, RayCounts& counts) const;

    /// The MIS weight of emission at `hit` that the caller's BSDF sample (one
    /// of nBsdf samples of pdf bsdfPdf, drawn at p with geometric normal n)
    /// found; 1 where no light sample can find it (no light of the set).
    float emitterHitWeight(const Hit& hit, float nBsdf, float bsdfPdf, const Vec3f& p, const Vec3f& n) const;
    /// What such a sample that left the scene along dir sees (escapedRadiance)
    /// and its MIS weight, where the environment light (the set's last light)
    /// takes it: the radiance and the pdf from one lookup.
    struct Escape {
        Rgb L;
        float weight;
    };
    Escape escape(const Vec3f& dir, float nBsdf, float bsdfPdf, const Vec3f& p, const Vec3f& n) const;
    /// Radiance a ray leaving the scene along dir sees: the environment
    /// light's, else Scene::background. The one rule for escaped rays.
    Rgb escapedRadiance(const Vec3f& dir) const;

private:
    struct Call;
    class BsdfQueue;

    /// Each point's MIS count and whether the estimator draws BSDF samples.
    void decideBsdfSamples(Call& call) const;
    /// The strategies: each adds light j's estimate (or all lights', for
    /// picked lights) to the call's sums.
    void sampleLight(size_t j, Call& call) const;
    void sampleDeltaLight(const Light& light, Call& call) const;
    void sampleOnePerPoint(size_t j, Call& call) const;
    void samplePairs(size_t j, Call& call) const;
    void sampleManyPerPoint(size_t j, Call& call) const;
    void sampleByArea(size_t j, Call& call) const;
    void samplePickedLights(Call& call) const;
    void sampleBsdf(Call& call) const;
    template <class SampleAt>
    void queueSamples(Call& call, float scale, SampleAt sampleAt) const;

    /// The MIS weight of emission that one of nBsdf BSDF samples of pdf
    /// bsdfPdf, drawn at p (geometric normal n), finds on light j, whose own
    /// sampling pdf for that direction is lightPdf (solid angle, before the
    /// light's selection probability).
    float bsdfSampleWeight(size_t j, float lightPdf, float nBsdf, float bsdfPdf, const Vec3f& p, const Vec3f& n) const;

    // Whether every shadow ray from the surface at p (geometric normal ng) to
    // area light j certainly meets nothing (ShapeBounds::segmentsClear):
    // then its samples there need no query.
    bool shadowsClear(size_t j, const Vec3f& p, const Vec3f& ng) const;
    void findClearTargets(const Scene& scene);

    const Scene& scene_;
    const Accelerator& accel_;
    const LightSet& lights_;
    uint32_t lightSamples_;
    BsdfSamples bsdf_;
    bool areaSamples_;
    const LightPicker* picker_;   // null: every light takes every point's samples
    bool sampledLights_ = false;  // some light is no point or directional light
    bool deltaLights_ = false;    // some light is a point or directional light
    // A constant environment is left to the BSDF samples wherever they weigh
    // against the light samples: for a constant radiance the BSDF's own
    // distribution follows the integrand up to visibility, and a light sample
    // (uniform over the sphere, half of it below the surface) only adds noise
    // and a shadow ray. Escaped BSDF samples then carry it in full (weight 1).
    bool environmentByBsdf_ = false;
    // An image environment is sampled by its compensated map
    // (EnvironmentLight::misSampled) where its light samples weigh against
    // BSDF samples, which then find the image's darker parts alone: at every
    // point when there are BSDF samples (the path integrator bounces from every
    // point it samples lights at; the estimator's own BSDF samples are taken
    // at every point an environment lights).
    bool environmentCompensated_ = false;
    /// The light to draw light j's samples from: lights_[j], or such an
    /// environment's misSampled().
    const Light& sampledLight(size_t j) const;
    /// Whether light j takes light samples (all but such an environment, the set's last light).
    bool takesLightSamples(size_t j) const { return !(environmentByBsdf_ && j + 1 == lights_.size()); }
    // Per light, where it is one rectangle or disk: the box its samples lie
    // in (padded), the primitive and its plane.
    struct ClearTarget {
        ShapeBounds::Targets targets;
        PrimRef self;
        Vec3f planePoint, planeNormal;
    };
    std::vector<std::optional<ClearTarget>> clearTargets_;
};

// Inline, so that it compiles into its caller's lane clones (core/lane_clones.h).
template <class Lane, class Lit>
[[gnu::always_inline]] inline void DirectLight::addTo(std::span<Lane> lanes, Lit lit, int depth,
                                                      RayCounts& counts) const {
    Points points;
    uint8_t lane[kMaxPoints];
    size_t n = 0;  // counted here, not in points.n, which the stores into points could alias
    // Every lane written, and kept by counting it: whether a lane is lit
    // follows the materials, which a branch on it mispredicted.
    for (size_t i = 0; i < lanes.size(); ++i) {
        const LitLane l = lit(i);
        lane[n] = static_cast<uint8_t>(i);
        points.sp[n] = &lanes[i].sp;
        points.key[n] = lanes[i].key;
        points.bsdfCount[n] = l.bsdfCount;
        n += l.lit ? 1 : 0;
    }
    if (n == 0) return;
    points.n = n;
    ScratchArray<Rgb, kMaxPoints> direct;
    estimate(points, depth, direct.data(), counts);
    for (size_t q = 0; q < n; ++q) lanes[lane[q]].L += lanes[lane[q]].throughput * direct[q];
}

}  // namespace penumbra
