// A light hierarchy (Conty Estevez & Kulla 2018, "Importance sampling of many
// lights with adaptive tree splitting"; pbrt-v4's BVHLightSampler has the same
// shape): a tree over the lights that have bounds, each node holding, for
// each of its children, the box, the emission cone and the summed power of
// its lights. A shading point descends from the root, choosing a child in
// proportion to its importance there, a cheap estimate of the light it sends
// to the point (power, distance, the emitters' orientation, the point's
// normal); the number u is rescaled at each level so one number makes every
// choice. The probability of a light is the product of the choices on its
// path, which probability() retraces from the light's place in the tree
// (its leaf and the nodes above it), computing the same numbers in the same
// order as pick(), so the MIS weights of BSDF samples that reach a light use
// exactly the probability with which it is picked.
//
// Built as a binary tree by binned splits that minimise the paper's cost,
// power x orientation measure x box area (deeper than kMaxSplitDepth levels,
// by halving the count), then collapsed to nodes of up to kWidth children,
// whose importances are computed together as the lanes of one loop: half the
// levels of the binary tree, and the children of a level at the cost of one.
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
    /// Children per node.
    static constexpr int kWidth = 4;
    /// Deeper than this, the binary tree's nodes are split in half by count.
    static constexpr uint32_t kMaxSplitDepth = 32;

    /// The tree over lights j with bounds[j] inside the accelerators' range
    /// (coordinates within +-1.8e18) and a positive powers[j] (NaN and
    /// non-positive powers leave a light out, infinite ones count as the
    /// largest float, and lights weaker than 1e-20 of the strongest count as
    /// none: they cannot be told from rounding).
    LightBVH(std::span<const std::optional<LightBounds>> bounds, std::span<const double> powers);

    bool empty() const { return nodes_.empty(); }
    /// Whether light j is in the tree.
    bool holds(size_t j) const { return j < leaves_.size() && leaves_[j].node != kNone; }
    /// Levels of nodes (1: the root holds every light).
    uint32_t depth() const { return depth_; }

    /// A light picked at p (geometric normal n; zero: no receiver term) with
    /// u in [0, 1): its index, probability (0 where the descent meets a node
    /// none of whose children can reach the point; index is then 0) and u
    /// rescaled.
    LightPicker::Pick pick(float u, const Vec3f& p, const Vec3f& n) const;
    /// The probability that pick() at (p, n) returns light j (0 for lights
    /// not in the tree).
    float probability(size_t j, const Vec3f& p, const Vec3f& n) const;

private:
    static constexpr uint32_t kNone = ~0u;
    // A node: its children's bounds as arrays over the children (absent
    // children have no power), and where each leads.
    struct Node {
        float cx[kWidth], cy[kWidth], cz[kWidth];  // box centre
        float hx[kWidth], hy[kWidth], hz[kWidth];  // box half extents
        float radius2[kWidth], radius[kWidth];     // the box's bounding sphere
        float ax[kWidth], ay[kWidth], az[kWidth];  // emission cone: axis, thetaO, thetaE
        float cosO[kWidth], sinO[kWidth], cosE[kWidth];
        float power[kWidth];                       // normalised: the strongest light has 1
        int32_t twoSided[kWidth];
        int32_t halfSpace[kWidth];  // every emitter sends light only into the half-space the axis faces
        uint32_t child[kWidth];     // a node, or for a leaf the light's index
        bool leaf[kWidth];
        uint32_t parent;       // kNone for the root
        uint32_t parentSlot;   // this node's place among its parent's children
    };
    struct Place {
        uint32_t node = kNone, slot = 0;
    };
    struct Binary;

    /// The importance of each child of `node` at (p, n), up to one factor
    /// common to all of them (out[c] >= 0; 0 for absent children): power
    /// times the cosines at the emitters and at the receiver, each widened by
    /// the angle the child's bounding sphere subtends, over the squared
    /// distance (the sphere's radius within it). 0 only where none of the
    /// child's lights can send light above n at p: where those angles rule
    /// it out, or its box lies wholly below p's tangent plane or (emitters
    /// that all face one half-space) wholly in front of p, which the angles
    /// cannot tell from inside the sphere.
    static void importances(const Node& node, const Vec3f& p, const Vec3f& n, float (&out)[kWidth]);

    uint32_t collapse(const std::vector<Binary>& tree, uint32_t root, uint32_t parent, uint32_t parentSlot,
                      uint32_t depth);

    std::vector<Node> nodes_;
    std::vector<Place> leaves_;  // per light of the set: its leaf's node and slot
    uint32_t depth_ = 0;
};

}  // namespace penumbra
