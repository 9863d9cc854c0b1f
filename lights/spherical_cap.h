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

}  // namespace penumbra
