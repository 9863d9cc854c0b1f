#include "shading/light_windows.h"

#include <algorithm>
#include <cmath>

#include "core/ray.h"

namespace penumbra {

LightWindows::LightWindows(const PhongSampler& sampler, const LightSet& lights, const Vec3f& p) : sampler_(sampler) {
    const size_t n = lights.areaLightCount();
    if (n > kMaxLights) {
        everywhere_ = true;
        return;
    }
    // A ray leaves from within rayOffsetScale(p) of p (spawnRay): seen from p,
    // a sphere it meets lies within that distance (twice, for safety) of the
    // light's; the sphere's own radius may have rounded short.
    const double offset = 2.0 * double(rayOffsetScale(p));
    // Angles by their cosines and sines, so that the cone's bounds take sums
    // of products and square roots instead of an asin per light and an acos
    // and four sines or cosines per lobe. Each sum is exact to about 1e-16,
    // far inside the margins.
    constexpr double m = kAngleMargin;
    constexpr double cosMargin = 1.0 - m * m / 2.0 + m * m * m * m / 24.0;  // the next terms are below 1e-19
    constexpr double sinMargin = m - m * m * m / 6.0 + m * m * m * m * m / 120.0;
    constexpr double cosAxisGap = 0.9999500004166653;  // cos(0.01): azimuths unused nearer an axis
    for (size_t i = 0; i < n; ++i) {
        const LightSet::BoundingSphere& b = lights.boundingSphere(i);
        if (b.radius2 < 0.f) continue;
        const double cx = double(b.center.x) - p.x, cy = double(b.center.y) - p.y, cz = double(b.center.z) - p.z;
        const double d = std::sqrt(cx * cx + cy * cy + cz * cz);
        const double reach = std::sqrt(double(b.radius2)) * (1.0 + 1e-5) + offset + 1e-5 * d;
        if (!(d > 1.01 * reach)) {  // in or next to the sphere (or not finite): every direction may meet it
            everywhere_ = true;
            return;
        }
        // The cone's half-angle: asin(reach / d) (below 1.43, as reach / d < 1 / 1.01) plus the margin.
        const double x = reach / d, y = std::sqrt(1.0 - x * x);
        const double sinHalf = x * cosMargin + y * sinMargin, cosHalf = y * cosMargin - x * sinMargin;
        for (const bool diffuse : {false, true}) {
            if (!sampler.picks(diffuse)) continue;
            const Frame& f = sampler.lobeFrame(diffuse);
            const auto along = [&](const Vec3f& a) { return (a.x * cx + a.y * cy + a.z * cz) / d; };
            // g, the cone axis's angle from the lobe's, in [0, pi]; the cone spans [g - half, g + half].
            const double cosG = std::clamp(along(f.n), -1.0, 1.0), sinG = std::sqrt(1.0 - cosG * cosG);
            const PhongSampler::Angle nearest{cosG * cosHalf + sinG * sinHalf, sinG * cosHalf - cosG * sinHalf};
            const PhongSampler::Angle farthest{cosG * cosHalf - sinG * sinHalf, sinG * cosHalf + cosG * sinHalf};
            const auto [lo, hi] = sampler.polarRange(diffuse, nearest, farthest);
            if (!(lo <= hi)) continue;
            // Eighths of a turn (the azimuth's unit).
            constexpr double kEighth = 0.78539816339744830962;  // pi / 4
            double width = 4.0;  // the whole turn: the cone holds the axis or its opposite, or nearly
            // Where g - half > 0.01 and g + half < pi - 0.01 (g - half lies in (-pi/2, pi), g + half in (0, 3 pi/2)).
            if (nearest.sin > 0.0 && nearest.cos < cosAxisGap && farthest.sin > 0.0 && farthest.cos > -cosAxisGap)
                width = std::min(4.0, (std::asin(std::min(1.0, sinHalf / sinG)) + kAngleMargin) / kEighth);
            Windows& w = windows_[diffuse ? 1 : 0];
            w.lo[w.count] = lo;
            w.hi[w.count] = hi;
            w.azimuth[w.count] = float(std::atan2(along(f.t), along(f.s)) / kEighth);
            w.halfWidth[w.count] = float(width);
            ++w.count;
        }
    }
}

}  // namespace penumbra
