// Rays, ray validity, and THE rule for offsetting secondary rays.
#pragma once

#include <bit>
#include <cstdint>
#include <limits>

#include "core/math.h"

namespace penumbra {

/// A ray o + t*d for t in [tnear, tfar]. Directions need not be unit length,
/// but every ray Penumbra spawns has a unit direction so that t is a distance.
struct Ray {
    Vec3f o;
    Vec3f d;
    float tnear = 0.f;
    float tfar = kInfinity;
};

/// The float just below x (std::nextafter(x, -inf) without the libm call):
/// occlusion queries ask for the open interval (tnear, tfar) this way.
inline float nextFloatDown(float x) {
    if (std::isnan(x) || x == -kInfinity) return x;
    if (x == 0.f) return -std::numeric_limits<float>::denorm_min();
    const uint32_t bits = std::bit_cast<uint32_t>(x);
    return std::bit_cast<float>(x > 0.f ? bits - 1u : bits + 1u);
}

/// Embree 3.13.5 (as Debian builds it) asserts on malformed rays and aborts the
/// process. These are the conditions it checks; an invalid ray must be answered
/// as a miss without reaching Embree. Both accelerators apply the same test so
/// they agree on every ray. Written on the ray's components without branches
/// (|x| <= bound is false for NaN and infinities), so that a loop over the
/// lanes of a ray packet vectorises; isValidRay is this on one ray.
inline bool isValidRayComponents(float ox, float oy, float oz, float dx, float dy, float dz, float tnear, float tfar) {
    constexpr float kMaxOrigin = 1.8e18f;
    constexpr float kMaxFloat = std::numeric_limits<float>::max();
    const bool origin = (std::fabs(ox) <= kMaxOrigin) & (std::fabs(oy) <= kMaxOrigin) & (std::fabs(oz) <= kMaxOrigin);
    const bool direction = (std::fabs(dx) <= kMaxFloat) & (std::fabs(dy) <= kMaxFloat) & (std::fabs(dz) <= kMaxFloat);
    const bool interval = (tnear >= 0.f) & (tfar == tfar);  // tnear >= 0 also rejects NaN; tfar may be infinite
    const bool moves = dx * dx + dy * dy + dz * dz != 0.f;  // no direction, nothing to find
    return origin & direction & interval & moves;
}

inline bool isValidRay(const Ray& r) {
    return isValidRayComponents(r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, r.tnear, r.tfar);
}

// ---------------------------------------------------------------------------
// Self-intersection: the one offset rule.
//
// A hit point computed in float carries an error proportional to the magnitude
// of its coordinates (Penumbra computes hit points from the surface's own
// parametrisation, not from o + t*d, so the error does not depend on how far the
// ray travelled). Every secondary ray (shadow, mirror) therefore starts at
//     p + sign * ng * kRayOffsetRelative * max(maxAbsComponent(p), 1)
// where ng is the geometric normal and sign puts the origin on the side the new
// ray leaves towards. The relative factor 2^-16 (~1.5e-5, about 128 float ulps)
// covers triangle interpolation and analytic re-projection errors with a wide
// margin; the floor of 1 scene unit keeps the offset non-zero near the origin.
// At coordinates around 1e4 the offset is ~0.15 units, at around 1 it is 1.5e-5.
// Shadow rays towards a point on a light stop the same distance short of it.
// ---------------------------------------------------------------------------
inline constexpr float kRayOffsetRelative = 1.f / 65536.f;

/// Magnitude of the offset used at point p.
inline float rayOffsetScale(const Vec3f& p) { return kRayOffsetRelative * std::max(maxAbsComponent(p), 1.f); }

/// Origin for a ray leaving a surface at p (geometric normal ng) in direction w.
inline Vec3f offsetRayOrigin(const Vec3f& p, const Vec3f& ng, const Vec3f& w) {
    Vec3f offset = ng * rayOffsetScale(p);
    return dot(w, ng) < 0.f ? p - offset : p + offset;
}

/// Ray leaving the surface at p (geometric normal ng) in unit direction w.
inline Ray spawnRay(const Vec3f& p, const Vec3f& ng, const Vec3f& w) {
    return Ray{offsetRayOrigin(p, ng, w), w, 0.f, kInfinity};
}

/// Shadow ray from the surface at p towards a target point; it stops short of
/// the target by the target's own offset, so the surface the target lies on
/// (for instance the light) never occludes it.
inline Ray spawnRayTo(const Vec3f& p, const Vec3f& ng, const Vec3f& target) {
    Vec3f dir = target - p;
    Vec3f o = offsetRayOrigin(p, ng, dir);
    Vec3f d = target - o;
    float dist = length(d);
    if (!(dist > 0.f)) return Ray{o, Vec3f{0.f, 0.f, 0.f}, 0.f, 0.f};
    float tfar = dist - rayOffsetScale(target);
    return Ray{o, d / dist, 0.f, std::max(tfar, 0.f)};
}

}  // namespace penumbra
