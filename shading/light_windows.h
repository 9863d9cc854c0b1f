// Which of a shading point's BRDF samples may meet an area light, told from
// each sample's u before its direction is made. Under small lights nearly
// all direct-light BRDF samples meet no light and add nothing
// (docs/rendering.md, "MIS"), yet making each one's direction (a pow or a
// square root, a sine and a cosine, a frame) and testing it against the
// lights cost most of what those samples cost.
//
// Seen from the point, a light's bounding sphere fills a cone of directions
// (half-angle b, its axis at angle g from a lobe's axis). A direction in it
// makes an angle within [g - b, g + b] with the lobe's axis, and (where the
// cone holds neither that axis nor its opposite) has an azimuth about the
// axis within asin(sin b / sin g) of the cone axis's. The sample's polar
// coordinate grows with that angle and its azimuth is its own
// (PhongSampler::polar), so each light gives each lobe one window of
// coordinates, worked out once per point, and each sample is tested against
// the windows alone. The cones are widened for the ray's offset origin and
// both windows by 2e-3 rad, above the rounding of a direction's making
// (under 1e-3 rad: near a lobe's axis, where cos a rounds to the float below
// 1; azimuths are not used within 0.01 rad of the axis, where rounding moves
// them most), so a sample outside every window is one whose ray the exact
// test (LightSet::firstEmitterHit) finds meeting no light.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/math.h"
#include "lights/light_set.h"
#include "shading/bsdf/phong_sampling.h"

namespace penumbra {

class LightWindows {
public:
    /// The windows of sampler's samples at p (spawned off the surface there)
    /// onto the area lights of `lights`. Keeps a reference to the sampler.
    LightWindows(const PhongSampler& sampler, const LightSet& lights, const Vec3f& p);

    /// False only where the ray of sampler.direction(u) can meet no area
    /// light: true for every u where p lies in or next to a light's bounding
    /// sphere, or where there are more lights than the windows hold.
    bool mayReachALight(Vec2f u) const {
        if (everywhere_) return true;
        const PhongSampler::Polar c = sampler_.polar(u);
        const Windows& w = windows_[c.diffuse ? 1 : 0];
        bool in = false;
        for (uint32_t k = 0; k < w.count; ++k) {
            float turn = c.azimuth - w.azimuth[k];  // to [-4, 4): eighths of a turn either way
            turn -= 8.f * std::floor((turn + 4.f) * 0.125f);
            in |= c.s >= w.lo[k] && c.s <= w.hi[k] && std::fabs(turn) <= w.halfWidth[k];
        }
        return in;
    }

    /// mayReachALight of 16 points as lanes: may[c] for (x[c], y[c]), the
    /// same answers, as loops over the lanes.
    static constexpr int kLanes = PhongSampler::kLanes;
    void mayReachLanes(const float (&x)[kLanes], const float (&y)[kLanes], int32_t (&may)[kLanes]) const;

    /// The margin added to each cone's half-angle, radians.
    static constexpr double kAngleMargin = 2e-3;

private:
    static constexpr size_t kMaxLights = LightSet::kMaxTestedEmitters;
    const PhongSampler& sampler_;
    bool everywhere_ = false;
    struct Windows {
        uint32_t count = 0;
        // Per light: the polar coordinate's range, the azimuth of the cone's
        // axis and the half-width about it (eighths of a turn; 4: any).
        float lo[kMaxLights], hi[kMaxLights], azimuth[kMaxLights], halfWidth[kMaxLights];
    };
    Windows windows_[2];  // [0] the cos^e lobe, [1] the diffuse one
};

// Inline so that it compiles into the caller's lane clones (core/lane_clones.h).
[[gnu::always_inline]] inline void LightWindows::mayReachLanes(const float (&x)[kLanes], const float (&y)[kLanes],
                                                               int32_t (&may)[kLanes]) const {
    for (int c = 0; c < kLanes; ++c) may[c] = everywhere_;
    if (everywhere_) return;
    alignas(64) int32_t diffuse[kLanes];
    alignas(64) float s[kLanes], azimuth[kLanes];
    sampler_.polarLanes(x, y, diffuse, s, azimuth);
    const Windows &lobe = windows_[0], &disk = windows_[1];
    constexpr float kInf = std::numeric_limits<float>::infinity();
    for (uint32_t k = 0; k < std::max(lobe.count, disk.count); ++k) {
        // Window k of each lobe; an empty one where that lobe has fewer.
        const bool inLobe = k < lobe.count, inDisk = k < disk.count;
        const float lo0 = inLobe ? lobe.lo[k] : kInf, hi0 = inLobe ? lobe.hi[k] : -kInf;
        const float lo1 = inDisk ? disk.lo[k] : kInf, hi1 = inDisk ? disk.hi[k] : -kInf;
        const float az0 = inLobe ? lobe.azimuth[k] : 0.f, az1 = inDisk ? disk.azimuth[k] : 0.f;
        const float half0 = inLobe ? lobe.halfWidth[k] : 0.f, half1 = inDisk ? disk.halfWidth[k] : 0.f;
        for (int c = 0; c < kLanes; ++c) {
            const bool d = diffuse[c] != 0;
            float turn = azimuth[c] - (d ? az1 : az0);
            turn -= 8.f * std::floor((turn + 4.f) * 0.125f);
            const bool inPolar = s[c] >= (d ? lo1 : lo0) && s[c] <= (d ? hi1 : hi0);
            may[c] |= int32_t(inPolar && std::fabs(turn) <= (d ? half1 : half0));
        }
    }
}

}  // namespace penumbra
