// Light interface. Area lights are built from the scene's emissive shapes, so
// emitters are also ordinary geometry that camera and mirror rays see.
#pragma once

#include <cstdint>
#include <optional>
#include <span>

#include "core/color.h"
#include "core/hit.h"
#include "core/math.h"
#include "lights/light_bounds.h"

namespace penumbra {

struct LanePoints;  // lights/light_lanes.h

/// The mean of a colour's channels, in double precision (Light::power).
inline double channelMean(const Rgb& c) { return (double(c.r) + double(c.g) + double(c.b)) / 3.0; }
struct LightLanes;

/// One light sample as seen from a shading point.
struct LightSample {
    Rgb L;             // radiance arriving along -wi (area) or I/d^2 / E (delta lights)
    Vec3f wi;          // unit direction from the shading point towards the light
    Vec3f point;       // sampled point on the light (unused for directional lights)
    float distance;    // to `point`; infinity for directional lights
    float pdf;         // solid-angle pdf for area lights; 1 for delta lights
    bool delta;        // point / directional: no pdf, no area
};

class Light {
public:
    virtual ~Light() = default;
    /// Samples the light from shading point p with u in [0,1)^2. nullopt when
    /// the sample carries nothing (back side of a one-sided emitter, zero pdf).
    virtual std::optional<LightSample> sample(const Vec3f& p, Vec2f u) const = 0;
    /// Solid-angle pdf with which sample(p, u) produces the direction from p
    /// to onLight, the point where a ray from p first meets this light (e.g. a
    /// BRDF-sampled ray's hit; its ng, ref.prim and p are used). 0 for delta
    /// lights and where the light sends nothing towards p (the back of a
    /// one-sided emitter), i.e. exactly where sample() cannot return it.
    virtual float pdf(const Vec3f& p, const Hit& onLight) const = 0;
    /// out[k] = sample(p, u[k]) for every k (u and out of one size). Lights
    /// whose sampling has a set-up per shading point (spherical rectangles)
    /// do it once for all of p's samples.
    virtual void sampleMany(const Vec3f& p, std::span<const Vec2f> u, std::span<std::optional<LightSample>> out) const {
        for (size_t k = 0; k < u.size(); ++k) out[k] = sample(p, u[k]);
    }
    /// reach[l] = mayReach(at.p(l), at.n(l)) for the first n lanes, 1 or 0.
    /// Defined in lights/light_lanes.cpp, as is sampleLanes.
    virtual void mayReachLanes(const LanePoints& at, int n, int32_t* reach) const;
    /// One sample at each of the first n lanes' points where want[l] is set:
    /// out.set(l, sample(at.p(l), {ux[l], uy[l]})), the same values; where
    /// want[l] is 0, out.ok[l] = 0; out.delta = isDelta(). Lights whose sample
    /// is a short chain of square roots and divisions take it as loops over
    /// the lanes. out must not overlap at, ux, uy or want.
    virtual void sampleLanes(const LanePoints& at, const float* ux, const float* uy, const int32_t* want, int n,
                             LightLanes& out) const;
    /// sampleMany as lanes: out.set(l, sample(p, {ux[l], uy[l]})) for l < n
    /// (at most LightLanes::kWidth), with sampleMany's shared set-up (the
    /// default calls sampleMany). Not for delta lights.
    virtual void sampleManyLanes(const Vec3f& p, const float* ux, const float* uy, int n, LightLanes& out) const;
    /// The estimator before solid-angle sampling: points uniform in area
    /// (InternalSettings::areaLightSamples, for comparisons). Same as sample() unless overridden.
    virtual std::optional<LightSample> sampleArea(const Vec3f& p, Vec2f u) const { return sample(p, u); }
    /// False only where no sample from p can count: where every point of the
    /// light lies on or below the plane through p with normal n (the
    /// integrators discard samples with wi . n <= 0) or where the light sends
    /// nothing towards p. A cheap bound, taken before sampling, so that
    /// shading points facing away from a light do not pay for its samples;
    /// true where a light cannot tell.
    virtual bool mayReach(const Vec3f& p, const Vec3f& n) const {
        (void)p;
        (void)n;
        return true;
    }
    /// Total emitted power, the mean of its colour channels, for
    /// power-proportional light selection. In double precision: a light of
    /// finite radiance can emit more than the largest float (two spheres of
    /// radiance 3e38 would make the float total infinite, and every
    /// probability inf / inf).
    virtual double power() const = 0;
    /// Where the light sends light (for the light hierarchy): a box holding
    /// it and a cone holding its emission directions; nullopt for lights at
    /// infinity (directional lights, the environment).
    virtual std::optional<LightBounds> bounds() const { return std::nullopt; }
    virtual bool isDelta() const { return false; }
};

}  // namespace penumbra
