#include "accel/shape_bounds.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/instance.h"

namespace penumbra {

ShapeBounds::ShapeBounds(const Scene& scene) {
    const size_t shapes = scene.spheres.size() + scene.boxes.size() + scene.rectangles.size() + scene.disks.size() +
                          scene.meshes.size() + scene.instances.size();
    if (shapes > kMaxShapes) return;
    const auto addBox = [&](const Bounds3f& b, PrimRef ref) {
        if (b.empty()) return;  // nothing a ray can meet
        const float pad = 2e-6f * std::max(1.f, std::max(maxAbsComponent(b.lo), maxAbsComponent(b.hi)));
        boxes_.push_back({Bounds3f{b.lo - Vec3f(pad), b.hi + Vec3f(pad)}, ref});
    };
    for (uint32_t i = 0; i < scene.boxes.size(); ++i) addBox(bounds(scene.boxes[i]), PrimRef{ShapeKind::Box, i, 0, 0});
    for (uint32_t i = 0; i < scene.rectangles.size(); ++i)
        addBox(bounds(scene.rectangles[i]), PrimRef{ShapeKind::Rectangle, i, 0, 0});
    for (uint32_t i = 0; i < scene.disks.size(); ++i) addBox(bounds(scene.disks[i]), PrimRef{ShapeKind::Disk, i, 0, 0});
    for (uint32_t i = 0; i < scene.meshes.size(); ++i)
        addBox(bounds(scene.meshes[i]), PrimRef{ShapeKind::Mesh, i, 0, 0});
    // Each prototype's box once (a pass over its vertices), however many instances place it.
    std::vector<std::optional<Bounds3f>> prototypeBounds(scene.prototypes.size());
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& in = scene.instances[i];
        if (in.prototype >= scene.prototypes.size()) continue;
        std::optional<Bounds3f>& object = prototypeBounds[in.prototype];
        if (!object) object = scene.prototypes[in.prototype].bounds();
        addBox(instanceBounds(*object, in.worldFromObject), PrimRef{ShapeKind::Instance, i, 0, 0});
    }
    for (uint32_t i = 0; i < scene.spheres.size(); ++i) {
        const Sphere& s = scene.spheres[i];
        const float pad = 1e-5f * (std::max(1.f, maxAbsComponent(s.center)) + s.radius);
        Sphere padded = s;
        padded.radius = s.radius + pad;
        spheres_.push_back(padded);
        sphereRefs_.push_back(PrimRef{ShapeKind::Sphere, i, 0, 0});
    }
    planes_ = scene.planes;
    bool finite = true;
    for (const PaddedBox& b : boxes_) finite = finite && isFinite(b.box.lo) && isFinite(b.box.hi);
    for (const Sphere& s : spheres_) finite = finite && isFinite(s.center) && std::isfinite(s.radius);
    for (const Plane& p : planes_) finite = finite && isFinite(p.point) && isFinite(p.normal);
    available_ = finite;  // else the bounds could hide a hit
}

bool ShapeBounds::segmentsClear(const Vec3f& origin, const Targets& targets, std::optional<PrimRef> except) const {
    if (!available_) return false;
    // Every segment lies in the box of the origin and the targets.
    Bounds3f hull = targets.box;
    hull.extend(origin);
    const float scale = std::max({1.f, maxAbsComponent(hull.lo), maxAbsComponent(hull.hi)});
    if (!(scale < kInfinity)) return false;  // NaN or infinite: unsure
    // A plane: the origin and the targets' sphere on one side of it, clear of it by far more than rounding.
    for (const Plane& p : planes_) {
        const float n = length(p.normal);
        const float margin = 1e-5f * scale * n;
        const float o = dot(origin - p.point, p.normal), c = dot(targets.center - p.point, p.normal);
        const float reach = targets.radius * n + margin;
        if (!((o > margin && c > reach) || (o < -margin && c < -reach))) return false;
    }
    for (const PaddedBox& b : boxes_) {
        if (except && b.ref == *except) continue;
        const Bounds3f& x = b.box;
        if (!(x.lo.x > hull.hi.x || x.lo.y > hull.hi.y || x.lo.z > hull.hi.z || x.hi.x < hull.lo.x ||
              x.hi.y < hull.lo.y || x.hi.z < hull.lo.z))
            return false;
    }
    // Spheres: the cone from the origin that holds the targets' sphere (as
    // long as its far side), against each sphere whose box the segments' box
    // meets: clear of it where the angle between the cone's axis and the
    // sphere's centre exceeds the cone's half-angle plus the sphere's angular
    // radius (by 1e-5 rad), compared through their cosines and sines. In
    // double: the margins stay far above the rounding.
    bool cone = false;
    double ax = 0, ay = 0, az = 0, cosA = 1, sinA = 0, reach = 0;
    for (size_t i = 0; i < spheres_.size(); ++i) {
        const Sphere& s = spheres_[i];
        if (except && sphereRefs_[i] == *except) continue;
        const Vec3f c = s.center;
        const float r = s.radius;
        if (c.x - r > hull.hi.x || c.y - r > hull.hi.y || c.z - r > hull.hi.z || c.x + r < hull.lo.x ||
            c.y + r < hull.lo.y || c.z + r < hull.lo.z)
            continue;
        if (!cone) {
            ax = double(targets.center.x) - origin.x, ay = double(targets.center.y) - origin.y,
            az = double(targets.center.z) - origin.z;
            const double len = std::sqrt(ax * ax + ay * ay + az * az);
            const double tr = double(targets.radius) * (1.0 + 1e-5) + 1e-5 * scale;
            if (!(len > 2.0 * tr)) return false;  // a cone that wide is no bound worth having
            ax /= len, ay /= len, az /= len;
            sinA = tr / len;
            cosA = std::sqrt(1.0 - sinA * sinA);
            reach = len + tr;
            cone = true;
        }
        const double vx = double(c.x) - origin.x, vy = double(c.y) - origin.y, vz = double(c.z) - origin.z;
        const double dist = std::sqrt(vx * vx + vy * vy + vz * vz);
        const double rr = double(r) + 1e-5 * scale;
        if (!(dist > rr)) return false;  // the origin in or at the sphere
        if (dist - rr > reach) continue;  // beyond every target
        const double sinB = rr / dist, cosB = std::sqrt(1.0 - sinB * sinB);
        // cos and sin of a + b (a < pi/6, b < pi/2), then the cosine of a + b + 1e-5.
        const double cosAB = cosA * cosB - sinA * sinB, sinAB = sinA * cosB + cosA * sinB;
        if (!((vx * ax + vy * ay + vz * az) / dist < cosAB - 1e-5 * sinAB - 1e-9)) return false;
    }
    return true;
}

}  // namespace penumbra
