// The Embree BVH accelerator (Embree 3.13, the only Embree user in Penumbra).
//
// Geometry layout, attached by ID so hits map back without a lookup table:
//   geomID 0..3   one user geometry per analytic kind (spheres, boxes,
//                 rectangles, disks), primID = index in that Scene array
//   geomID 4 + i  scene.meshes[i] as a native triangle mesh, primID = triangle
//
// Analytic shapes are user geometries whose callbacks call the very same
// core/shapes.h intersect() routines as the naive loop. Embree's native
// "sphere points" would be faster but are not exact spheres (they are
// ray-facing discs or curve approximations depending on the type), so the
// Embree and the naive accelerator would no longer agree on the reference.
//
// Planes are infinite and have no bounding box a BVH could hold, so they stay
// out of Embree and are tested analytically here, after the Embree closest-hit
// query (with tfar clipped to the Embree hit) and before the occlusion query.
// Both accelerators therefore return identical plane hits.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "accel/accelerator.h"
#include "accel/embree_device.h"
#include "accel/embree_packets.h"
#include "core/error.h"

namespace penumbra {
namespace {

constexpr unsigned kFirstMeshGeomId = 4;

// Which Scene array each user geometry serves, with its geomID and kind.
template <class Shape>
struct ShapeTraits;
template <>
struct ShapeTraits<Sphere> {
    static constexpr unsigned kGeomId = 0;
    static constexpr ShapeKind kKind = ShapeKind::Sphere;
    static const std::vector<Sphere>& of(const Scene& s) { return s.spheres; }
};
template <>
struct ShapeTraits<Box> {
    static constexpr unsigned kGeomId = 1;
    static constexpr ShapeKind kKind = ShapeKind::Box;
    static const std::vector<Box>& of(const Scene& s) { return s.boxes; }
};
template <>
struct ShapeTraits<Rectangle> {
    static constexpr unsigned kGeomId = 2;
    static constexpr ShapeKind kKind = ShapeKind::Rectangle;
    static const std::vector<Rectangle>& of(const Scene& s) { return s.rectangles; }
};
template <>
struct ShapeTraits<Disk> {
    static constexpr unsigned kGeomId = 3;
    static constexpr ShapeKind kKind = ShapeKind::Disk;
    static const std::vector<Disk>& of(const Scene& s) { return s.disks; }
};

// Embree only uses the hit normal for its own filters; Penumbra recomputes
// every normal in Scene::completeHit. These are cheap and unnormalised.
Vec3f hitNormal(const Scene&, const Sphere& s, const Ray& r, const PrimHit& h) { return r.o + h.t * r.d - s.center; }
Vec3f hitNormal(const Scene&, const Rectangle& q, const Ray&, const PrimHit&) { return cross(q.a, q.b); }
Vec3f hitNormal(const Scene&, const Disk& d, const Ray&, const PrimHit&) { return d.normal; }
Vec3f hitNormal(const Scene& scene, const Box& b, const Ray& r, const PrimHit& h) {
    // The face is found from the hit point; reuse the one routine that does it.
    const auto index = static_cast<uint32_t>(&b - scene.boxes.data());
    return scene.completeHit(r, PrimRef{ShapeKind::Box, index, 0}, h.t, h.u, h.v).ng;
}

inline Ray rayFromN(RTCRayN* rays, unsigned n, unsigned i) {
    Ray r;
    r.o = {RTCRayN_org_x(rays, n, i), RTCRayN_org_y(rays, n, i), RTCRayN_org_z(rays, n, i)};
    r.d = {RTCRayN_dir_x(rays, n, i), RTCRayN_dir_y(rays, n, i), RTCRayN_dir_z(rays, n, i)};
    r.tnear = RTCRayN_tnear(rays, n, i);
    r.tfar = RTCRayN_tfar(rays, n, i);
    return r;
}

// Callbacks of one analytic kind. The geometry user pointer is the Scene.
template <class Shape>
struct UserShapeCallbacks {
    static const Shape& shape(void* userPtr, unsigned primID) {
        return ShapeTraits<Shape>::of(*static_cast<const Scene*>(userPtr))[primID];
    }

    static void boundsFn(const RTCBoundsFunctionArguments* args) {
        Bounds3f b = bounds(shape(args->geometryUserPtr, args->primID));
        // A few ulps of slack: the box only decides whether the exact test
        // runs, and the disk/box bounds carry rounding of their own. Flat
        // shapes (axis-aligned rectangles) thereby get a non-zero thickness.
        const float pad = 1e-6f * std::max(maxAbsComponent(b.lo), maxAbsComponent(b.hi));
        RTCBounds* o = args->bounds_o;
        o->lower_x = b.lo.x - pad;
        o->lower_y = b.lo.y - pad;
        o->lower_z = b.lo.z - pad;
        o->upper_x = b.hi.x + pad;
        o->upper_y = b.hi.y + pad;
        o->upper_z = b.hi.z + pad;
    }

    static void intersectFn(const RTCIntersectFunctionNArguments* args) {
        const Scene& scene = *static_cast<const Scene*>(args->geometryUserPtr);
        const Shape& s = shape(args->geometryUserPtr, args->primID);
        const unsigned n = args->N;
        RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, n);
        RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, n);
        for (unsigned i = 0; i < n; ++i) {
            if (args->valid[i] == 0) continue;
            // The ray's tfar is the closest hit so far; intersect() only
            // reports t in (tnear, tfar], so a hit here is always closer.
            const Ray r = rayFromN(rays, n, i);
            const auto h = intersect(s, r);
            if (!h) continue;
            const Vec3f ng = hitNormal(scene, s, r, *h);
            RTCRayN_tfar(rays, n, i) = h->t;
            RTCHitN_Ng_x(hits, n, i) = ng.x;
            RTCHitN_Ng_y(hits, n, i) = ng.y;
            RTCHitN_Ng_z(hits, n, i) = ng.z;
            RTCHitN_u(hits, n, i) = h->u;
            RTCHitN_v(hits, n, i) = h->v;
            RTCHitN_primID(hits, n, i) = args->primID;
            RTCHitN_geomID(hits, n, i) = args->geomID;
            RTCHitN_instID(hits, n, i, 0) = RTC_INVALID_GEOMETRY_ID;
        }
    }

    static void occludedFn(const RTCOccludedFunctionNArguments* args) {
        const Shape& s = shape(args->geometryUserPtr, args->primID);
        const unsigned n = args->N;
        for (unsigned i = 0; i < n; ++i) {
            if (args->valid[i] == 0) continue;
            if (intersect(s, rayFromN(args->ray, n, i))) RTCRayN_tfar(args->ray, n, i) = -kInfinity;
        }
    }
};

RTCBuildQuality toEmbree(BuildQuality q) {
    switch (q) {
        case BuildQuality::Low: return RTC_BUILD_QUALITY_LOW;
        case BuildQuality::Medium: return RTC_BUILD_QUALITY_MEDIUM;
        case BuildQuality::High: return RTC_BUILD_QUALITY_HIGH;
    }
    return RTC_BUILD_QUALITY_HIGH;
}

const char* errorName(RTCError code) {
    switch (code) {
        case RTC_ERROR_NONE: return "no error";
        case RTC_ERROR_UNKNOWN: return "unknown error";
        case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
        case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
        case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
        case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
        case RTC_ERROR_CANCELLED: return "cancelled";
    }
    return "unknown error";
}

inline RTCRay toRtcRay(const Ray& r, float tfar) {
    RTCRay ray;
    ray.org_x = r.o.x;
    ray.org_y = r.o.y;
    ray.org_z = r.o.z;
    ray.tnear = r.tnear;
    ray.dir_x = r.d.x;
    ray.dir_y = r.d.y;
    ray.dir_z = r.d.z;
    ray.time = 0.f;
    ray.tfar = tfar;
    ray.mask = ~0u;
    ray.id = 0;
    ray.flags = 0;
    return ray;
}

class EmbreeAccelerator final : public Accelerator {
public:
    EmbreeAccelerator(const Scene& scene, BuildQuality quality) : Accelerator(scene) { build(toEmbree(quality)); }

    ~EmbreeAccelerator() override {
        // Release the scene while the device's callbacks can still reach us.
        rtcScene_.reset();
        device_.reset();
    }

    std::optional<PrimIntersection> intersectPrim(const Ray& ray) const override {
        if (!acceptRay(ray)) return std::nullopt;
        if (!(ray.tfar > ray.tnear)) return std::nullopt;  // empty interval (tnear, tfar]
        std::optional<PrimIntersection> best;
        Ray r = ray;
        if (hasEmbreeGeometry_) {
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            RTCRayHit rh;
            rh.ray = toRtcRay(ray, ray.tfar);
            rh.hit.Ng_x = rh.hit.Ng_y = rh.hit.Ng_z = 0.f;
            rh.hit.u = rh.hit.v = 0.f;
            rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            for (unsigned& id : rh.hit.instID) id = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(rtcScene_.get(), &ctx, &rh);
            if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
                best = PrimIntersection{refOf(rh.hit.geomID, rh.hit.primID), rh.ray.tfar, rh.hit.u, rh.hit.v};
                r.tfar = rh.ray.tfar;
            }
        }
        closerPlane(r, best);
        return best;
    }

    void intersectPrimBatch(std::span<const Ray> rays, std::span<std::optional<PrimIntersection>> out) const override {
        // Packets as wide as the remaining rays need: 16, 8 or 4 lanes.
        for (size_t i = 0; i < rays.size();) {
            const size_t left = rays.size() - i;
            if (left == 1) {
                out[i] = intersectPrim(rays[i]);
                i += 1;
            } else if (left <= 4) {
                i += intersectPacket<4>(rays.subspan(i), out.subspan(i));
            } else if (left <= 8) {
                i += intersectPacket<8>(rays.subspan(i), out.subspan(i));
            } else {
                i += intersectPacket<16>(rays.subspan(i), out.subspan(i));
            }
        }
    }

    void occludedBatch(std::span<const Ray> rays, std::span<uint8_t> out) const override {
        for (size_t i = 0; i < rays.size();) {
            const size_t left = rays.size() - i;
            if (left == 1) {
                out[i] = occluded(rays[i]) ? 1 : 0;
                i += 1;
            } else if (left <= 4) {
                i += occludedPacket<4>(rays.subspan(i), out.subspan(i));
            } else if (left <= 8) {
                i += occludedPacket<8>(rays.subspan(i), out.subspan(i));
            } else {
                i += occludedPacket<16>(rays.subspan(i), out.subspan(i));
            }
        }
    }

    // Maps an Embree hit back to the scene's arrays (geometries are attached by id).
    static PrimRef refOf(unsigned geomID, unsigned primID) {
        if (geomID >= kFirstMeshGeomId) return PrimRef{ShapeKind::Mesh, geomID - kFirstMeshGeomId, primID};
        return PrimRef{kKindOfUserGeom[geomID], primID, 0};
    }

    // Planes are tested outside Embree (see the top of this file): replaces
    // `best` with a plane hit closer than r.tfar, shrinking r.tfar.
    void closerPlane(Ray& r, std::optional<PrimIntersection>& best) const {
        const auto& planes = scene_.planes;
        for (size_t i = 0; i < planes.size(); ++i) {
            if (auto h = penumbra::intersect(planes[i], r)) {
                r.tfar = h->t;
                best = PrimIntersection{PrimRef{ShapeKind::Plane, static_cast<uint32_t>(i), 0}, h->t, h->u, h->v};
            }
        }
    }

    // One packet of up to W rays; returns how many rays it answered. Lanes
    // whose ray is invalid (counted) or has an empty interval stay inactive,
    // so no invalid ray reaches Embree; they miss, exactly as intersectPrim says.
    template <int W>
    size_t intersectPacket(std::span<const Ray> rays, std::span<std::optional<PrimIntersection>> out) const {
        const int n = static_cast<int>(std::min<size_t>(W, rays.size()));
        alignas(64) int valid[W];
        alignas(64) typename Packet<W>::RayHit rh;
        bool any = false;
        for (int l = 0; l < W; ++l) {
            const bool ok = l < n && acceptRay(rays[l]) && rays[l].tfar > rays[l].tnear;
            valid[l] = ok ? -1 : 0;
            any |= ok;
            setLane(rh.ray, l, ok ? rays[l] : kIdleLane);
            rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.primID[l] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
        }
        if (any && hasEmbreeGeometry_) {
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            Packet<W>::intersect(valid, rtcScene_.get(), &ctx, &rh);
        }
        for (int l = 0; l < n; ++l) {
            out[l].reset();
            if (!valid[l]) continue;
            Ray r = rays[l];
            if (rh.hit.geomID[l] != RTC_INVALID_GEOMETRY_ID) {
                out[l] = PrimIntersection{refOf(rh.hit.geomID[l], rh.hit.primID[l]), rh.ray.tfar[l], rh.hit.u[l],
                                          rh.hit.v[l]};
                r.tfar = rh.ray.tfar[l];
            }
            closerPlane(r, out[l]);
        }
        return size_t(n);
    }

    template <int W>
    size_t occludedPacket(std::span<const Ray> rays, std::span<uint8_t> out) const {
        const int n = static_cast<int>(std::min<size_t>(W, rays.size()));
        alignas(64) int valid[W];
        alignas(64) typename Packet<W>::RayOnly pr;
        bool any = false;
        for (int l = 0; l < W; ++l) {
            bool ok = false;
            if (l < n) {
                out[l] = 0;
                if (acceptRay(rays[l])) {
                    // The open interval (tnear, tfar), as in occluded().
                    Ray r = rays[l];
                    r.tfar = std::nextafter(r.tfar, -kInfinity);
                    if (r.tfar > r.tnear) {
                        bool plane = false;
                        for (const auto& p : scene_.planes)
                            if (penumbra::intersect(p, r)) {
                                plane = true;
                                break;
                            }
                        if (plane) {
                            out[l] = 1;
                        } else {
                            ok = hasEmbreeGeometry_;
                            if (ok) setLane(pr, l, r);
                        }
                    }
                }
            }
            valid[l] = ok ? -1 : 0;
            any |= ok;
            if (!ok) setLane(pr, l, kIdleLane);
        }
        if (!any) return size_t(n);
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        Packet<W>::occluded(valid, rtcScene_.get(), &ctx, &pr);
        for (int l = 0; l < n; ++l)
            if (valid[l] && pr.tfar[l] == -kInfinity) out[l] = 1;
        return size_t(n);
    }

    // Filler for inactive packet lanes: a harmless ray Embree never traces.
    static constexpr Ray kIdleLane{Vec3f{0.f, 0.f, 0.f}, Vec3f{0.f, 0.f, 1.f}, 0.f, 0.f};

    bool occluded(const Ray& ray) const override {
        if (!acceptRay(ray)) return false;
        // Occlusion is the open interval (tnear, tfar): every test here
        // accepts t <= tfar, so ask for the float just below tfar.
        Ray r = ray;
        r.tfar = std::nextafter(ray.tfar, -kInfinity);
        if (!(r.tfar > r.tnear)) return false;
        for (const auto& p : scene_.planes)
            if (penumbra::intersect(p, r)) return true;
        if (!hasEmbreeGeometry_) return false;
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        RTCRay q = toRtcRay(r, r.tfar);
        rtcOccluded1(rtcScene_.get(), &ctx, &q);
        return q.tfar == -kInfinity;
    }

    std::string name() const override { return "embree"; }

    size_t memoryBytes() const override { return memoryAfterCommit_; }

private:
    static constexpr std::array<ShapeKind, 4> kKindOfUserGeom{ShapeKind::Sphere, ShapeKind::Box, ShapeKind::Rectangle,
                                                             ShapeKind::Disk};

    static void errorCallback(void* userPtr, RTCError code, const char* str) {
        auto* self = static_cast<EmbreeAccelerator*>(userPtr);
        std::lock_guard<std::mutex> lock(self->errorMutex_);
        self->errors_.push_back(std::string(errorName(code)) + (str && *str ? std::string(": ") + str : ""));
    }

    static bool memoryCallback(void* userPtr, ssize_t bytes, bool /*post*/) {
        static_cast<EmbreeAccelerator*>(userPtr)->memoryBytes_.fetch_add(bytes, std::memory_order_relaxed);
        return true;  // never veto an allocation: out-of-memory is Embree's to report
    }

    // Turns errors the device reported during the last call into an Error.
    void check(const char* what) {
        std::lock_guard<std::mutex> lock(errorMutex_);
        if (errors_.empty()) return;
        std::string msg = std::string("Embree error during ") + what + ": ";
        for (size_t i = 0; i < errors_.size(); ++i) msg += (i ? "; " : "") + errors_[i];
        errors_.clear();
        throw Error(ErrorCode::Embree, msg);
    }

    void build(RTCBuildQuality quality) {
        device_ = EmbreeDevice(rtcNewDevice(nullptr));
        if (!device_) {
            throw Error(ErrorCode::Embree,
                        std::string("Embree error during rtcNewDevice: ") + errorName(rtcGetDeviceError(nullptr)));
        }
        rtcSetDeviceErrorFunction(device_.get(), &errorCallback, this);
        rtcSetDeviceMemoryMonitorFunction(device_.get(), &memoryCallback, this);
        check("device setup");

        rtcScene_ = EmbreeScene(rtcNewScene(device_.get()));
        check("rtcNewScene");
        rtcSetSceneFlags(rtcScene_.get(), RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(rtcScene_.get(), quality);
        check("scene setup");

        addUserGeometry<Sphere>(quality);
        addUserGeometry<Box>(quality);
        addUserGeometry<Rectangle>(quality);
        addUserGeometry<Disk>(quality);
        for (size_t i = 0; i < scene_.meshes.size(); ++i) addMesh(i, quality);

        rtcCommitScene(rtcScene_.get());
        check("rtcCommitScene");
        memoryAfterCommit_ = static_cast<size_t>(std::max<int64_t>(0, memoryBytes_.load()));
    }

    template <class Shape>
    void addUserGeometry(RTCBuildQuality quality) {
        const auto& shapes = ShapeTraits<Shape>::of(scene_);
        if (shapes.empty()) return;
        EmbreeGeometry g(rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_USER));
        check("rtcNewGeometry(user)");
        RTCGeometry geom = g.get();
        rtcSetGeometryUserPrimitiveCount(geom, static_cast<unsigned>(shapes.size()));
        // Callbacks only read the scene.
        rtcSetGeometryUserData(geom, const_cast<Scene*>(&scene_));
        rtcSetGeometryBoundsFunction(geom, &UserShapeCallbacks<Shape>::boundsFn, nullptr);
        rtcSetGeometryIntersectFunction(geom, &UserShapeCallbacks<Shape>::intersectFn);
        rtcSetGeometryOccludedFunction(geom, &UserShapeCallbacks<Shape>::occludedFn);
        rtcSetGeometryBuildQuality(geom, quality);
        rtcCommitGeometry(geom);
        check("user geometry setup");
        rtcAttachGeometryByID(rtcScene_.get(), geom, ShapeTraits<Shape>::kGeomId);
        check("rtcAttachGeometryByID(user)");
        hasEmbreeGeometry_ = true;
    }

    void addMesh(size_t index, RTCBuildQuality quality) {
        const TriangleMesh& m = scene_.meshes[index];
        EmbreeGeometry g(rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_TRIANGLE));
        check("rtcNewGeometry(triangle)");
        RTCGeometry geom = g.get();
        // Shared, not copied: the Scene outlives the accelerator, and
        // PositionBuffer keeps the padding Embree's 16-byte loads need.
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, m.positions.data(), 0,
                                   sizeof(Vec3f), m.positions.size());
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, m.indices.data(), 0,
                                   3 * sizeof(uint32_t), m.triangleCount());
        rtcSetGeometryBuildQuality(geom, quality);
        rtcCommitGeometry(geom);
        check(("mesh '" + m.name + "' setup").c_str());
        rtcAttachGeometryByID(rtcScene_.get(), geom, kFirstMeshGeomId + static_cast<unsigned>(index));
        check(("rtcAttachGeometryByID(mesh '" + m.name + "')").c_str());
        hasEmbreeGeometry_ = true;
    }

    // Declared before the Embree handles so they outlive them: the device
    // calls back into these while it releases its memory.
    std::mutex errorMutex_;
    std::vector<std::string> errors_;
    std::atomic<int64_t> memoryBytes_{0};
    size_t memoryAfterCommit_ = 0;
    bool hasEmbreeGeometry_ = false;

    EmbreeDevice device_;
    EmbreeScene rtcScene_;
};

}  // namespace

std::unique_ptr<Accelerator> makeEmbreeAccelerator(const Scene& scene, BuildQuality quality) {
    return std::make_unique<EmbreeAccelerator>(scene, quality);
}

}  // namespace penumbra
