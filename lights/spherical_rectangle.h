// Spherical rectangle sampling (Urena, Fajardo & King 2013): directions
// uniform in the solid angle a rectangle subtends at a point.
#pragma once

#include "core/math.h"

namespace penumbra {

/// A rectangle (corner s, orthogonal edges ex and ey) as seen from o: set up
/// once per shading point, then sampled with any number of u.
class SphericalRectangle {
public:
    SphericalRectangle(const Vec3f& o, const Vec3f& s, const Vec3f& ex, const Vec3f& ey);
    /// Subtended solid angle; 0 when o lies in the rectangle's plane.
    float solidAngle() const { return S_; }
    /// The point of the rectangle in the direction sampled by u in [0,1)^2
    /// (uniform in solid angle, pdf 1 / solidAngle()).
    Vec3f sample(Vec2f u) const;

private:
    Vec3f o_, x_, y_, z_;
    float z0_ = 0, x0_ = 0, y0_ = 0, x1_ = 0, y1_ = 0;
    float b0_ = 0, b1_ = 0, cosK_ = 1, sinK_ = 0, S_ = 0;
};

}  // namespace penumbra
