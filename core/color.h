// Linear RGB radiance / reflectance triple.
#pragma once

#include <algorithm>
#include <cmath>

#include <penumbra/types.hpp>

namespace penumbra {

struct Rgb {
    float r = 0.f, g = 0.f, b = 0.f;

    constexpr Rgb() = default;
    constexpr Rgb(float r_, float g_, float b_) : r(r_), g(g_), b(b_) {}
    constexpr explicit Rgb(float s) : r(s), g(s), b(s) {}
    // The API's plain colour (in pnb::Material, ...) converts both ways, so the
    // values defined once in types.hpp are used inside with this arithmetic.
    constexpr Rgb(const pnb::Color& c) : r(c.r), g(c.g), b(c.b) {}
    constexpr operator pnb::Color() const { return {r, g, b}; }

    constexpr Rgb& operator+=(const Rgb& o) { r += o.r; g += o.g; b += o.b; return *this; }
    constexpr Rgb& operator*=(const Rgb& o) { r *= o.r; g *= o.g; b *= o.b; return *this; }
    constexpr Rgb& operator*=(float s) { r *= s; g *= s; b *= s; return *this; }
    constexpr bool operator==(const Rgb& o) const = default;

    constexpr bool isBlack() const { return r == 0.f && g == 0.f && b == 0.f; }
    constexpr float maxComponent() const { return std::max(r, std::max(g, b)); }
    constexpr float average() const { return (r + g + b) * (1.f / 3.f); }
    bool isFinite() const { return std::isfinite(r) && std::isfinite(g) && std::isfinite(b); }
};

constexpr Rgb operator+(const Rgb& a, const Rgb& b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
constexpr Rgb operator-(const Rgb& a, const Rgb& b) { return {a.r - b.r, a.g - b.g, a.b - b.b}; }
constexpr Rgb operator*(const Rgb& a, const Rgb& b) { return {a.r * b.r, a.g * b.g, a.b * b.b}; }
constexpr Rgb operator*(const Rgb& a, float s) { return {a.r * s, a.g * s, a.b * s}; }
constexpr Rgb operator*(float s, const Rgb& a) { return {a.r * s, a.g * s, a.b * s}; }
constexpr Rgb operator/(const Rgb& a, float s) {
    const float inv = 1.f / s;
    return {a.r * inv, a.g * inv, a.b * inv};
}

}  // namespace penumbra
