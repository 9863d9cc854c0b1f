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
        const double half = std::asin(reach / d) + kAngleMargin;
        for (const bool diffuse : {false, true}) {
            if (!sampler.picks(diffuse)) continue;
            const Frame& f = sampler.lobeFrame(diffuse);
            const auto along = [&](const Vec3f& a) { return (a.x * cx + a.y * cy + a.z * cz) / d; };
            const double g = std::acos(std::clamp(along(f.n), -1.0, 1.0));
            const auto [lo, hi] = sampler.polarRange(diffuse, g - half, g + half);
            if (!(lo <= hi)) continue;
            // Eighths of a turn (the azimuth's unit).
            constexpr double kEighth = 0.78539816339744830962;  // pi / 4
            double width = 4.0;  // the whole turn: the cone holds the axis or its opposite, or nearly
            if (g - half > 0.01 && g + half < kPi - 0.01)
                width = std::min(4.0, (std::asin(std::min(1.0, std::sin(half) / std::sin(g))) + kAngleMargin) / kEighth);
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
