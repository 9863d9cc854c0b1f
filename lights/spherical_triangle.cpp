#include "lights/spherical_triangle.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

// Double precision: the spherical excess is a small difference of angles.
struct D3 {
    double x, y, z;
};
D3 d3(const Vec3f& v) { return {v.x, v.y, v.z}; }
D3 operator-(const D3& a, const D3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator+(const D3& a, const D3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator*(double s, const D3& a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(const D3& a, const D3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
D3 unit(const D3& a) {
    const double l = std::sqrt(dot(a, a));
    return l > 0 ? (1.0 / l) * a : D3{0, 0, 0};
}
double angleBetween(const D3& a, const D3& b) { return std::acos(std::clamp(dot(a, b), -1.0, 1.0)); }
// The part of a orthogonal to the unit vector b, normalised.
D3 orthogonalPart(const D3& a, const D3& b) { return unit(a - dot(a, b) * b); }

double solidAngle(const D3& A, const D3& B, const D3& C) {
    const double triple = std::fabs(dot(A, cross(B, C)));
    return 2.0 * std::atan2(triple, 1.0 + dot(A, B) + dot(B, C) + dot(C, A));
}

}  // namespace

float triangleSolidAngle(const Vec3f& o, const Vec3f& p0, const Vec3f& p1, const Vec3f& p2) {
    const D3 O = d3(o);
    return float(solidAngle(unit(d3(p0) - O), unit(d3(p1) - O), unit(d3(p2) - O)));
}

std::optional<SphericalTriangleSample> sampleSphericalTriangle(const Vec3f& o, const Vec3f& p0, const Vec3f& p1,
                                                               const Vec3f& p2, Vec2f u) {
    const D3 O = d3(o), P0 = d3(p0);
    const D3 A = unit(P0 - O), B = unit(d3(p1) - O), C = unit(d3(p2) - O);
    const double area = solidAngle(A, B, C);
    if (!(area > 0)) return std::nullopt;
    // Interior angle at A and the arc length c = |AB|.
    const D3 nAB = unit(cross(A, B)), nCA = unit(cross(C, A));
    const double alpha = angleBetween(nAB, -1.0 * nCA);
    const double cosC = dot(A, B);
    // Arvo's construction: the sub-triangle A B C' of area u.x * area fixes C'
    // on the arc AC; then the direction is placed on the arc B C' so that the
    // solid angle is uniform.
    const double areaHat = double(u.x) * area;
    const double s = std::sin(areaHat - alpha), t = std::cos(areaHat - alpha);
    const double cosA = std::cos(alpha), sinA = std::sin(alpha);
    const double uu = t - cosA, v = s + sinA * cosC;
    const double den = (v * s + uu * t) * sinA;
    const double q = den != 0 ? std::clamp(((v * t - uu * s) * cosA - v) / den, -1.0, 1.0) : 1.0;
    const D3 Chat = q * A + std::sqrt(std::max(0.0, 1.0 - q * q)) * orthogonalPart(C, A);
    const double z = 1.0 - double(u.y) * (1.0 - dot(Chat, B));
    const D3 w = unit(z * B + std::sqrt(std::max(0.0, 1.0 - z * z)) * orthogonalPart(Chat, B));
    // Where w meets the triangle's plane.
    const D3 n = cross(d3(p1) - P0, d3(p2) - P0);
    const double dn = dot(w, n);
    if (dn == 0) return std::nullopt;
    const double dist = dot(P0 - O, n) / dn;
    if (!(dist > 0)) return std::nullopt;
    const D3 p = O + dist * w;
    return SphericalTriangleSample{Vec3f{float(w.x), float(w.y), float(w.z)}, Vec3f{float(p.x), float(p.y), float(p.z)},
                                   float(area)};
}

}  // namespace penumbra
