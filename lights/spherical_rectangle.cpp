#include "lights/spherical_rectangle.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace penumbra {

// The notation follows the paper: a local frame with the rectangle in the
// plane z = z0 < 0, spanning [x0, x1] x [y0, y1]; scalars in double because
// the solid angle is a small difference of angles near pi.
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
    const auto unit = [](double a, double b, double c) {
        const double l = std::sqrt(a * a + b * b + c * c);
        return std::array<double, 3>{a / l, b / l, c / l};
    };
    const auto n0 = unit(0, z0_, -y0_), n1 = unit(-z0_, 0, x1_), n2 = unit(0, -z0_, y1_), n3 = unit(z0_, 0, -x0_);
    // The interior angles g_i as unit complex numbers (cos g, sin g), g in
    // [0, pi]: their sums and differences then take products, not acos.
    struct Angle {
        double c, s;
    };
    const auto angle = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
        const double c = std::clamp(-(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]), -1.0, 1.0);
        return Angle{c, std::sqrt(std::max(0.0, 1.0 - c * c))};
    };
    const auto times = [](Angle a, Angle b) { return Angle{a.c * b.c - a.s * b.s, a.s * b.c + a.c * b.s}; };
    const Angle g01 = times(angle(n0, n1), angle(n1, n2)), g23 = times(angle(n2, n3), angle(n3, n0));
    b0_ = n0[2];
    b1_ = n2[2];
    // k = 2 pi - g2 - g3: (cos k, sin k) = conj(g2 g3). S = g0 + g1 + g2 + g3 - 2 pi in [0, 2 pi).
    cosK_ = g23.c;
    sinK_ = -g23.s;
    const Angle sum = times(g01, g23);
    S_ = std::atan2(sum.s, sum.c);
    // A rounding error below 0 is a tiny solid angle, not one of almost 2 pi.
    if (S_ < 0) S_ = S_ > -1e-6 ? 0.0 : S_ + 2.0 * 3.14159265358979323846;
    if (!std::isfinite(S_)) S_ = 0;
}

Vec3f SphericalRectangle::sample(Vec2f u) const {
    // x by inverting the solid angle of the part of the rectangle left of x...
    // au = u.x S + k, by the angle-sum formulas from (cos k, sin k).
    const double phi = double(u.x) * S_;
    const double cp = std::cos(phi), sp = std::sin(phi);
    const double cosAu = cp * cosK_ - sp * sinK_, sinAu = sp * cosK_ + cp * sinK_;
    const double fu = std::fabs(sinAu) > 1e-300 ? (cosAu * b0_ - b1_) / sinAu : 1e300;
    double cu = std::copysign(1.0, fu) / std::sqrt(fu * fu + b0_ * b0_);
    cu = std::clamp(cu, -1.0, 1.0);
    const double xu = std::clamp(-(cu * z0_) / std::max(std::sqrt(1.0 - cu * cu), 1e-300), x0_, x1_);
    // ... then y uniformly in the solid angle of the segment at x.
    const double d = std::sqrt(xu * xu + z0_ * z0_);
    const double h0 = y0_ / std::sqrt(d * d + y0_ * y0_), h1 = y1_ / std::sqrt(d * d + y1_ * y1_);
    const double hv = h0 + double(u.y) * (h1 - h0), hv2 = hv * hv;
    const double yv = hv2 < 1.0 - 1e-12 ? hv * d / std::sqrt(1.0 - hv2) : y1_;
    return o_ + float(xu) * x_ + float(std::clamp(yv, y0_, y1_)) * y_ + float(z0_) * z_;
}

}  // namespace penumbra
