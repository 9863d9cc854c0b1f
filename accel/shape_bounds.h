// The bounds of each shape of a scene of a few shapes, padded, for telling
// cheaply that rays or whole sets of shadow rays meet nothing: a sphere as
// itself, every other shape (a mesh or an instance whole) as its box.
//
// The pad, 2e-6 of the shape's coordinates (1e-5 for spheres, whose test
// rounds more), is far above the rounding of the accelerators' hits (a few
// ulps, 1e-7 of the coordinates) and of the tests, and below the offset at
// which a ray leaves a surface (1.5e-5 of the point's coordinates, at least
// 1.5e-5: core/ray.h): a shadow ray leaving a wall of a room 7 units wide
// does not meet that wall's box.
#pragma once

#include <optional>
#include <vector>

#include "core/hit.h"
#include "core/math.h"
#include "core/scene.h"

namespace penumbra {

class ShapeBounds {
public:
    /// At most kMaxShapes shapes (spheres, boxes, rectangles, disks, meshes
    /// and instances; infinite planes are not counted), or none are kept:
    /// the tests' cost grows with them and their gain falls (figures:
    /// docs/accelerators.md, "Occlusion packets skip what meets no shape's bounds").
    static constexpr size_t kMaxShapes = 8;

    explicit ShapeBounds(const Scene& scene);

    /// Whether the bounds are kept (few shapes, all finite).
    bool available() const { return available_; }

    struct PaddedBox {
        Bounds3f box;
        PrimRef ref;
    };
    const std::vector<PaddedBox>& boxes() const { return boxes_; }
    const std::vector<Sphere>& spheres() const { return spheres_; }  // radius padded

    /// Where segments end: a box and a sphere that both hold every end point.
    struct Targets {
        Bounds3f box;
        Vec3f center;
        float radius;
    };
    /// Whether every segment from `origin` to a point of `targets` certainly
    /// meets no shape and no plane, `except` (a rectangle or disk the targets
    /// lie on) aside: then shadow rays from origin to points of a light on
    /// `except`, stopping short of it, need no query. Tests the box of the
    /// segments against each shape's box, and where a sphere's box is met, the
    /// cone from origin that holds the targets' sphere against the sphere.
    /// False where unsure, and always where the bounds are not kept. Cheap
    /// next to the 16 shadow rays it may spare: no trigonometry, four square
    /// roots per sphere met.
    bool segmentsClear(const Vec3f& origin, const Targets& targets, std::optional<PrimRef> except) const;

private:
    bool available_ = false;
    std::vector<PaddedBox> boxes_;
    std::vector<Sphere> spheres_;
    std::vector<PrimRef> sphereRefs_;
    std::vector<Plane> planes_;
};

}  // namespace penumbra
