// Direct light over the 16 lanes of a packet, as arrays. A lane is one light
// sample: at each of a batch's shading points (gathered once; the light's
// samples from Light::sampleLanes), or one of a single shading point's samples,
// 16 at a time (Light::sampleManyLanes). The samples' BRDF weights and shadow
// rays are written by loops over the lanes straight into the packet
// (RayLanes), and the weights of the unoccluded ones are handed back per lane.
// Where a lane's weight needs more than a Lambertian response and its MIS
// weight (a glossy lobe, pow), that lane takes shadowSampleWeight, the rule
// every shadow ray's weight follows.
#pragma once

#include <cstdint>

#include "accel/accelerator.h"
#include "core/color.h"
#include "core/ray_lanes.h"
#include "lights/light_lanes.h"
#include "shading/bsdf/bsdf.h"
#include "shading/mis.h"
#include "shading/shading_point.h"

namespace penumbra {

/// The weight f * L * scale / pdf that light sample ls adds at sp if its
/// shadow ray is unoccluded; false where it adds nothing (below the geometric
/// surface, or a black response). lightPdf: the light-sampling pdf of the
/// sample's direction (solid angle pdf times the light's selection
/// probability). misCount > 0: the sample is weighed by the power heuristic,
/// as one of nLight light samples, against misCount BSDF samples of the pdf
/// bsdfEvaluate gives (a fraction where a bounce picks the smooth lobes with
/// that probability); 0: no BSDF sample can find the light (weight 1).
inline bool shadowSampleWeight(const ShadingPoint& sp, const LightSample& ls, float scale, float lightPdf,
                               float misCount, float nLight, Rgb& weight) {
    if (dot(ls.wi, sp.ng) <= 0.f) return false;  // below the geometric surface
    Rgb f;
    if (misCount > 0.f && !ls.delta) {
        const BsdfSample e = bsdfEvaluate(sp, ls.wi);
        f = e.fCos;
        scale *= powerHeuristic(nLight, lightPdf, misCount, e.pdf);
    } else {
        f = bsdfResponse(sp, ls.wi, ls.delta);
    }
    if (f.isBlack()) return false;
    weight = f * ls.L * (scale / ls.pdf);
    return true;
}

class ShadowLanes {
public:
    static constexpr int kWidth = RayLanes::kWidth;

    /// Lane c's shading point; misCount as in shadowSampleWeight. The point
    /// must outlive the lanes (lanes that need the scalar rule read it).
    void setLane(int c, const ShadingPoint& sp, float misCount) {
        points_.set(c, sp.p, sp.ng);
        setShading(c, sp, misCount);
    }
    /// The lanes' points and normals at once, where the caller has them as
    /// lanes already: then setShading sets the rest of each lane.
    void setPoints(const LanePoints& points) { points_ = points; }
    /// setLane but for the point and normal.
    void setShading(int c, const ShadingPoint& sp, float misCount);
    /// Every lane at one shading point (its samples are then the lanes).
    void setAll(const ShadingPoint& sp, float misCount) {
        for (int c = 0; c < kWidth; ++c) setLane(c, sp, misCount);
    }
    /// The lanes' points and geometric normals, for Light::mayReachLanes and sampleLanes.
    const LanePoints& points() const { return points_; }

    /// Traces the samples of the first n lanes (those with samples.ok[c]) as
    /// one packet and writes into added[c] the weight (scale 1, light pdf =
    /// the sample's pdf; a delta light's samples, samples.delta, as
    /// shadowSampleWeight weighs them) of each unoccluded one, Rgb{} for the others.
    /// Returns how many shadow rays it answered. clear: the caller knows that
    /// nothing lies between the lanes' points and their samples
    /// (DirectLight::shadowsClear): the rays are neither made nor traced, and
    /// every one is unoccluded, as a query would have found.
    uint32_t trace(const LightLanes& samples, int n, float nLight, const Accelerator& accel, Rgb* added,
                   bool clear = false) const;

private:
    LanePoints points_;  // p and ng
    alignas(64) float nsx_[kWidth], nsy_[kWidth], nsz_[kWidth];
    alignas(64) float kdr_[kWidth], kdg_[kWidth], kdb_[kWidth];
    alignas(64) int32_t scalar_[kWidth];  // 1: glossy, weighed by shadowSampleWeight
    alignas(64) float misCount_[kWidth];
    const ShadingPoint* sp_[kWidth];
};

[[gnu::always_inline]] inline void ShadowLanes::setShading(int c, const ShadingPoint& sp, float misCount) {
    nsx_[c] = sp.ns.x;
    nsy_[c] = sp.ns.y;
    nsz_[c] = sp.ns.z;
    kdr_[c] = sp.kd.r;
    kdg_[c] = sp.kd.g;
    kdb_[c] = sp.kd.b;
    // Only the Lambertian lanes' weights come from the arrays (the others'
    // from shadowSampleWeight), so no specular term is gathered.
    scalar_[c] = sp.glossy;
    sp_[c] = &sp;
    misCount_[c] = misCount;
}

}  // namespace penumbra
