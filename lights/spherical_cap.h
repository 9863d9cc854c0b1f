// Sampling a sphere by the cone of directions it subtends at an outside
// point: uniform in solid angle over exactly the visible cap.
#pragma once

#include <optional>

#include "core/math.h"

namespace penumbra {

struct SphereConeSample {
    Vec3f wi;     // unit direction from o
    Vec3f point;  // on the sphere (its near side)
    Vec3f n;      // outward unit normal at point
    float pdf;    // solid angle, 1 / (2 pi (1 - cos theta_max))
};

/// Solid-angle pdf of cone sampling from o; 0 when o is not outside the sphere.
float sphereConePdf(const Vec3f& o, const Vec3f& center, float radius);

/// Samples the cone the sphere subtends at o with u in [0,1)^2; nullopt when
/// o is not outside the sphere (sample the area then).
std::optional<SphereConeSample> sampleSphereCone(const Vec3f& o, const Vec3f& center, float radius, Vec2f u);

/// Whether a sphere (centre c, squared radius r2) subtends at least `omega`
/// at p (always when p is inside it). Inline and without branches: the
/// integrators ask it at every shading point, for every light, also in loops
/// over a batch's lanes (which then vectorise).
inline bool subtendsAtLeast(const Vec3f& c, float r2, const Vec3f& p, float omega) {
    const float d2 = lengthSquared(c - p);
    // The cap 2 pi (1 - cos theta), sin^2 theta = r^2 / d^2, grows with
    // sin^2 theta (outside the sphere theta < 90 degrees, so the cap is at
    // most 2 pi): compare r^2 with the sin^2 of omega's cap times d^2, no
    // square root or division.
    const float cosOmega = 1.f - omega * kInv2Pi;
    const bool inside = !(d2 > r2);
    return inside | ((cosOmega > 0.f) & (r2 >= (1.f - cosOmega * cosOmega) * d2));
}

}  // namespace penumbra
