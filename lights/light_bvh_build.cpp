// The light hierarchy's construction: the binary tree of binned splits, then
// its collapse to nodes of LightBVH::kWidth children (lights/light_bvh.h).
#include <algorithm>
#include <cmath>
#include <limits>

#include "lights/light_bvh.h"

namespace penumbra {

namespace {

// The box's share of the split cost: its surface area, plus a little of its
// squared edge sum so that boxes of lights on one line (no area) still
// prefer short splits.
double boxMeasure(const Bounds3f& b) {
    const Vec3f d = b.diagonal();
    const double x = d.x, y = d.y, z = d.z;
    return 2.0 * (x * y + y * z + z * x) + 1e-3 * (x + y + z) * (x + y + z);
}

// A light as the binary build sorts it.
struct Item {
    LightBounds bounds;
    float power;
    uint32_t light;
    Vec3f centroid;
};

// Where items splits into the node's two children (they are reordered so
// that the first child's come first): the binned split of least cost, or
// half of them by count where no split separates them or the tree is deep.
size_t split(std::span<Item> items, uint32_t depth) {
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
    if (depth >= LightBVH::kMaxSplitDepth || !(maxComponent(extent) > 0.f)) return halve();

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

}  // namespace

// A node of the binary tree: its lights' bounds, power and count, and its
// children (none for a leaf, which holds one light).
struct LightBVH::Binary {
    LightBounds bounds;
    float power = 0.f;
    uint32_t count = 1;
    uint32_t left = kNone, right = kNone;
    uint32_t light = kNone;
};

namespace {

// Builds the binary tree's node of `items` and those below it into `tree`;
// returns its index.
template <class Binary>
uint32_t buildBinary(std::span<Item> items, uint32_t depth, std::vector<Binary>& tree) {
    const uint32_t index = uint32_t(tree.size());
    tree.emplace_back();
    if (items.size() == 1) {
        tree[index].bounds = items[0].bounds;
        tree[index].power = items[0].power;
        tree[index].light = items[0].light;
        return index;
    }
    const size_t mid = split(items, depth);
    const uint32_t left = buildBinary(items.subspan(0, mid), depth + 1, tree);
    const uint32_t right = buildBinary(items.subspan(mid), depth + 1, tree);
    Binary& b = tree[index];
    b.left = left;
    b.right = right;
    b.bounds = unite(tree[left].bounds, tree[right].bounds);
    b.power = tree[left].power + tree[right].power;
    b.count = tree[left].count + tree[right].count;
    return index;
}

}  // namespace

LightBVH::LightBVH(std::span<const std::optional<LightBounds>> bounds, std::span<const double> powers) {
    leaves_.resize(bounds.size());
    constexpr float kRange = 1.8e18f;  // the accelerators' coordinates (core/ray.h)
    const auto usable = [&](size_t j) {
        const double p = j < powers.size() ? weighedPower(powers[j]) : 0.0;
        if (!bounds[j] || p == 0.0) return 0.0;
        const Bounds3f& box = bounds[j]->box;
        if (!(maxAbsComponent(box.lo) <= kRange) || !(maxAbsComponent(box.hi) <= kRange)) return 0.0;
        return p;
    };
    double strongest = 0.0;
    for (size_t j = 0; j < bounds.size(); ++j) strongest = std::max(strongest, usable(j));
    std::vector<Item> items;
    for (size_t j = 0; j < bounds.size(); ++j) {
        const float power = strongest > 0.0 ? float(usable(j) / strongest) : 0.f;
        if (power >= 1e-20f) items.push_back(Item{*bounds[j], power, uint32_t(j), bounds[j]->box.center()});
    }
    if (items.empty()) return;
    std::vector<Binary> tree;
    tree.reserve(2 * items.size() - 1);
    buildBinary(std::span<Item>(items), 0, tree);
    collapse(tree, 0, kNone, 0, 1);
}

// Makes the node whose children are binary node `root`'s descendants: its two
// children, the one of more lights replaced by its own two while there is
// room; returns its index. A single light is a root of one child.
uint32_t LightBVH::collapse(const std::vector<Binary>& tree, uint32_t root, uint32_t parent, uint32_t parentSlot,
                            uint32_t depth) {
    std::vector<uint32_t> slots;
    if (tree[root].light != kNone) {
        slots = {root};
    } else {
        slots = {tree[root].left, tree[root].right};
        while (slots.size() < size_t(kWidth)) {
            size_t widest = slots.size();
            for (size_t s = 0; s < slots.size(); ++s)
                if (tree[slots[s]].light == kNone && (widest == slots.size() || tree[slots[s]].count > tree[slots[widest]].count))
                    widest = s;
            if (widest == slots.size()) break;  // all leaves
            const Binary& b = tree[slots[widest]];
            slots[widest] = b.left;
            slots.insert(slots.begin() + std::ptrdiff_t(widest) + 1, b.right);
        }
    }
    const uint32_t index = uint32_t(nodes_.size());
    nodes_.emplace_back();
    depth_ = std::max(depth_, depth);
    for (size_t s = 0; s < slots.size(); ++s) {
        const Binary& b = tree[slots[s]];
        const int c = int(s);
        Node& node = nodes_[index];
        node.cx[c] = 0.5f * (b.bounds.box.lo.x + b.bounds.box.hi.x);
        node.cy[c] = 0.5f * (b.bounds.box.lo.y + b.bounds.box.hi.y);
        node.cz[c] = 0.5f * (b.bounds.box.lo.z + b.bounds.box.hi.z);
        node.hx[c] = 0.5f * (b.bounds.box.hi.x - b.bounds.box.lo.x);
        node.hy[c] = 0.5f * (b.bounds.box.hi.y - b.bounds.box.lo.y);
        node.hz[c] = 0.5f * (b.bounds.box.hi.z - b.bounds.box.lo.z);
        node.radius2[c] = node.hx[c] * node.hx[c] + node.hy[c] * node.hy[c] + node.hz[c] * node.hz[c];
        node.radius[c] = std::sqrt(node.radius2[c]);
        node.ax[c] = b.bounds.axis.x;
        node.ay[c] = b.bounds.axis.y;
        node.az[c] = b.bounds.axis.z;
        node.cosO[c] = b.bounds.cosThetaO;
        node.sinO[c] = std::sqrt(std::max(0.f, 1.f - b.bounds.cosThetaO * b.bounds.cosThetaO));
        node.cosE[c] = b.bounds.cosThetaE;
        node.power[c] = b.power;
        node.twoSided[c] = b.bounds.twoSided;
        // thetaO + thetaE <= pi/2, both in [0, pi/2]: cos(thetaO + thetaE) >= 0.
        const float sinE = std::sqrt(std::max(0.f, 1.f - node.cosE[c] * node.cosE[c]));
        node.halfSpace[c] = !b.bounds.twoSided && node.cosO[c] >= 0.f && node.cosE[c] >= 0.f &&
                            node.cosO[c] * node.cosE[c] - node.sinO[c] * sinE >= 0.f;
        node.leaf[c] = b.light != kNone;
        if (node.leaf[c]) {
            node.child[c] = b.light;
            leaves_[b.light] = Place{index, uint32_t(c)};
        }
    }
    nodes_[index].parent = parent;
    nodes_[index].parentSlot = parentSlot;
    for (size_t s = 0; s < slots.size(); ++s)
        if (tree[slots[s]].light == kNone) {
            const uint32_t child = collapse(tree, slots[s], index, uint32_t(s), depth + 1);
            nodes_[index].child[s] = child;
        }
    return index;
}

}  // namespace penumbra
