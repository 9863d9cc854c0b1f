#include "lights/light_bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra {

namespace {

// cos and sin of max(0, a - b), from the cosines and sines of angles a and b in [0, pi].
double cosMinusClamped(double sinA, double cosA, double sinB, double cosB) {
    return cosA >= cosB ? 1.0 : cosA * cosB + sinA * sinB;
}
double sinMinusClamped(double sinA, double cosA, double sinB, double cosB) {
    return cosA >= cosB ? 0.0 : sinA * cosB - cosA * sinB;
}

// The box's share of the split cost: its surface area, plus a little of its
// squared edge sum so that boxes of lights on one line (no area) still
// prefer short splits.
double boxMeasure(const Bounds3f& b) {
    const Vec3f d = b.diagonal();
    const double x = d.x, y = d.y, z = d.z;
    return 2.0 * (x * y + y * z + z * x) + 1e-3 * (x + y + z) * (x + y + z);
}

}  // namespace

struct LightBVH::Item {
    LightBounds bounds;
    float power;
    uint32_t light;
    Vec3f centroid;
};

LightBVH::LightBVH(std::span<const std::optional<LightBounds>> bounds, std::span<const double> powers) {
    trails_.resize(bounds.size());
    const auto usable = [&](size_t j) {
        const double p = j < powers.size() ? powers[j] : 0.0;
        if (!bounds[j] || !(p > 0.0) || !isFinite(bounds[j]->box.lo) || !isFinite(bounds[j]->box.hi)) return 0.0;
        return std::min(p, double(std::numeric_limits<float>::max()));
    };
    double strongest = 0.0;
    for (size_t j = 0; j < bounds.size(); ++j) strongest = std::max(strongest, usable(j));
    std::vector<Item> items;
    for (size_t j = 0; j < bounds.size(); ++j) {
        const float power = strongest > 0.0 ? float(usable(j) / strongest) : 0.f;
        if (power > 0.f) items.push_back(Item{*bounds[j], power, uint32_t(j), bounds[j]->box.center()});
    }
    if (items.empty()) return;
    nodes_.reserve(2 * items.size() - 1);
    build(items, 0, 0);
}

// Builds the node of `items` and those below it (depth-first: a node's first
// child follows it); returns its bounds and power (its children's, united).
LightBVH::Built LightBVH::build(std::span<Item> items, uint64_t turns, uint32_t depth) {
    const uint32_t index = uint32_t(nodes_.size());
    nodes_.emplace_back();
    Built b{items[0].bounds, items[0].power};
    if (items.size() == 1) {
        nodes_[index].leaf = true;
        nodes_[index].link = items[0].light;
        trails_[items[0].light] = Trail{turns, depth};
        depth_ = std::max(depth_, depth);
    } else {
        const size_t mid = split(items, depth);
        const Built first = build(items.subspan(0, mid), turns, depth + 1);
        const uint32_t second = uint32_t(nodes_.size());
        const Built rest = build(items.subspan(mid), turns | (uint64_t(1) << depth), depth + 1);
        b = Built{unite(first.bounds, rest.bounds), first.power + rest.power};
        nodes_[index].leaf = false;
        nodes_[index].link = second;
    }
    Node& node = nodes_[index];
    node.center = b.bounds.box.center();
    node.half = 0.5f * b.bounds.box.diagonal();
    node.radius2 = lengthSquared(node.half);
    node.radius = std::sqrt(node.radius2);
    node.axis = b.bounds.axis;
    node.cosThetaO = b.bounds.cosThetaO;
    node.sinThetaO = std::sqrt(std::max(0.f, 1.f - b.bounds.cosThetaO * b.bounds.cosThetaO));
    node.cosThetaE = b.bounds.cosThetaE;
    node.power = b.power;
    node.twoSided = b.bounds.twoSided;
    // thetaO + thetaE <= pi/2, both in [0, pi/2]: cos(thetaO + thetaE) >= 0.
    const float sinThetaE = std::sqrt(std::max(0.f, 1.f - node.cosThetaE * node.cosThetaE));
    node.halfSpace = !node.twoSided && node.cosThetaO >= 0.f && node.cosThetaE >= 0.f &&
                     node.cosThetaO * node.cosThetaE - node.sinThetaO * sinThetaE >= 0.f;
    return b;
}

// Where items splits into the node's two children (they are reordered so
// that the first child's come first): the binned split of least cost, or
// half of them by count where no split separates them or the tree is deep.
size_t LightBVH::split(std::span<Item> items, uint32_t depth) {
    const size_t n = items.size();
    Bounds3f centroids, box;
    for (const Item& it : items) {
        centroids.extend(it.centroid);
        box.extend(it.bounds.box);
    }
    const Vec3f extent = centroids.diagonal();
    const auto halve = [&] {
        const int axis = maxDimension(extent);
        std::nth_element(items.begin(), items.begin() + std::ptrdiff_t(n / 2), items.end(),
                         [axis](const Item& a, const Item& b) {
                             return a.centroid[axis] < b.centroid[axis] ||
                                    (a.centroid[axis] == b.centroid[axis] && a.light < b.light);
                         });
        return n / 2;
    };
    if (depth >= kMaxSplitDepth || !(maxComponent(extent) > 0.f)) return halve();

    constexpr int kBuckets = 12;
    const auto bucketOf = [&](const Item& it, int axis) {
        const int k = int(float(kBuckets) * ((it.centroid[axis] - centroids.lo[axis]) / extent[axis]));
        return std::clamp(k, 0, kBuckets - 1);
    };
    struct Cluster {
        LightBounds bounds;
        double power = 0.0;
        size_t count = 0;
        void add(const LightBounds& b, double p, size_t c) {
            bounds = count ? unite(bounds, b) : b;
            power += p;
            count += c;
        }
        double cost() const {
            return count ? power * orientationMeasure(bounds.cosThetaO, bounds.cosThetaE) * boxMeasure(bounds.box) : 0.0;
        }
    };
    double bestCost = std::numeric_limits<double>::infinity();
    int bestAxis = -1, bestBucket = 0;
    const Vec3f boxExtent = box.diagonal();
    for (int axis = 0; axis < 3; ++axis) {
        if (!(extent[axis] > 0.f)) continue;
        Cluster buckets[kBuckets];
        for (const Item& it : items) buckets[bucketOf(it, axis)].add(it.bounds, it.power, 1);
        // Splits after bucket s: the first s + 1 buckets against the rest.
        double below[kBuckets - 1];
        size_t belowCount[kBuckets - 1];
        Cluster acc;
        for (int s = 0; s < kBuckets - 1; ++s) {
            if (buckets[s].count) acc.add(buckets[s].bounds, buckets[s].power, buckets[s].count);
            below[s] = acc.cost();
            belowCount[s] = acc.count;
        }
        // Thin boxes cut across their long side are no bargain: scale by the box's aspect.
        const double aspect = double(maxComponent(boxExtent)) / double(boxExtent[axis]);
        acc = Cluster{};
        for (int s = kBuckets - 2; s >= 0; --s) {
            if (buckets[s + 1].count) acc.add(buckets[s + 1].bounds, buckets[s + 1].power, buckets[s + 1].count);
            if (belowCount[s] == 0 || belowCount[s] == n) continue;
            const double cost = (below[s] + acc.cost()) * aspect;
            if (cost < bestCost) {
                bestCost = cost;
                bestAxis = axis;
                bestBucket = s;
            }
        }
    }
    if (bestAxis < 0) return halve();
    const auto mid = std::partition(items.begin(), items.end(),
                                    [&](const Item& it) { return bucketOf(it, bestAxis) <= bestBucket; });
    return size_t(mid - items.begin());
}

// In double precision: squared distances and power ratios of scenes that
// span the float range neither overflow nor vanish, so no light that reaches
// a point loses its share to rounding.
double LightBVH::importance(const Node& node, const Vec3f& p, const Vec3f& n) {
    const double wx = double(p.x) - node.center.x, wy = double(p.y) - node.center.y, wz = double(p.z) - node.center.z;
    const double d2 = wx * wx + wy * wy + wz * wz;  // w: from the lights towards p
    // The box's farthest reach above p's tangent plane (n . x - n . p over the box) and,
    // where every emitter sends light only into the half-space its axis faces, the box's
    // reach behind p along the axis; where either is not positive, nothing arrives.
    const bool hasNormal = n.x != 0.f || n.y != 0.f || n.z != 0.f;
    const auto reach = [&](const Vec3f& dir, double sign) {
        return sign * -(dir.x * wx + dir.y * wy + dir.z * wz) +
               (std::fabs(dir.x) * node.half.x + std::fabs(dir.y) * node.half.y + std::fabs(dir.z) * node.half.z);
    };
    if (hasNormal && !(reach(n, 1.0) > 0.0)) return 0.0;
    if (node.halfSpace && !(reach(node.axis, -1.0) > 0.0)) return 0.0;
    // Within the bounding sphere: light may come from anywhere, from as near as
    // its radius (a point light at p itself: as near as a float's square can tell).
    if (!(d2 > double(node.radius2))) return node.power / std::max(double(node.radius2), 1e-76);
    // The half angle thetaB the sphere subtends at p widens both angles below.
    const double invD = 1.0 / std::sqrt(d2);
    const double sinB = node.radius * invD, cosB = std::sqrt(std::max(0.0, 1.0 - sinB * sinB));
    // At the emitters: the angle from the cone's axis to p, less the cone's and thetaB.
    double cosEmit = 1.0;
    if (node.cosThetaO > -1.f) {
        double cosW = (node.axis.x * wx + node.axis.y * wy + node.axis.z * wz) * invD;
        if (node.twoSided) cosW = std::fabs(cosW);
        const double sinW = std::sqrt(std::max(0.0, 1.0 - cosW * cosW));
        const double cosX = cosMinusClamped(sinW, cosW, node.sinThetaO, node.cosThetaO);
        const double sinX = sinMinusClamped(sinW, cosW, node.sinThetaO, node.cosThetaO);
        cosEmit = cosMinusClamped(sinX, cosX, sinB, cosB);
        if (!(cosEmit > node.cosThetaE)) return 0.0;
    }
    // At the receiver: the angle from n to the lights, less thetaB.
    double cosReceive = 1.0;
    if (hasNormal) {
        const double cosI = -(n.x * wx + n.y * wy + n.z * wz) * invD;
        const double sinI = std::sqrt(std::max(0.0, 1.0 - cosI * cosI));
        cosReceive = cosMinusClamped(sinI, cosI, sinB, cosB);
        if (!(cosReceive > 0.0)) return 0.0;
    }
    const double value = node.power * cosEmit * cosReceive * (invD * invD);
    return value > 0.0 ? value : 0.0;
}

float LightBVH::firstShare(double a, double b) {
    if (!(b > 0.0)) return a > 0.0 ? 1.f : 0.f;
    if (!(a > 0.0)) return 0.f;
    return float(a / (a + b));
}

LightPicker::Pick LightBVH::pick(float u, const Vec3f& p, const Vec3f& n) const {
    if (empty()) return {0, 0.f, u};
    uint32_t k = 0;
    float probability = 1.f;
    if (nodes_[0].leaf && !(importance(nodes_[0], p, n) > 0.0)) return {0, 0.f, u};
    while (!nodes_[k].leaf) {
        const uint32_t first = k + 1, second = nodes_[k].link;
        const double a = importance(nodes_[first], p, n), b = importance(nodes_[second], p, n);
        if (!(a > 0.0) && !(b > 0.0)) return {0, 0.f, u};
        const float share = firstShare(a, b);
        if (u < share) {
            u = u / share;
            probability *= share;
            k = first;
        } else {
            u = (u - share) / (1.f - share);
            probability *= 1.f - share;
            k = second;
        }
        u = std::min(u, 0x1.fffffep-1f);
    }
    return {nodes_[k].link, probability, u};
}

float LightBVH::probability(size_t j, const Vec3f& p, const Vec3f& n) const {
    if (!holds(j)) return 0.f;
    const Trail trail = trails_[j];
    if (trail.depth == 0) return importance(nodes_[0], p, n) > 0.0 ? 1.f : 0.f;
    uint32_t k = 0;
    float probability = 1.f;
    for (uint32_t level = 0; level < trail.depth; ++level) {
        const uint32_t first = k + 1, second = nodes_[k].link;
        const double a = importance(nodes_[first], p, n), b = importance(nodes_[second], p, n);
        if (!(a > 0.0) && !(b > 0.0)) return 0.f;
        const float share = firstShare(a, b);
        if ((trail.turns >> level) & 1u) {
            probability *= 1.f - share;
            k = second;
        } else {
            probability *= share;
            k = first;
        }
    }
    return probability;
}

}  // namespace penumbra
