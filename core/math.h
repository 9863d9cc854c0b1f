// Plain value types for geometry: 2D/3D float vectors and an orthonormal frame.
// Conventions (used everywhere in Penumbra): right-handed world, y is up in the
// assets we write, directions wo/wi point away from the surface.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <penumbra/types.hpp>

namespace penumbra {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;
inline constexpr float kInv2Pi = 0.15915494309189533577f;
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

struct Vec2f {
    float x = 0.f, y = 0.f;
};

struct Vec3f {
    float x = 0.f, y = 0.f, z = 0.f;

    constexpr Vec3f() = default;
    constexpr Vec3f(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
    constexpr explicit Vec3f(float s) : x(s), y(s), z(s) {}
    // The API's plain vector (in pnb::Camera, ...) converts both ways, so the
    // values defined once in types.hpp are used inside with this arithmetic.
    constexpr Vec3f(const pnb::Vec3& v) : x(v.x), y(v.y), z(v.z) {}
    constexpr operator pnb::Vec3() const { return {x, y, z}; }

    constexpr float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }

    constexpr Vec3f operator-() const { return {-x, -y, -z}; }
    constexpr Vec3f& operator+=(const Vec3f& o) { x += o.x; y += o.y; z += o.z; return *this; }
    constexpr Vec3f& operator-=(const Vec3f& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
    constexpr Vec3f& operator*=(float s) { x *= s; y *= s; z *= s; return *this; }
    constexpr bool operator==(const Vec3f& o) const = default;
};

constexpr Vec3f operator+(const Vec3f& a, const Vec3f& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr Vec3f operator-(const Vec3f& a, const Vec3f& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr Vec3f operator*(const Vec3f& a, float s) { return {a.x * s, a.y * s, a.z * s}; }
constexpr Vec3f operator*(float s, const Vec3f& a) { return {a.x * s, a.y * s, a.z * s}; }
/// Division by a scalar multiplies by its reciprocal: one division instead of three.
constexpr Vec3f operator/(const Vec3f& a, float s) {
    const float inv = 1.f / s;
    return {a.x * inv, a.y * inv, a.z * inv};
}
/// Component-wise product (used for scaling by per-axis factors).
constexpr Vec3f mul(const Vec3f& a, const Vec3f& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }

constexpr float dot(const Vec3f& a, const Vec3f& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3f cross(const Vec3f& a, const Vec3f& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr float lengthSquared(const Vec3f& a) { return dot(a, a); }
inline float length(const Vec3f& a) { return std::sqrt(dot(a, a)); }
/// Unit vector in the direction of a; the zero vector stays zero (never NaN).
/// The choice is made per component: a select of whole vectors kept GCC from
/// vectorising loops over lanes that normalise (completeTriangleHitLanes).
inline Vec3f normalize(const Vec3f& a) {
    const float l = length(a), inv = 1.f / l;
    const bool some = l > 0.f;
    return {some ? a.x * inv : 0.f, some ? a.y * inv : 0.f, some ? a.z * inv : 0.f};
}
inline Vec3f min(const Vec3f& a, const Vec3f& b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
inline Vec3f max(const Vec3f& a, const Vec3f& b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
inline Vec3f abs(const Vec3f& a) { return {std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}; }
inline float maxComponent(const Vec3f& a) { return std::max(a.x, std::max(a.y, a.z)); }
inline float maxAbsComponent(const Vec3f& a) { return maxComponent(abs(a)); }
inline int maxDimension(const Vec3f& a) { return (a.x > a.y) ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2); }
inline bool isFinite(const Vec3f& a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

/// Mirror reflection of an incoming direction d about the normal n: r = d - 2(d.n)n.
constexpr Vec3f reflect(const Vec3f& d, const Vec3f& n) { return d - 2.f * dot(d, n) * n; }

/// Orthonormal frame around a unit normal (Duff et al. 2017, branchless, no NaN at the poles).
struct Frame {
    Vec3f s, t, n;

    static Frame fromNormal(const Vec3f& n) {
        float sign = std::copysign(1.f, n.z);
        float a = -1.f / (sign + n.z);
        float b = n.x * n.y * a;
        return {Vec3f{1.f + sign * n.x * n.x * a, sign * b, -sign * n.x}, Vec3f{b, sign + n.y * n.y * a, -n.y}, n};
    }
    Vec3f toLocal(const Vec3f& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3f toWorld(const Vec3f& v) const { return s * v.x + t * v.y + n * v.z; }
};

/// Axis-aligned bounding box; empty when lo > hi.
struct Bounds3f {
    Vec3f lo{kInfinity, kInfinity, kInfinity};
    Vec3f hi{-kInfinity, -kInfinity, -kInfinity};

    void extend(const Vec3f& p) { lo = min(lo, p); hi = max(hi, p); }
    void extend(const Bounds3f& b) { lo = min(lo, b.lo); hi = max(hi, b.hi); }
    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    Vec3f center() const { return (lo + hi) * 0.5f; }
    Vec3f diagonal() const { return hi - lo; }
};

}  // namespace penumbra
