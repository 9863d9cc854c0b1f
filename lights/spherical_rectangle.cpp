#include "lights/spherical_rectangle.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

// The notation follows the paper: a local frame with the rectangle in the
// plane z = z0 < 0, spanning [x0, x1] x [y0, y1]. Single precision
// throughout: the interior angles are kept as unit complex numbers
// (cos g, sin g), with sin g from a cross product rather than
// sqrt(1 - cos^2 g), so their sum S = g0 + g1 + g2 + g3 - 2 pi is a product
// and one atan2, not a difference of large angles.
SphericalRectangle::SphericalRectangle(const Vec3f& o, const Vec3f& s, const Vec3f& ex, const Vec3f& ey) : o_(o) {
    const float exl = length(ex), eyl = length(ey);
    x_ = ex / exl;
    y_ = ey / eyl;
    z_ = cross(x_, y_);
    const Vec3f d = s - o;
    z0_ = dot(d, z_);
    if (z0_ > 0) {
        z_ = -z_;
        z0_ = -z0_;
    }
    x0_ = dot(d, x_);
    y0_ = dot(d, y_);
    x1_ = x0_ + exl;
    y1_ = y0_ + eyl;
    if (!(z0_ < 0) || !(exl > 0.f) || !(eyl > 0.f)) return;  // in the plane: S = 0
    // Unit normals of the four planes through o and an edge.
    const Vec3f n0 = normalize(Vec3f{0, z0_, -y0_}), n1 = normalize(Vec3f{-z0_, 0, x1_});
    const Vec3f n2 = normalize(Vec3f{0, -z0_, y1_}), n3 = normalize(Vec3f{z0_, 0, -x0_});
    struct Angle {
        float c, s;
    };
    // The angle between two consecutive planes: pi minus the angle of their normals.
    const auto angle = [](const Vec3f& a, const Vec3f& b) { return Angle{-dot(a, b), length(cross(a, b))}; };
    const auto times = [](Angle a, Angle b) { return Angle{a.c * b.c - a.s * b.s, a.s * b.c + a.c * b.s}; };
    const Angle g01 = times(angle(n0, n1), angle(n1, n2)), g23 = times(angle(n2, n3), angle(n3, n0));
    b0_ = n0.z;
    b1_ = n2.z;
    // k = 2 pi - g2 - g3: (cos k, sin k) = conj(g2 g3). S = g0 + g1 + g2 + g3 - 2 pi in [0, 2 pi).
    cosK_ = g23.c;
    sinK_ = -g23.s;
    const Angle sum = times(g01, g23);
    S_ = std::atan2(sum.s, sum.c);
    // A rounding error below 0 is a tiny solid angle, not one of almost 2 pi.
    if (S_ < 0) S_ = S_ > -1e-5f ? 0.f : S_ + 2.f * kPi;
    if (!std::isfinite(S_)) S_ = 0;
}

Vec3f SphericalRectangle::sample(Vec2f u) const {
    // x by inverting the solid angle of the part of the rectangle left of x...
    // au = u.x S + k, by the angle-sum formulas from (cos k, sin k).
    const float phi = u.x * S_;
    const float cp = std::cos(phi), sp = std::sin(phi);
    const float cosAu = cp * cosK_ - sp * sinK_, sinAu = sp * cosK_ + cp * sinK_;
    const float fu = std::fabs(sinAu) > 1e-30f ? (cosAu * b0_ - b1_) / sinAu : 1e30f;
    const float cu = std::clamp(std::copysign(1.f, fu) / std::sqrt(fu * fu + b0_ * b0_), -1.f, 1.f);
    const float xu = std::clamp(-(cu * z0_) / std::max(std::sqrt(std::max(0.f, 1.f - cu * cu)), 1e-30f), x0_, x1_);
    // ... then y uniformly in the solid angle of the segment at x.
    const float d2 = xu * xu + z0_ * z0_;
    const float h0 = y0_ / std::sqrt(d2 + y0_ * y0_), h1 = y1_ / std::sqrt(d2 + y1_ * y1_);
    const float hv = h0 + u.y * (h1 - h0), hv2 = hv * hv;
    const float yv = hv2 < 1.f - 1e-6f ? hv * std::sqrt(d2 / (1.f - hv2)) : y1_;
    return o_ + xu * x_ + std::clamp(yv, y0_, y1_) * y_ + z0_ * z_;
}

}  // namespace penumbra
