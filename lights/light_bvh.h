// A light hierarchy (Conty Estevez & Kulla 2018, "Importance sampling of many
// lights with adaptive tree splitting"; pbrt-v4's BVHLightSampler has the same
// shape): a binary tree over the lights that have bounds, each node holding
// the bounding sphere, the emission cone and the summed power of its lights.
// A shading point descends from the root, choosing each child in proportion
// to its importance there, a cheap estimate of the light it sends to the
// point (power, distance, the emitters' orientation, the point's normal);
// the number u is rescaled at each level so one number makes every choice.
// The probability of a light is the product of the choices on its path,
// which probability() retraces from the light's bit trail (its left/right
// turns), computing the same numbers in the same order as pick(), so the MIS
// weights of BSDF samples that reach a light use exactly the probability with
// which it is picked.
//
// Built by binned splits that minimise the paper's cost, power x orientation
// measure x box area, along the axis of the largest extent-normalised gain;
// deeper than kMaxSplitDepth levels, by halving the count, so no trail is
// longer than 64 turns.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "lights/light_bounds.h"
#include "lights/light_picker.h"

namespace penumbra {

class LightBVH {
public:
    /// The tree over lights j with bounds[j] and a positive, finite or
    /// infinite powers[j] (NaN and non-positive powers leave a light out; an
    /// infinite one counts as the largest float).
    LightBVH(std::span<const std::optional<LightBounds>> bounds, std::span<const double> powers);

    bool empty() const { return nodes_.empty(); }
    /// Whether light j is in the tree.
    bool holds(size_t j) const { return j < trails_.size() && trails_[j].depth != kNotHeld; }
    /// Levels below the root (0: a single light).
    uint32_t depth() const { return depth_; }

    /// A light picked at p (geometric normal n; zero: no receiver term) with
    /// u in [0, 1): its index, probability (0: no light of the tree can reach
    /// the point by the importance bound; index is then 0) and u rescaled.
    LightPicker::Pick pick(float u, const Vec3f& p, const Vec3f& n) const;
    /// The probability that pick() at (p, n) returns light j (0 for lights
    /// not in the tree).
    float probability(size_t j, const Vec3f& p, const Vec3f& n) const;

    /// The importance of the whole tree's light at (p, n), for tests.
    double rootImportance(const Vec3f& p, const Vec3f& n) const {
        return empty() ? 0.0 : importance(nodes_[0], p, n);
    }

    /// Deeper than this, nodes are split in half by count.
    static constexpr uint32_t kMaxSplitDepth = 32;

private:
    struct Node {
        Vec3f center;   // the box: its centre and half extents
        Vec3f half;
        float radius2, radius;  // its bounding sphere's squared radius and radius
        Vec3f axis;     // emission cone
        float cosThetaO, sinThetaO, cosThetaE;
        float power;    // normalised: the strongest light has 1
        uint32_t link;  // leaf: the light's index; else the second child (the first follows the node)
        bool leaf;
        bool twoSided;
        bool halfSpace;  // every emitter sends light only into the half-space axis faces
    };
    struct Trail {
        uint64_t turns = 0;  // bit k: the second child at level k
        uint32_t depth = kNotHeld;
    };
    struct Item;
    static constexpr uint32_t kNotHeld = ~0u;

    /// An upper estimate of the light the node's lights give p: power times
    /// the cosines at the emitters and at the receiver, each widened by the
    /// angle the node's bounding sphere subtends, over the squared distance.
    /// 0 only where no light of the node can send light above n at p: where
    /// those widened angles rule it out, or its box lies wholly below p's
    /// tangent plane or (one-sided emitters facing one half-space) wholly in
    /// front of p, which the angles cannot tell from inside the sphere.
    static double importance(const Node& node, const Vec3f& p, const Vec3f& n);
    /// The share of the first of two children with importances a and b.
    static float firstShare(double a, double b);

    struct Built {
        LightBounds bounds;
        float power;
    };
    Built build(std::span<Item> items, uint64_t turns, uint32_t depth);
    static size_t split(std::span<Item> items, uint32_t depth);

    std::vector<Node> nodes_;
    std::vector<Trail> trails_;  // per light of the set
    uint32_t depth_ = 0;
};

}  // namespace penumbra
