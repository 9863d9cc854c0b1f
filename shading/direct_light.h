// The direct-light estimator: at every shading point of a batch, light
// samples (of every light, or of lights picked in proportion to power) and,
// where they pay, BSDF samples, combined by multiple importance sampling
// (Veach's power heuristic, shading/mis.h). The one place that holds the
// rules of direct light: which strategy samples a light, the shadow-ray
// queue, the MIS weight of a light sample and of a BSDF sample that finds a
// light (an emitter hit or an escape to the environment), and the sample
// dimensions they draw from (shading/sample_key.h). docs/rendering.md
// ("Direct light") states the estimator.
//
// Each strategy is a member of its own: delta lights; one, a few (2 to 15)
// or many (16 and more) light samples per point, the first two over the
// batch's points as the lanes of a packet (shading/shadow_lanes.h), the last
// over one point's samples; points uniform in area (a comparison baseline);
// power-picked lights; BSDF samples, which skip what can meet no light
// (shading/light_windows.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "accel/accelerator.h"
#include "accel/shape_bounds.h"
#include "core/render_settings.h"
#include "core/scene.h"
#include "lights/light_set.h"
#include "shading/ray_counts.h"
#include "shading/sample_key.h"
#include "shading/shading_point.h"

namespace penumbra {

class DirectLight {
public:
    /// Most shading points one estimate() call takes (a batch's lanes).
    static constexpr size_t kMaxPoints = 16;

    DirectLight(const Scene& scene, const Accelerator& accel, const LightSet& lights, const RenderSettings& settings);

    /// The shading points of one call, in lane order.
    struct Points {
        size_t n = 0;
        const ShadingPoint* sp[kMaxPoints];
        SampleKey key[kMaxPoints];
        void add(const ShadingPoint& s, const SampleKey& k) {
            sp[n] = &s;
            key[n] = k;
            ++n;
        }
    };

    /// Writes into direct[q] the direct light leaving points.sp[q] towards
    /// its wo, for points at bounce depth `depth` (their sample dimensions).
    /// Each point's value depends on that point and its key alone.
    void estimate(const Points& points, int depth, Rgb* direct, RayCounts& counts) const;

private:
    struct Call;
    class BsdfQueue;

    /// Whether each point also takes BSDF samples (into call.mis).
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
    DirectLightSampling mode_;
    const LightPicker* picker_;  // null: every light takes every point's samples
    bool sampledLights_ = false;  // some light is no point or directional light
    // Per light, where it is one rectangle or disk: the box its samples lie
    // in (padded), the primitive and its plane.
    struct ClearTarget {
        ShapeBounds::Targets targets;
        PrimRef self;
        Vec3f planePoint, planeNormal;
    };
    std::vector<std::optional<ClearTarget>> clearTargets_;
};

}  // namespace penumbra
