// The O(N) reference accelerator: every query tests every primitive with the
// same core routines the Embree user geometries call. It is the ground truth
// the Embree agreement tests compare against, and the benchmark baseline.
//
// Instances are tested as Embree tests them: the ray is taken into the
// prototype's object space (origin and direction by objectFromWorld, the
// direction not renormalised, so t means the same distance along the ray in
// both spaces) and meets the prototype's triangles there.
//
// A candidate hit on a surface that can cut out counts only where the alpha
// rule (accel/alpha_test.h) says the surface is there, as Embree's filters do.
#include <cmath>

#include "accel/accelerator.h"

namespace penumbra {
namespace {

class NaiveAccelerator final : public Accelerator {
public:
    NaiveAccelerator(const Scene& scene, std::shared_ptr<const TextureCache> textures)
        : Accelerator(scene, std::move(textures)) {}

    std::unique_ptr<Accelerator> edited(const Scene& scene, std::shared_ptr<const void>) const override {
        return std::make_unique<NaiveAccelerator>(scene, textures_);
    }

    // Whether the candidate hit h on `ref` counts: the alpha rule, where the surface can cut out.
    bool present(const Ray& world, const Ray& local, const PrimRef& ref, const PrimHit& h) const {
        return !alpha_.any() || alpha_.present(local, ref, h.t, h.u, h.v, alphaRayKey(world));
    }

    std::optional<PrimIntersection> intersectPrim(const Ray& ray) const override {
        if (!acceptRay(ray)) return std::nullopt;
        // The query interval shrinks to the closest hit so far, so each test
        // answers "closer than everything before" exactly as Embree's tfar
        // does. Planes come last, as in the Embree accelerator (which tests
        // them after its BVH query), so both break exact ties the same way.
        Ray r = ray;
        std::optional<PrimIntersection> best;
        auto consider = [&](ShapeKind kind, size_t object, uint32_t prim, const std::optional<PrimHit>& h,
                            uint32_t part = 0) {
            if (!h) return;
            const PrimRef ref{kind, static_cast<uint32_t>(object), prim, part};
            if (!present(ray, r, ref, *h)) return;
            r.tfar = h->t;
            best = PrimIntersection{ref, h->t, h->u, h->v};
        };
        const Scene& s = scene_;
        for (size_t i = 0; i < s.spheres.size(); ++i) consider(ShapeKind::Sphere, i, 0, penumbra::intersect(s.spheres[i], r));
        for (size_t i = 0; i < s.boxes.size(); ++i) consider(ShapeKind::Box, i, 0, penumbra::intersect(s.boxes[i], r));
        for (size_t i = 0; i < s.rectangles.size(); ++i)
            consider(ShapeKind::Rectangle, i, 0, penumbra::intersect(s.rectangles[i], r));
        for (size_t i = 0; i < s.disks.size(); ++i) consider(ShapeKind::Disk, i, 0, penumbra::intersect(s.disks[i], r));
        for (size_t m = 0; m < s.meshes.size(); ++m) {
            const TriangleMesh& mesh = s.meshes[m];
            const size_t n = mesh.triangleCount();
            for (size_t t = 0; t < n; ++t) {
                Vec3f p0, p1, p2;
                mesh.vertices(t, p0, p1, p2);
                consider(ShapeKind::Mesh, m, static_cast<uint32_t>(t), intersectTriangle(p0, p1, p2, r));
            }
        }
        for (size_t i = 0; i < s.instances.size(); ++i) {
            const Instance& in = s.instances[i];
            const auto& parts = s.prototypes[in.prototype].meshes;
            Ray o = objectRay(in, r);
            for (size_t k = 0; k < parts.size(); ++k) {
                const size_t n = parts[k].triangleCount();
                for (size_t t = 0; t < n; ++t) {
                    Vec3f p0, p1, p2;
                    parts[k].vertices(t, p0, p1, p2);
                    consider(ShapeKind::Instance, i, static_cast<uint32_t>(t), intersectTriangle(p0, p1, p2, o),
                             static_cast<uint32_t>(k));
                    o.tfar = r.tfar;
                }
            }
        }
        for (size_t i = 0; i < s.planes.size(); ++i) consider(ShapeKind::Plane, i, 0, penumbra::intersect(s.planes[i], r));
        return best;
    }

    bool occluded(const Ray& ray) const override {
        if (!acceptRay(ray)) return false;
        // Occlusion is the open interval (tnear, tfar); the shape tests accept
        // t <= tfar, and the float just below tfar turns that into t < tfar.
        Ray r = ray;
        r.tfar = nextFloatDown(ray.tfar);
        const Scene& s = scene_;
        for (const auto& p : s.planes)
            if (penumbra::intersect(p, r)) return true;
        for (const auto& x : s.spheres)
            if (penumbra::intersect(x, r)) return true;
        for (const auto& x : s.boxes)
            if (penumbra::intersect(x, r)) return true;
        for (size_t i = 0; i < s.rectangles.size(); ++i) {
            const auto h = penumbra::intersect(s.rectangles[i], r);
            if (h && present(ray, r, PrimRef{ShapeKind::Rectangle, uint32_t(i), 0}, *h)) return true;
        }
        for (const auto& x : s.disks)
            if (penumbra::intersect(x, r)) return true;
        for (size_t m = 0; m < s.meshes.size(); ++m) {
            const TriangleMesh& mesh = s.meshes[m];
            const size_t n = mesh.triangleCount();
            for (size_t t = 0; t < n; ++t) {
                Vec3f p0, p1, p2;
                mesh.vertices(t, p0, p1, p2);
                const auto h = intersectTriangle(p0, p1, p2, r);
                if (h && present(ray, r, PrimRef{ShapeKind::Mesh, uint32_t(m), uint32_t(t)}, *h)) return true;
            }
        }
        for (size_t i = 0; i < s.instances.size(); ++i) {
            const Instance& in = s.instances[i];
            const Ray o = objectRay(in, r);
            const auto& parts = s.prototypes[in.prototype].meshes;
            for (size_t k = 0; k < parts.size(); ++k) {
                const size_t n = parts[k].triangleCount();
                for (size_t t = 0; t < n; ++t) {
                    Vec3f p0, p1, p2;
                    parts[k].vertices(t, p0, p1, p2);
                    const auto h = intersectTriangle(p0, p1, p2, o);
                    const PrimRef ref{ShapeKind::Instance, uint32_t(i), uint32_t(t), uint32_t(k)};
                    if (h && present(ray, o, ref, *h)) return true;
                }
            }
        }
        return false;
    }

    // The world ray in the instance's object space, same interval.
    static Ray objectRay(const Instance& in, const Ray& r) {
        Ray o = r;
        o.o = in.objectFromWorld.applyPoint(r.o);
        o.d = in.objectFromWorld.applyVector(r.d);
        return o;
    }

    std::string name() const override { return "naive"; }

    /// The naive loop builds nothing.
    size_t memoryBytes() const override { return 0; }
};

}  // namespace

std::unique_ptr<Accelerator> makeNaiveAccelerator(const Scene& scene, std::shared_ptr<const TextureCache> textures) {
    return std::make_unique<NaiveAccelerator>(scene, std::move(textures));
}

}  // namespace penumbra
