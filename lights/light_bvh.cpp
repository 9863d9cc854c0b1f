// The light hierarchy's queries: importance, pick and probability
// (lights/light_bvh.h); its construction is lights/light_bvh_build.cpp.
#include "lights/light_bvh.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace penumbra {

namespace {

// Squared distances are taken as at least this: a point light at the
// shading point itself is as near as can be told, not infinitely near.
constexpr float kNearest2 = 1e-30f;

// Nodes on the way from the root to a leaf: at most one per level of the
// binary tree (kMaxSplitDepth levels of binned splits, then halving).
constexpr size_t kMaxLevels = 2 * LightBVH::kMaxSplitDepth + 2;

}  // namespace

// A loop over the children, without branches, so that it compiles to one
// vector step; only the nearest child's distance is looked at afterwards.
void LightBVH::importances(const Node& node, const Vec3f& p, const Vec3f& n, float (&out)[kWidth]) {
    const float px = p.x, py = p.y, pz = p.z, nx = n.x, ny = n.y, nz = n.z;
    const int32_t hasNormal = (nx != 0.f) | (ny != 0.f) | (nz != 0.f);
    const float anx = std::fabs(nx), any = std::fabs(ny), anz = std::fabs(nz);
    float raw[kWidth], dist2[kWidth];  // local: no stores that might alias the node
    for (int c = 0; c < kWidth; ++c) {
        const float wx = px - node.cx[c], wy = py - node.cy[c], wz = pz - node.cz[c];  // from the lights to p
        const float d2 = wx * wx + wy * wy + wz * wz;
        const float nw = nx * wx + ny * wy + nz * wz;
        const float aw = node.ax[c] * wx + node.ay[c] * wy + node.az[c] * wz;
        // The box's farthest reach above p's tangent plane, and (emitters
        // facing one half-space) behind p along the axis.
        const float aboveP = (anx * node.hx[c] + any * node.hy[c] + anz * node.hz[c]) - nw;
        const float behindP = aw + (std::fabs(node.ax[c]) * node.hx[c] + std::fabs(node.ay[c]) * node.hy[c] +
                                    std::fabs(node.az[c]) * node.hz[c]);
        // Within the bounding sphere light may come from anywhere, from as near as its radius.
        const int32_t inside = !(d2 > node.radius2[c]);
        const float invD = 1.f / std::sqrt(std::max(d2, kNearest2));
        const float sinB = node.radius[c] * invD;  // the half angle thetaB the sphere subtends
        const float cosB = std::sqrt(std::max(0.f, 1.f - sinB * sinB));
        // At the emitters: the angle from the cone's axis to p, less the cone's and thetaB.
        float cosW = aw * invD;
        cosW = node.twoSided[c] ? std::fabs(cosW) : cosW;
        const float sinW = std::sqrt(std::max(0.f, 1.f - cosW * cosW));
        const float cosO = node.cosO[c], sinO = node.sinO[c];
        const int32_t inCone = cosW >= cosO;
        const float cosX = inCone ? 1.f : cosW * cosO + sinW * sinO;
        const float sinX = inCone ? 0.f : sinW * cosO - cosW * sinO;
        const float cosEmit = (inside | (cosX >= cosB)) ? 1.f : cosX * cosB + sinX * sinB;
        // At the receiver: the angle from n to the lights, less thetaB.
        const float cosI = -nw * invD;
        const float sinI = std::sqrt(std::max(0.f, 1.f - cosI * cosI));
        const float cosReceive = (inside | !hasNormal | (cosI >= cosB)) ? 1.f : cosI * cosB + sinI * sinB;
        // One select per test (their conjunction as one integer would not vectorise).
        float value = node.power[c] * cosEmit * cosReceive;
        value = (hasNormal == 0) | (aboveP > 0.f) ? value : 0.f;
        value = (node.halfSpace[c] == 0) | (behindP > 0.f) ? value : 0.f;
        value = cosEmit > node.cosE[c] ? value : 0.f;
        value = cosReceive > 0.f ? value : 0.f;
        dist2[c] = std::max(inside ? node.radius2[c] : d2, kNearest2);
        raw[c] = value;
    }
    // Over the squared distance, scaled by the nearest child's so that no
    // ratio overflows a float.
    float nearest = kInfinity;
    for (int c = 0; c < kWidth; ++c) nearest = raw[c] > 0.f ? std::min(nearest, dist2[c]) : nearest;
    for (int c = 0; c < kWidth; ++c) {
        const float scale = nearest / dist2[c];  // NaN only for points beyond the scene's range
        out[c] = (raw[c] > 0.f) & (scale > 0.f) ? raw[c] * scale : 0.f;
    }
}

LightPicker::Pick LightBVH::pick(float u, const Vec3f& p, const Vec3f& n) const {
    if (empty()) return {0, 0.f, u};
    uint32_t k = 0;
    float probability = 1.f;
    for (;;) {
        const Node& node = nodes_[k];
        float importance[kWidth];
        importances(node, p, n, importance);
        float total = 0.f;
        for (int c = 0; c < kWidth; ++c) total += importance[c];
        if (!(total > 0.f)) return {0, 0.f, u};
        // The child whose share of [0, total) holds u * total (the last that
        // has one, where rounding puts u * total at the end).
        const float target = u * total;
        int chosen = 0;
        float below = 0.f, sum = 0.f;
        for (int c = 0; c < kWidth; ++c) {
            if (!(importance[c] > 0.f)) continue;
            chosen = c;
            below = sum;
            sum += importance[c];
            if (target < sum) break;
        }
        probability *= importance[chosen] / total;
        u = std::clamp((target - below) / importance[chosen], 0.f, 0x1.fffffep-1f);
        if (node.leaf[chosen]) return {node.child[chosen], probability, u};
        k = node.child[chosen];
    }
}

float LightBVH::probability(size_t j, const Vec3f& p, const Vec3f& n) const {
    if (!holds(j)) return 0.f;
    // The path from the leaf up, then its shares from the root down, in pick()'s order.
    std::array<Place, kMaxLevels> path;
    size_t levels = 0;
    for (Place at = leaves_[j]; at.node != kNone && levels < path.size();
         at = Place{nodes_[at.node].parent, nodes_[at.node].parentSlot})
        path[levels++] = at;
    float probability = 1.f;
    for (size_t l = levels; l-- > 0;) {
        float importance[kWidth];
        importances(nodes_[path[l].node], p, n, importance);
        float total = 0.f;
        for (int c = 0; c < kWidth; ++c) total += importance[c];
        const float mine = importance[path[l].slot];
        if (!(total > 0.f) || !(mine > 0.f)) return 0.f;
        probability *= mine / total;
    }
    return probability;
}

}  // namespace penumbra
