// The analytic shapes the Embree accelerator tests itself, over a packet's
// lanes as arrays, instead of handing them to Embree: the planes always
// (infinite: no box a BVH could hold), and the spheres and boxes of a scene of
// few shapes. Embree's call has a fixed cost per packet, and each
// user-geometry leaf it visits a callback; a handful of branch-free tests over
// 16 lanes costs less than either, and a packet whose lanes meet nothing
// Embree holds then skips its call (figures: docs/accelerators.md, "Few
// spheres and boxes are tested over the lanes"). Each test is the
// core/shapes.h routine the naive loop runs, so the two accelerators agree on
// these shapes bit for bit.
#pragma once

#include <cstdint>
#include <vector>

#include "accel/shape_bounds.h"
#include "core/scene.h"
#include "core/shapes.h"

namespace penumbra {

class LaneShapes {
public:
    /// fewShapes: the scene has few shapes in all (ShapeBounds::available,
    /// at most 8), so that what Embree keeps is small and most packets skip
    /// it. Elsewhere every packet would pay these tests and Embree's call
    /// too (docs/accelerators.md has the figures).
    LaneShapes(const Scene& scene, bool fewShapes) {
        spheresAndBoxes_ = fewShapes;
        if (spheresAndBoxes_) {
            spheres_ = scene.spheres;
            boxes_ = scene.boxes;
            for (const Box& b : boxes_) boxSpheres_.push_back(boundingSphere(b));
        }
        planes_ = scene.planes;
        for (size_t i = 0; i < spheres_.size(); ++i) refs_.push_back(PrimRef{ShapeKind::Sphere, uint32_t(i), 0});
        for (size_t i = 0; i < boxes_.size(); ++i) refs_.push_back(PrimRef{ShapeKind::Box, uint32_t(i), 0});
        for (size_t i = 0; i < planes_.size(); ++i) refs_.push_back(PrimRef{ShapeKind::Plane, uint32_t(i), 0});
    }

    /// Whether the scene's spheres and boxes are tested here: Embree must leave them out.
    bool holdsSpheresAndBoxes() const { return spheresAndBoxes_; }

    /// The shape a hit index of closest() names (u = v = 0: these shapes' hits carry none).
    PrimRef ref(int hit) const { return refs_[size_t(hit)]; }

    /// For each lane where valid[l] is set: the closest of these shapes' hits
    /// in (tnear, tfar], where there is one, shrinks tfar to it and sets
    /// hit[l] to its index; other lanes keep both. Planes last, as ever.
    template <int W, class PacketRay>
    [[gnu::always_inline]] void closest(PacketRay& p, const int* valid, int* hit) const {
        eachShapeNear<W>(p, valid, [&](int index, const auto& distance) __attribute__((always_inline)) {
            closestOf<W>(index, p, valid, hit, distance);
        });
    }

    /// blocked[l] |= 1 for each lane whose (tnear, tfar] holds one of these shapes' hits.
    template <int W, class PacketRay>
    [[gnu::always_inline]] void occlude(const PacketRay& p, int* blocked) const {
        eachShapeNear<W>(p, nullptr, [&](int, const auto& distance) __attribute__((always_inline)) {
            occludeBy<W>(blocked, distance);
        });
    }

    /// closest() for one ray: its hit index or -1; shrinks r.tfar to the hit.
    int closest(Ray& r) const {
        OneRay p(r);
        const int valid = 1;
        int hit = -1;
        closest<1>(p, &valid, &hit);
        r.tfar = p.tfar[0];
        return hit;
    }

    /// occlude() for one ray.
    bool occludes(const Ray& r) const {
        int blocked = 0;
        occlude<1>(OneRay(r), &blocked);
        return blocked != 0;
    }

private:
    // One ray as a packet of one lane, for the single-ray queries.
    struct OneRay {
        float org_x[1], org_y[1], org_z[1], dir_x[1], dir_y[1], dir_z[1], tnear[1], tfar[1];
        explicit OneRay(const Ray& r)
            : org_x{r.o.x}, org_y{r.o.y}, org_z{r.o.z}, dir_x{r.d.x}, dir_y{r.d.y}, dir_z{r.d.z}, tnear{r.tnear},
              tfar{r.tfar} {}
    };

    // visit(index, distance) for each shape some lane (of `valid`, or any)
    // may meet, in the order of the hit indices (spheres, boxes, planes);
    // distance(l) is lane l's hit distance, as the core/shapes.h routine
    // finds it. Spheres and boxes no lane passes near are skipped
    // (anyLaneNear); an axis-aligned box's lanes share the reciprocals, and
    // the form is picked per box, so that no loop over the lanes branches.
    template <int W, class PacketRay, class Visit>
    [[gnu::always_inline]] void eachShapeNear(const PacketRay& p, const int* valid, const Visit& visit) const {
        int index = 0;
        for (const Sphere s : spheres_) {  // copies: the lanes' stores cannot change them, so the loops vectorise
            if (anyLaneNear<W>(s, p, valid))
                visit(index, [&](int l) {
                    return sphereHitDistance(s, p.org_x[l], p.org_y[l], p.org_z[l], p.dir_x[l], p.dir_y[l],
                                             p.dir_z[l], p.tnear[l], p.tfar[l]);
                });
            ++index;
        }
        if (const uint32_t near = lanesNearBoxes<W>(p, valid)) {
            const Reciprocals<W> inv(p);
            for (size_t i = 0; i < boxes_.size(); ++i) {
                const Box b = boxes_[i];
                if (!(near >> i & 1u)) continue;
                if (b.identity)
                    visit(index + int(i), alignedBoxDistance<W>(b, p, inv));
                else
                    visit(index + int(i), transformedBoxDistance(b, p));
            }
        }
        index += int(boxes_.size());
        for (const Plane q : planes_)
            visit(index++, [&](int l) {
                return planeHitDistance(q, p.org_x[l], p.org_y[l], p.org_z[l], p.dir_x[l], p.dir_y[l], p.dir_z[l],
                                        p.tnear[l], p.tfar[l]);
            });
    }

    // The lanes' slabReciprocal direction components, computed once for all
    // the axis-aligned boxes (the same values each box's test would compute).
    template <int W>
    struct Reciprocals {
        alignas(64) float x[W], y[W], z[W];
        template <class PacketRay>
        [[gnu::always_inline]] explicit Reciprocals(const PacketRay& p) {
            for (int l = 0; l < W; ++l) {
                x[l] = slabReciprocal(p.dir_x[l]);
                y[l] = slabReciprocal(p.dir_y[l]);
                z[l] = slabReciprocal(p.dir_z[l]);
            }
        }
    };

    // Lane l's distance to box b, as boxHitDistance finds it: an axis-aligned
    // box's with the shared reciprocals, another's in its object space. Two
    // forms, picked per box, so that neither loop over the lanes branches.
    template <int W, class PacketRay>
    [[gnu::always_inline]] static auto alignedBoxDistance(const Box& b, const PacketRay& p, const Reciprocals<W>& inv) {
        return [&b, &p, &inv](int l) {
            return boxHitDistanceInObjectSpace(b, p.org_x[l], p.org_y[l], p.org_z[l], p.dir_x[l], p.dir_y[l],
                                               p.dir_z[l], inv.x[l], inv.y[l], inv.z[l], p.tnear[l], p.tfar[l]);
        };
    }
    template <class PacketRay>
    [[gnu::always_inline]] static auto transformedBoxDistance(const Box& b, const PacketRay& p) {
        return [&b, &p](int l) {
            return boxHitDistanceTransformed(b, p.org_x[l], p.org_y[l], p.org_z[l], p.dir_x[l], p.dir_y[l],
                                             p.dir_z[l], p.tnear[l], p.tfar[l]);
        };
    }

    // Whether the line of some lane (of `valid`, or any) may pass within
    // sphere s: a packet where none does skips the exact test and its
    // divisions and square root (most packets meet one sphere at most). The
    // line's squared distance from the centre times a = |d|^2 is
    // a |f|^2 - b^2 (f = o - centre, b = f.d), no division; its rounding is
    // a few ulps of a |f|^2, and the margin, 1e-5 of that, lies far above it,
    // so no lane the exact test could hit is ever left out. NaN counts as near.
    template <int W, class PacketRay>
    [[gnu::always_inline]] static bool anyLaneNear(const Sphere& s, const PacketRay& p, const int* valid) {
        const float r2 = s.radius * s.radius;
        int near = 0;
        for (int l = 0; l < W; ++l) {
            const float fx = p.org_x[l] - s.center.x, fy = p.org_y[l] - s.center.y, fz = p.org_z[l] - s.center.z;
            const float dx = p.dir_x[l], dy = p.dir_y[l], dz = p.dir_z[l];
            const float a = dx * dx + dy * dy + dz * dz, b = fx * dx + fy * dy + fz * dz;
            const float af = a * (fx * fx + fy * fy + fz * fz);
            const int close = int(!(af - b * b - a * r2 > 1e-5f * af));
            near |= valid ? valid[l] & close : close;
        }
        return near != 0;
    }

    // Bit i set where some lane may meet box i: its line passes near the
    // box's bounding sphere (anyLaneNear). None: the packet skips the boxes
    // and the reciprocals' divisions.
    template <int W, class PacketRay>
    [[gnu::always_inline]] uint32_t lanesNearBoxes(const PacketRay& p, const int* valid) const {
        uint32_t near = 0;
        for (size_t i = 0; i < boxSpheres_.size(); ++i)
            near |= anyLaneNear<W>(boxSpheres_[i], p, valid) ? 1u << i : 0u;
        return near;
    }

    // A sphere round every corner of the box (its world bounds' centre and
    // half diagonal, grown by 1e-4: the test of a corner's distance rounds far
    // less), for lanesNearBoxes.
    static Sphere boundingSphere(const Box& b) {
        const Bounds3f box = bounds(b);
        if (box.empty()) return Sphere{Vec3f{0.f, 0.f, 0.f}, 0.f, 0};  // a box that meets nothing
        return Sphere{0.5f * (box.lo + box.hi), 0.5f * length(box.hi - box.lo) * (1.f + 1e-4f), 0};
    }

    // hit[l] and tfar of each valid lane where distance(l) finds a hit
    // (distance(l) is infinite where there is none, at most tfar where there is one).
    template <int W, class PacketRay, class Distance>
    [[gnu::always_inline]] static void closestOf(int index, PacketRay& p, const int* valid, int* hit,
                                                 const Distance& distance) {
        for (int l = 0; l < W; ++l) {
            const float t = distance(l);
            const bool closer = valid[l] && t < kInfinity;
            hit[l] = closer ? index : hit[l];
            p.tfar[l] = closer ? t : p.tfar[l];
        }
    }

    template <int W, class Distance>
    [[gnu::always_inline]] static void occludeBy(int* blocked, const Distance& distance) {
        for (int l = 0; l < W; ++l) blocked[l] |= distance(l) < kInfinity;
    }

    bool spheresAndBoxes_ = false;
    std::vector<Sphere> spheres_;  // empty unless spheresAndBoxes_
    std::vector<Box> boxes_;       // empty unless spheresAndBoxes_
    std::vector<Sphere> boxSpheres_;  // boundingSphere of each box
    std::vector<Plane> planes_;
    std::vector<PrimRef> refs_;    // spheres, boxes, planes: closest()'s hit indices
};

}  // namespace penumbra
