#include "shading/shadow_lanes.h"

#include <algorithm>
#include <cmath>

#include "core/lane_clones.h"

namespace penumbra {

namespace {

// Every lane's shadow ray as spawnRayTo makes it towards the sampled point:
// offsetRayOrigin, then from the origin to the point, stopping short by the
// point's own offset. Inlined into trace's per-CPU clones.
[[gnu::always_inline]] inline void raysToPoints(const LanePoints& at, const LightLanes& s, int n, RayLanes& rays) {
    for (int c = 0; c < n; ++c) {
        const float px = at.px[c], py = at.py[c], pz = at.pz[c], gx = at.nx[c], gy = at.ny[c], gz = at.nz[c];
        const float ax = std::fabs(px), ay = std::fabs(py), az = std::fabs(pz);
        const float ayz = ay < az ? az : ay, axyz = ax < ayz ? ayz : ax;
        const float scale = kRayOffsetRelative * (axyz < 1.f ? 1.f : axyz);
        const float qx = s.qx[c], qy = s.qy[c], qz = s.qz[c];
        const bool inward = (qx - px) * gx + (qy - py) * gy + (qz - pz) * gz < 0.f;
        const float offx = gx * scale, offy = gy * scale, offz = gz * scale;
        const float ox = inward ? px - offx : px + offx;
        const float oy = inward ? py - offy : py + offy;
        const float oz = inward ? pz - offz : pz + offz;
        const float dx = qx - ox, dy = qy - oy, dz = qz - oz;
        const float dist = std::sqrt(dx * dx + dy * dy + dz * dz);
        const float inv = 1.f / dist;
        const float bx = std::fabs(qx), by = std::fabs(qy), bz = std::fabs(qz);
        const float byz = by < bz ? bz : by, bxyz = bx < byz ? byz : bx;
        const float tfar = dist - kRayOffsetRelative * (bxyz < 1.f ? 1.f : bxyz);
        const bool moves = dist > 0.f;
        rays.ox[c] = ox;
        rays.oy[c] = oy;
        rays.oz[c] = oz;
        rays.dx[c] = moves ? dx * inv : 0.f;
        rays.dy[c] = moves ? dy * inv : 0.f;
        rays.dz[c] = moves ? dz * inv : 0.f;
        rays.tnear[c] = 0.f;
        rays.tfar[c] = moves ? (tfar < 0.f ? 0.f : tfar) : 0.f;
    }
}

}  // namespace

PENUMBRA_LANE_CLONES uint32_t ShadowLanes::trace(const LightLanes& s, int n, float nLight, const Accelerator& accel,
                                                 Rgb* added, bool clear) const {
    const LanePoints& at = points_;
    RayLanes rays;
    alignas(64) float wr[kWidth], wg[kWidth], wb[kWidth];
    // Every lane's shadow ray (none where the caller knows them clear) and,
    // where the surface is not glossy, phongResponse with no specular lobe
    // times L / pdf and the MIS weight (shadowSampleWeight's, with
    // lambertEvaluate's pdf): the same operations in the same order, so the
    // same values bit for bit (its specular term, ks times a zero lobe, adds
    // an exact zero there, so it is left out; under a delta light the classic
    // model's kd is not divided by pi, and times 1 it stays exact).
    if (!clear) raysToPoints(at, s, n, rays);
    // What kd is scaled by before the cosine: 1 / pi, but 1 for the classic
    // Phong model under a point or directional light (phongResponse). Set
    // apart from the loop below, which a per-lane choice kept from vectorising.
    alignas(64) float kdScale[kWidth];
    std::fill_n(kdScale, kWidth, kInvPi);
    if (s.delta)
        for (int c = 0; c < n; ++c)
            if (sp_[c]->material->model == PhongModel::Classic) kdScale[c] = 1.f;
    for (int c = 0; c < n; ++c) {
        const float gx = at.nx[c], gy = at.ny[c], gz = at.nz[c];
        const float wx = s.wx[c], wy = s.wy[c], wz = s.wz[c];
        const float cosTheta = nsx_[c] * wx + nsy_[c] * wy + nsz_[c] * wz;
        const int32_t above = wx * gx + wy * gy + wz * gz > 0.f;
        const float fr0 = kdr_[c] * kdScale[c] * cosTheta;
        const float fg0 = kdg_[c] * kdScale[c] * cosTheta;
        const float fb0 = kdb_[c] * kdScale[c] * cosTheta;
        const bool lit = cosTheta > 0.f;  // else phongResponse is zero
        const float fr = lit ? fr0 : 0.f, fg = lit ? fg0 : 0.f, fb = lit ? fb0 : 0.f;
        const int32_t black = int32_t(fr == 0.f) & int32_t(fg == 0.f) & int32_t(fb == 0.f);
        // The MIS weight against the cosine lobe's pdf; 1 without (and times
        // 1 the quotient stays exact).
        const float bsdfPdf = lambertPdf(cosTheta);
        const bool mis = misCount_[c] > 0.f && !s.delta;
        const float scale = mis ? powerHeuristic(nLight, s.pdf[c], misCount_[c], bsdfPdf) : 1.f;
        const float invPdf = scale / s.pdf[c];
        wr[c] = fr * s.Lr[c] * invPdf;
        wg[c] = fg * s.Lg[c] * invPdf;
        wb[c] = fb * s.Lb[c] * invPdf;
        rays.active[c] = s.ok[c] & above & (1 - black);
    }
    for (int c = n; c < kWidth; ++c) rays.active[c] = 0;
    // The lanes the loop above does not cover: glossy weights, and
    // samples of lights at infinity (a ray in a direction, not to a point).
    for (int c = 0; c < n; ++c) {
        const bool atInfinity = std::fabs(s.distance[c]) == kInfinity;
        if (!s.ok[c] || !(scalar_[c] || atInfinity)) continue;
        const LightSample ls = s.get(c);
        if (atInfinity) rays.set(c, spawnRay(at.p(c), at.n(c), ls.wi));
        if (!scalar_[c]) continue;
        Rgb w;
        rays.active[c] = shadowSampleWeight(*sp_[c], ls, 1.f, ls.pdf, misCount_[c], nLight, w) ? 1 : 0;
        wr[c] = w.r;
        wg[c] = w.g;
        wb[c] = w.b;
    }
    alignas(64) uint8_t blocked[kWidth] = {};
    if (!clear) {
        // The accelerator's hints, where it takes them: a ray that runs above
        // the surface of a convex mesh leaves it (spawnRay's rule: its origin
        // lies outside).
        alignas(64) int32_t leaving[kWidth];
        const bool hinted = accel.takesLeavingHints();
        if (hinted) {
            std::fill_n(leaving, kWidth, -1);
            for (int c = 0; c < n; ++c) {
                const bool above = rays.dx[c] * at.nx[c] + rays.dy[c] * at.ny[c] + rays.dz[c] * at.nz[c] > 0.f;
                leaving[c] = above ? sp_[c]->convexMesh : -1;
            }
        }
        accel.occludedLanes(rays, blocked, hinted ? leaving : nullptr);
    }
    uint32_t traced = 0;
    for (int c = 0; c < n; ++c) traced += uint32_t(rays.active[c]);
    // Zeros first, then the unoccluded lanes' weights: the one loop with a
    // select was vectorised into shuffles and blends that cost more than it saved.
    std::fill_n(added, n, Rgb{});
    for (int c = 0; c < n; ++c)
        if (rays.active[c] && !blocked[c]) added[c] = Rgb{wr[c], wg[c], wb[c]};
    return traced;
}

}  // namespace penumbra
