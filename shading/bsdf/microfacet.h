// The isotropic Trowbridge-Reitz (GGX) microfacet distribution with Smith's
// masking-shadowing, as glTF 2.0 (Appendix B) and most real-time and offline
// renderers use it, and the sampling of its visible normals (Heitz 2018,
// "Sampling the GGX Distribution of Visible Normals", JCGT 7(4)).
//
// Every vector here is in the local frame of the shading normal (z up) and
// unit; alpha is the width, glTF's roughness squared.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/math.h"

namespace penumbra {

class GgxDistribution {
public:
    explicit GgxDistribution(float alpha) : alpha_(alpha), alpha2_(alpha * alpha) {}

    float alpha() const { return alpha_; }

    /// D(h): the density of microfacet normals h per unit projected area,
    /// normalised so that the integral of D(h) h.z over the hemisphere is 1.
    float d(const Vec3f& h) const {
        if (!(h.z > 0.f)) return 0.f;
        const float k = h.z * h.z * (alpha2_ - 1.f) + 1.f;
        return alpha2_ / (kPi * k * k);
    }

    /// Smith's Lambda(w): G1(w) = 1 / (1 + Lambda(w)).
    float lambda(const Vec3f& w) const {
        const float cos2 = w.z * w.z;
        if (!(cos2 > 0.f)) return kInfinity;
        const float tan2 = std::max(0.f, 1.f - cos2) / cos2;
        return 0.5f * (std::sqrt(1.f + alpha2_ * tan2) - 1.f);
    }

    /// The share of microfacets seen from w that are not masked.
    float g1(const Vec3f& w) const { return 1.f / (1.f + lambda(w)); }

    /// Smith's height-correlated masking-shadowing of a reflection pair
    /// (both directions above the surface).
    float g2(const Vec3f& wo, const Vec3f& wi) const { return 1.f / (1.f + lambda(wo) + lambda(wi)); }

    /// The density of the normals visible from wo (wo.z > 0), per solid
    /// angle of h: G1(wo) max(0, wo.h) D(h) / wo.z.
    float visibleNormalPdf(const Vec3f& wo, const Vec3f& h) const {
        const float cosOh = dot(wo, h);
        if (!(cosOh > 0.f) || !(wo.z > 0.f)) return 0.f;
        return g1(wo) * cosOh * d(h) / wo.z;
    }

    /// Draws a normal h with visibleNormalPdf(wo, h), u in [0, 1)^2: the
    /// view is stretched so that the distribution becomes the unit
    /// hemisphere's, a point is drawn on the part of the disk it sees
    /// (uniform in the projected area) and lifted back onto the hemisphere,
    /// then the stretch is undone on the normal.
    Vec3f sampleVisibleNormal(const Vec3f& wo, Vec2f u) const {
        const Vec3f v = normalize(Vec3f{alpha_ * wo.x, alpha_ * wo.y, wo.z});
        const float lenSq = v.x * v.x + v.y * v.y;
        const Vec3f t1 = lenSq > 0.f ? Vec3f{-v.y, v.x, 0.f} * (1.f / std::sqrt(lenSq)) : Vec3f{1.f, 0.f, 0.f};
        const Vec3f t2 = cross(v, t1);
        const float r = std::sqrt(u.x), phi = 2.f * kPi * u.y;
        const float p1 = r * std::cos(phi);
        const float s = 0.5f * (1.f + v.z);
        // The disk's half hidden behind the hemisphere's rim is folded onto the visible part.
        const float p2 = (1.f - s) * std::sqrt(std::max(0.f, 1.f - p1 * p1)) + s * (r * std::sin(phi));
        const Vec3f nh = t1 * p1 + t2 * p2 + v * std::sqrt(std::max(0.f, 1.f - p1 * p1 - p2 * p2));
        return normalize(Vec3f{alpha_ * nh.x, alpha_ * nh.y, std::max(1e-7f, nh.z)});
    }

private:
    float alpha_, alpha2_;
};

}  // namespace penumbra
