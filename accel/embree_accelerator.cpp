// The Embree BVH accelerator (Embree 3.13, the only Embree user in Penumbra).
//
// Geometry layout, attached by ID so hits map back to the Scene's arrays:
//   geomID 0      spheres (user geometry, callbacks over the packet lanes as
//                 arrays), primID = index in Scene::spheres
//   geomID 1      boxes as native quads, 6 per box; boxOfQuad_[primID] = box
//   geomID 2      rectangles as native quads, primID = index in Scene::rectangles
//   geomID 3      disks (user geometry), primID = index in Scene::disks
//   geomID 4 + i  scene.meshes[i] as a native triangle mesh, primID = triangle
//   geomID 4 + M + j  scene.instances[j] (M = scene.meshes.size()) as an Embree
//                 instance of its prototype's scene; a hit has instID[0] = this
//                 geomID, geomID = the mesh within the prototype, primID = triangle
//
// Instancing: each prototype that has instances gets its own RTCScene (its
// meshes attached by their index, the vertex buffers shared as for ordinary
// meshes) built once, whatever the number of instances; each instance is an
// RTC_GEOMETRY_TYPE_INSTANCE geometry holding only its 3x4 transform. Embree
// takes the ray into object space with the inverse transform and reports t
// along the unnormalised object-space ray, which is t along the world ray; the
// naive loop does the same (accel/naive_accelerator.cpp). Embree is built with
// one instance level (RTC_MAX_INSTANCE_LEVEL_COUNT 1), so prototypes hold
// meshes, never instances (the JSON loader flattens nested groups).
//
// Boxes and rectangles are planar polygons, so Embree's own quads answer
// them exactly as the analytic tests do (up to rounding; the agreement tests
// hold them to the naive loop), with Embree's SIMD code instead of a callback
// per ray. A quad's (u, v) is the parallelogram's (s, t), as the rectangle
// test reports it; a box hit keeps PrimRef{Box, box, 0} and its face is found
// when the hit is completed, as for the naive loop. Spheres and disks stay
// user geometries whose callbacks call the very same core/shapes.h routines
// as the naive loop (nothing native fits a disk; RTC_GEOMETRY_TYPE_SPHERE_POINT
// would need its precision checked against the ray-offset rule of core/ray.h
// on small, distant spheres first, which has not been done).
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
#include <cstdlib>
#include <mutex>
#include <string>
#include <type_traits>
#include <vector>

#include "accel/accelerator.h"
#include "accel/embree_device.h"
#include "accel/embree_packets.h"
#include "accel/shape_bounds.h"
#include "core/error.h"
#include "core/lane_clones.h"

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
struct ShapeTraits<Disk> {
    static constexpr unsigned kGeomId = 3;
    static constexpr ShapeKind kKind = ShapeKind::Disk;
    static const std::vector<Disk>& of(const Scene& s) { return s.disks; }
};

// Embree only uses the hit normal for its own filters; Penumbra recomputes
// every normal when it completes the hit. These are cheap and unnormalised.
Vec3f hitNormal(const Sphere& s, const Ray& r, const PrimHit& h) { return r.o + h.t * r.d - s.center; }
Vec3f hitNormal(const Disk& d, const Ray&, const PrimHit&) { return d.normal; }

inline Ray rayFromN(RTCRayN* rays, unsigned n, unsigned i) {
    Ray r;
    r.o = {RTCRayN_org_x(rays, n, i), RTCRayN_org_y(rays, n, i), RTCRayN_org_z(rays, n, i)};
    r.d = {RTCRayN_dir_x(rays, n, i), RTCRayN_dir_y(rays, n, i), RTCRayN_dir_z(rays, n, i)};
    r.tnear = RTCRayN_tnear(rays, n, i);
    r.tfar = RTCRayN_tfar(rays, n, i);
    return r;
}

// Sphere distances of the valid lanes among the N rays of a callback (at
// most 16 at a time): sphereHitDistance over the lanes as arrays, so that the
// loop vectorises (spheres are most of what the user geometries answer);
// +infinity for the lanes that miss or are not valid.
PENUMBRA_LANE_CLONES void sphereLaneDistances(const Sphere& s, RTCRayN* rays, unsigned n, unsigned first,
                                              unsigned count, const int* valid, float* t) {
    const float* ox = &RTCRayN_org_x(rays, n, first);
    const float* oy = &RTCRayN_org_y(rays, n, first);
    const float* oz = &RTCRayN_org_z(rays, n, first);
    const float* dx = &RTCRayN_dir_x(rays, n, first);
    const float* dy = &RTCRayN_dir_y(rays, n, first);
    const float* dz = &RTCRayN_dir_z(rays, n, first);
    const float* tnear = &RTCRayN_tnear(rays, n, first);
    const float* tfar = &RTCRayN_tfar(rays, n, first);
    for (unsigned l = 0; l < count; ++l) {
        const float d = sphereHitDistance(s, ox[l], oy[l], oz[l], dx[l], dy[l], dz[l], tnear[l], tfar[l]);
        t[l] = valid[first + l] != 0 ? d : kInfinity;
    }
}

// Callbacks of one analytic kind. The geometry user pointer is the Scene.
template <class Shape>
struct UserShapeCallbacks {
    static constexpr unsigned kMaxLanes = 16;  // Embree's widest packet

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
        const Shape& s = shape(args->geometryUserPtr, args->primID);
        const unsigned n = args->N;
        RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, n);
        RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, n);
        if constexpr (std::is_same_v<Shape, Sphere>) {
            for (unsigned first = 0; first < n; first += kMaxLanes) {
                const unsigned count = std::min(n - first, kMaxLanes);
                alignas(64) float t[kMaxLanes];
                sphereLaneDistances(s, rays, n, first, count, args->valid, t);
                for (unsigned l = 0; l < count; ++l)
                    if (t[l] < kInfinity) setHit(args, s, rays, hits, first + l, PrimHit{t[l], 0.f, 0.f});
            }
            return;
        }
        for (unsigned i = 0; i < n; ++i) {
            if (args->valid[i] == 0) continue;
            const auto h = intersect(s, rayFromN(rays, n, i));
            if (h) setHit(args, s, rays, hits, i, *h);
        }
    }

    // Records a hit found in lane i. The ray's tfar is the closest hit so far
    // and the tests only report t in (tnear, tfar], so the hit is always closer.
    static void setHit(const RTCIntersectFunctionNArguments* args, const Shape& s, RTCRayN* rays, RTCHitN* hits,
                       unsigned i, const PrimHit& h) {
        const unsigned n = args->N;
        const Vec3f ng = hitNormal(s, rayFromN(rays, n, i), h);
        RTCRayN_tfar(rays, n, i) = h.t;
        RTCHitN_Ng_x(hits, n, i) = ng.x;
        RTCHitN_Ng_y(hits, n, i) = ng.y;
        RTCHitN_Ng_z(hits, n, i) = ng.z;
        RTCHitN_u(hits, n, i) = h.u;
        RTCHitN_v(hits, n, i) = h.v;
        RTCHitN_primID(hits, n, i) = args->primID;
        RTCHitN_geomID(hits, n, i) = args->geomID;
        RTCHitN_instID(hits, n, i, 0) = RTC_INVALID_GEOMETRY_ID;
    }

    static void occludedFn(const RTCOccludedFunctionNArguments* args) {
        const Shape& s = shape(args->geometryUserPtr, args->primID);
        const unsigned n = args->N;
        if constexpr (std::is_same_v<Shape, Sphere>) {
            for (unsigned first = 0; first < n; first += kMaxLanes) {
                const unsigned count = std::min(n - first, kMaxLanes);
                alignas(64) float t[kMaxLanes];
                sphereLaneDistances(s, args->ray, n, first, count, args->valid, t);
                for (unsigned l = 0; l < count; ++l)
                    if (t[l] < kInfinity) RTCRayN_tfar(args->ray, n, first + l) = -kInfinity;
            }
            return;
        }
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
        // Release the scene while the device's callbacks can still reach us;
        // the instances hold references to the prototype scenes, so those go after.
        rtcScene_.reset();
        prototypeScenes_.clear();
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
                best = PrimIntersection{refOf(rh.hit.geomID, rh.hit.primID, rh.hit.instID[0]), rh.ray.tfar, rh.hit.u,
                                        rh.hit.v};
                r.tfar = rh.ray.tfar;
            }
        }
        closerPlane(r, best);
        return best;
    }

    // The virtual entry points hand over to non-virtual bodies compiled per ISA (core/lane_clones.h).
    void intersectPrimBatch(std::span<const Ray> rays, std::span<std::optional<PrimIntersection>> out) const override {
        intersectPackets(rays, out);
    }

    PENUMBRA_LANE_CLONES void intersectPackets(std::span<const Ray> rays,
                                               std::span<std::optional<PrimIntersection>> out) const {
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
    PrimRef refOf(unsigned geomID, unsigned primID, unsigned instID) const {
        if (instID != RTC_INVALID_GEOMETRY_ID)
            return PrimRef{ShapeKind::Instance, instID - firstInstanceGeomId_, primID, geomID};
        if (geomID >= kFirstMeshGeomId) return PrimRef{ShapeKind::Mesh, geomID - kFirstMeshGeomId, primID};
        if (geomID == kBoxGeomId) return PrimRef{ShapeKind::Box, boxOfQuad_[primID], 0};
        return PrimRef{kKindOfGeom[geomID], primID, 0};
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

    // Writes up to W rays into a packet's lanes (idle rays after the last)
    // and marks in ok[] the lanes whose ray is valid (isValidRay), counting
    // the invalid ones; their lanes get the idle ray, so no invalid ray
    // reaches Embree. The tests run over the lanes as arrays (vectorised).
    template <int W, class PacketRay>
    void loadLanes(std::span<const Ray> rays, int n, PacketRay& p, int* ok) const {
        for (int l = 0; l < W; ++l) setLane(p, l, l < n ? rays[l] : kIdleLane);
        int invalid = 0;
        for (int l = 0; l < W; ++l) {
            ok[l] = isValidRayComponents(p.org_x[l], p.org_y[l], p.org_z[l], p.dir_x[l], p.dir_y[l], p.dir_z[l],
                                         p.tnear[l], p.tfar[l]);
            invalid += 1 - ok[l];
        }
        if (invalid == 0) return;
        countInvalidRays(uint64_t(invalid));
        for (int l = 0; l < W; ++l)
            if (!ok[l]) setLane(p, l, kIdleLane);
    }

    // One packet of up to W rays; returns how many rays it answered. Lanes
    // whose ray is invalid (counted) or has an empty interval stay inactive,
    // so no invalid ray reaches Embree; they miss, exactly as intersectPrim says.
    template <int W>
    [[gnu::always_inline]] size_t intersectPacket(std::span<const Ray> rays,
                                                  std::span<std::optional<PrimIntersection>> out) const {
        const int n = static_cast<int>(std::min<size_t>(W, rays.size()));
        alignas(64) int ok[W];
        alignas(64) typename Packet<W>::RayHit rh;
        loadLanes<W>(rays, n, rh.ray, ok);
        answerPacket<W>(rh, ok, n, out.data());
        return size_t(n);
    }

    void intersectPrimLanes(const RayLanes& rays, std::optional<PrimIntersection>* out) const override {
        intersectRayLanes(rays, out);
    }

    PENUMBRA_LANE_CLONES void intersectRayLanes(const RayLanes& rays, std::optional<PrimIntersection>* out) const {
        alignas(64) int ok[RayLanes::kWidth];
        alignas(64) RTCRayHit16 rh;
        loadRayLanes(rays, rh.ray, ok);
        answerPacket<RayLanes::kWidth>(rh, ok, RayLanes::kWidth, out, true);
    }

    // Whether Embree's coherent traversal (RTC_INTERSECT_CONTEXT_FLAG_COHERENT:
    // the packet's node tests against one frustum of all its rays) may answer
    // the lanes of `valid`: their directions all point into one octant, no
    // component nearer zero than 2^-20. With an exactly zero component (a ray
    // along an axis) that traversal missed hits the single-ray query finds
    // (Embree 3.13.5; tests/accel/agreement_test.cpp has the cases), so such
    // packets, and any that mix octants, take the default traversal.
    template <int W>
    [[gnu::always_inline]] static bool sharesOneOctant(const typename Packet<W>::RayOnly& r, const int* valid) {
        constexpr float kMin = 0x1p-20f;
        int first = -1;
        for (int l = 0; l < W && first < 0; ++l)
            if (valid[l]) first = l;
        if (first < 0) return false;
        const bool nx = r.dir_x[first] < 0.f, ny = r.dir_y[first] < 0.f, nz = r.dir_z[first] < 0.f;
        int differ = 0;
        for (int l = 0; l < W; ++l) {
            const float x = r.dir_x[l], y = r.dir_y[l], z = r.dir_z[l];
            const int small = int(!(std::fabs(x) >= kMin)) | int(!(std::fabs(y) >= kMin)) | int(!(std::fabs(z) >= kMin));
            const int sign = int((x < 0.f) != nx) | int((y < 0.f) != ny) | int((z < 0.f) != nz);
            differ |= valid[l] & (small | sign);
        }
        return differ == 0;
    }

    // The closest-hit query of a loaded packet whose valid lanes ok[] marks
    // (the others hold the idle ray); writes the first n answers. coherent:
    // the lanes are a block of camera rays (Accelerator::intersectLanes), for
    // Embree's coherent traversal where sharesOneOctant allows it.
    template <int W>
    [[gnu::always_inline]] void answerPacket(typename Packet<W>::RayHit& rh, const int* ok, int n,
                                             std::optional<PrimIntersection>* out, bool coherent = false) const {
        alignas(64) int valid[W];
        int any = 0;
        for (int l = 0; l < W; ++l) {
            valid[l] = (ok[l] & (rh.ray.tfar[l] > rh.ray.tnear[l])) ? -1 : 0;
            any |= valid[l];
            rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.primID[l] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
        }
        alignas(64) int query[W];  // the lanes Embree answers: valid ones that meet its bounds
        for (int l = 0; l < W; ++l) query[l] = valid[l];
        if (any && hasEmbreeGeometry_ && keepLanesInRootBounds<W>(rh.ray, query)) {
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            if (coherent && sharesOneOctant<W>(rh.ray, query)) ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
            Packet<W>::intersect(query, rtcScene_.get(), &ctx, &rh);
        }
        // Planes after Embree, each against the lane's closest hit so far
        // (Embree shrank tfar to it), as closerPlane does for one ray.
        alignas(64) int plane[W];
        for (int l = 0; l < W; ++l) plane[l] = -1;
        const auto& planes = scene_.planes;
        for (size_t i = 0; i < planes.size(); ++i) {
            const Plane p = planes[i];  // a copy: the lanes' stores cannot change it
            const int index = static_cast<int>(i);
            for (int l = 0; l < W; ++l) {
                const float t = planeHitDistance(p, rh.ray.org_x[l], rh.ray.org_y[l], rh.ray.org_z[l], rh.ray.dir_x[l],
                                                 rh.ray.dir_y[l], rh.ray.dir_z[l], rh.ray.tnear[l], rh.ray.tfar[l]);
                // t is infinite when there is no hit, and at most tfar when there is one.
                plane[l] = t < kInfinity ? index : plane[l];
                rh.ray.tfar[l] = std::min(t, rh.ray.tfar[l]);
            }
        }
        for (int l = 0; l < n; ++l) {
            if (!valid[l]) {
                out[l].reset();
            } else if (plane[l] >= 0) {
                out[l] = PrimIntersection{PrimRef{ShapeKind::Plane, static_cast<uint32_t>(plane[l]), 0}, rh.ray.tfar[l],
                                          0.f, 0.f};
            } else if (rh.hit.geomID[l] != RTC_INVALID_GEOMETRY_ID) {
                out[l] = PrimIntersection{refOf(rh.hit.geomID[l], rh.hit.primID[l], rh.hit.instID[0][l]),
                                          rh.ray.tfar[l], rh.hit.u[l], rh.hit.v[l]};
            } else {
                out[l].reset();
            }
        }
    }

    template <int W>
    size_t occludedPacket(std::span<const Ray> rays, std::span<uint8_t> out) const {
        const int n = static_cast<int>(std::min<size_t>(W, rays.size()));
        alignas(64) int ok[W];
        alignas(64) typename Packet<W>::RayOnly pr;
        loadLanes<W>(rays, n, pr, ok);
        occludedLoaded<W>(pr, ok, n, out.data());
        return size_t(n);
    }

    void occludedLanes(const RayLanes& rays, uint8_t* out) const override { occludedRayLanes(rays, out); }

    PENUMBRA_LANE_CLONES void occludedRayLanes(const RayLanes& rays, uint8_t* out) const {
        alignas(64) int ok[RayLanes::kWidth];
        alignas(64) RTCRay16 pr;
        loadRayLanes(rays, pr, ok);
        occludedLoaded<RayLanes::kWidth>(pr, ok, RayLanes::kWidth, out);
    }

    // The lanes' arrays are the packet's: copies them in with the validity
    // test and the idle lanes, as loadLanes does for rays given one by one.
    PENUMBRA_LANE_CLONES void loadRayLanes(const RayLanes& rays, RTCRay16& pr, int* ok) const {
        constexpr int W = RayLanes::kWidth;
        int invalid = 0;
        for (int l = 0; l < W; ++l) {
            const int valid = isValidRayComponents(rays.ox[l], rays.oy[l], rays.oz[l], rays.dx[l], rays.dy[l],
                                                   rays.dz[l], rays.tnear[l], rays.tfar[l]);
            ok[l] = rays.active[l] & valid;
            invalid += rays.active[l] & (1 - valid);
        }
        if (invalid > 0) countInvalidRays(uint64_t(invalid));
        for (int l = 0; l < W; ++l) {
            const bool use = ok[l] != 0;
            pr.org_x[l] = use ? rays.ox[l] : kIdleLane.o.x;
            pr.org_y[l] = use ? rays.oy[l] : kIdleLane.o.y;
            pr.org_z[l] = use ? rays.oz[l] : kIdleLane.o.z;
            pr.dir_x[l] = use ? rays.dx[l] : kIdleLane.d.x;
            pr.dir_y[l] = use ? rays.dy[l] : kIdleLane.d.y;
            pr.dir_z[l] = use ? rays.dz[l] : kIdleLane.d.z;
            pr.tnear[l] = use ? rays.tnear[l] : kIdleLane.tnear;
            pr.tfar[l] = use ? rays.tfar[l] : kIdleLane.tfar;
            pr.time[l] = 0.f;
            pr.mask[l] = ~0u;
            pr.id[l] = static_cast<unsigned>(l);
            pr.flags[l] = 0;
        }
    }

    // The occlusion query of a loaded packet whose valid lanes ok[] marks
    // (the others hold the idle ray); writes the first n answers.
    template <int W>
    [[gnu::always_inline]] void occludedLoaded(typename Packet<W>::RayOnly& pr, const int* ok, int n,
                                               uint8_t* out) const {
        alignas(64) int valid[W];
        alignas(64) int blocked[W];
        // The open interval (tnear, tfar), as in occluded(): every test here
        // accepts t <= tfar, so ask for the float just below tfar.
        for (int l = 0; l < W; ++l) pr.tfar[l] = nextFloatDown(pr.tfar[l]);
        for (int l = 0; l < W; ++l) blocked[l] = 0;
        for (const Plane& p : scene_.planes)
            for (int l = 0; l < W; ++l)
                blocked[l] |= planeHitDistance(p, pr.org_x[l], pr.org_y[l], pr.org_z[l], pr.dir_x[l], pr.dir_y[l],
                                               pr.dir_z[l], pr.tnear[l], pr.tfar[l]) < kInfinity;
        int any = 0;
        for (int l = 0; l < W; ++l) {
            const int open = ok[l] & (pr.tfar[l] > pr.tnear[l]);
            blocked[l] &= open;
            valid[l] = (open & !blocked[l] & int(hasEmbreeGeometry_)) ? -1 : 0;
            any |= valid[l];
        }
        for (int l = 0; l < n; ++l) out[l] = static_cast<uint8_t>(blocked[l]);
        if (!any || !keepLanesInRootBounds<W>(pr, valid)) return;
        if (shapeBounds_.available() && !keepLanesMeetingShapes<W>(pr, valid)) return;
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        Packet<W>::occluded(valid, rtcScene_.get(), &ctx, &pr);
        for (int l = 0; l < n; ++l)
            if (valid[l] && pr.tfar[l] == -kInfinity) out[l] = 1;
    }

    // Filler for inactive packet lanes: a harmless ray Embree never traces.
    static constexpr Ray kIdleLane{Vec3f{0.f, 0.f, 0.f}, Vec3f{0.f, 0.f, 1.f}, 0.f, 0.f};

    bool occluded(const Ray& ray) const override {
        if (!acceptRay(ray)) return false;
        // Occlusion is the open interval (tnear, tfar): every test here
        // accepts t <= tfar, so ask for the float just below tfar.
        Ray r = ray;
        r.tfar = nextFloatDown(ray.tfar);
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
    static constexpr unsigned kBoxGeomId = 1, kRectangleGeomId = 2;
    static constexpr std::array<ShapeKind, 4> kKindOfGeom{ShapeKind::Sphere, ShapeKind::Box, ShapeKind::Rectangle,
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
        // PENUMBRA_EMBREE_CONFIG, when set, is Embree's device configuration
        // string (for instance "isa=avx2"): for measuring ISAs, not for use.
        device_ = EmbreeDevice(rtcNewDevice(std::getenv("PENUMBRA_EMBREE_CONFIG")));
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
        addBoxQuads(quality);
        addRectangleQuads(quality);
        addUserGeometry<Disk>(quality);
        for (size_t i = 0; i < scene_.meshes.size(); ++i)
            attachMesh(scene_.meshes[i], rtcScene_.get(), kFirstMeshGeomId + static_cast<unsigned>(i), quality);
        hasEmbreeGeometry_ = hasEmbreeGeometry_ || !scene_.meshes.empty();
        firstInstanceGeomId_ = kFirstMeshGeomId + static_cast<unsigned>(scene_.meshes.size());
        for (size_t j = 0; j < scene_.instances.size(); ++j) addInstance(j, quality);

        rtcCommitScene(rtcScene_.get());
        check("rtcCommitScene");
        memoryAfterCommit_ = static_cast<size_t>(std::max<int64_t>(0, memoryBytes_.load()));
        if (hasEmbreeGeometry_) setRootBounds();
    }

    // The box every Embree geometry lies in (rtcGetSceneBounds), grown by a
    // margin far above the rounding of the hits and of the slab test, so that
    // the packet pre-test (keepLanesInRootBounds) passes every ray Embree could hit.
    void setRootBounds() {
        RTCBounds b;
        rtcGetSceneBounds(rtcScene_.get(), &b);
        check("rtcGetSceneBounds");
        const Vec3f lo{b.lower_x, b.lower_y, b.lower_z}, hi{b.upper_x, b.upper_y, b.upper_z};
        if (!isFinite(lo) || !isFinite(hi) || !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z)) return;
        const float pad =
            1e-4f * (maxComponent(hi - lo) + std::max(maxAbsComponent(lo), maxAbsComponent(hi))) + 1e-6f;
        rootLo_ = lo - Vec3f(pad);
        rootHi_ = hi + Vec3f(pad);
        hasRootBounds_ = true;
    }

    // Clears valid[l] for the lanes whose interval [tnear, tfar] does not meet
    // the root bounds (a slab test over the lanes). A zero direction component
    // takes a huge finite reciprocal; a NaN that a denormal one can still give
    // (without flush-to-zero) only removes limits as std::min/max pass it on,
    // so the test may keep too many lanes, never too few. Embree would find
    // nothing for the cleared lanes, and a packet with no lane left skips its
    // call: in small scenes the call's fixed cost is most of a packet's (the
    // textbook scene's ground and sky). A packet whose rays all start inside
    // the bounds (a closed room) cannot lose a lane and skips the slab test and
    // its divisions. Returns whether any lane is left.
    template <int W, class PacketRay>
    [[gnu::always_inline]] bool keepLanesInRootBounds(const PacketRay& p, int* valid) const {
        const Vec3f lo = rootLo_, hi = rootHi_;
        int any = 0, outside = 0;
        for (int l = 0; l < W; ++l) {
            any |= valid[l];
            outside |= valid[l] & int(!(p.org_x[l] >= lo.x && p.org_x[l] <= hi.x && p.org_y[l] >= lo.y &&
                                         p.org_y[l] <= hi.y && p.org_z[l] >= lo.z && p.org_z[l] <= hi.z));
        }
        if (!hasRootBounds_ || !outside) return any != 0;
        any = 0;
        for (int l = 0; l < W; ++l) {
            const float ix = 1.f / (p.dir_x[l] != 0.f ? p.dir_x[l] : 1e-30f);
            const float iy = 1.f / (p.dir_y[l] != 0.f ? p.dir_y[l] : 1e-30f);
            const float iz = 1.f / (p.dir_z[l] != 0.f ? p.dir_z[l] : 1e-30f);
            const float ax = (lo.x - p.org_x[l]) * ix, bx = (hi.x - p.org_x[l]) * ix;
            const float ay = (lo.y - p.org_y[l]) * iy, by = (hi.y - p.org_y[l]) * iy;
            const float az = (lo.z - p.org_z[l]) * iz, bz = (hi.z - p.org_z[l]) * iz;
            const float t0 =
                std::max(std::max(p.tnear[l], std::min(ax, bx)), std::max(std::min(ay, by), std::min(az, bz)));
            const float t1 =
                std::min(std::min(p.tfar[l], std::max(ax, bx)), std::min(std::max(ay, by), std::max(az, bz)));
            const bool misses = t0 > t1 + 1e-5f * std::fabs(t1);
            valid[l] = misses ? 0 : valid[l];
            any |= valid[l];
        }
        return any != 0;
    }

    // Clears valid[l] for the lanes whose interval [tnear, tfar] meets no
    // shape's bounds (accel/shape_bounds.h): slab tests against the boxes and the
    // closest approach to the spheres, over the lanes. As in
    // keepLanesInRootBounds, a NaN only keeps a lane. In a scene of a few
    // shapes most shadow rays cross open space between the surfaces (the
    // room: those from its walls to the light, past both spheres) and the
    // packet then skips Embree's call. Returns whether any lane is left.
    template <int W, class PacketRay>
    [[gnu::always_inline]] bool keepLanesMeetingShapes(const PacketRay& p, int* valid) const {
        alignas(64) int meets[W];
        alignas(64) float ix[W], iy[W], iz[W];
        for (int l = 0; l < W; ++l) {
            meets[l] = 0;
            ix[l] = 1.f / (p.dir_x[l] != 0.f ? p.dir_x[l] : 1e-30f);
            iy[l] = 1.f / (p.dir_y[l] != 0.f ? p.dir_y[l] : 1e-30f);
            iz[l] = 1.f / (p.dir_z[l] != 0.f ? p.dir_z[l] : 1e-30f);
        }
        for (const ShapeBounds::PaddedBox& b : shapeBounds_.boxes()) {
            const Vec3f lo = b.box.lo, hi = b.box.hi;
            for (int l = 0; l < W; ++l) {
                const float ax = (lo.x - p.org_x[l]) * ix[l], bx = (hi.x - p.org_x[l]) * ix[l];
                const float ay = (lo.y - p.org_y[l]) * iy[l], by = (hi.y - p.org_y[l]) * iy[l];
                const float az = (lo.z - p.org_z[l]) * iz[l], bz = (hi.z - p.org_z[l]) * iz[l];
                const float t0 =
                    std::max(std::max(p.tnear[l], std::min(ax, bx)), std::max(std::min(ay, by), std::min(az, bz)));
                const float t1 =
                    std::min(std::min(p.tfar[l], std::max(ax, bx)), std::min(std::max(ay, by), std::max(az, bz)));
                meets[l] |= int(!(t0 > t1 + 1e-6f * std::fabs(t1)));  // a few ulps of t: the slab test's rounding
            }
        }
        for (const Sphere& s : shapeBounds_.spheres()) {
            const Vec3f c = s.center;
            const float r2 = s.radius * s.radius;
            for (int l = 0; l < W; ++l) {
                // The closest point of the interval to the centre (directions are unit, up to rounding).
                const float cx = c.x - p.org_x[l], cy = c.y - p.org_y[l], cz = c.z - p.org_z[l];
                const float along = cx * p.dir_x[l] + cy * p.dir_y[l] + cz * p.dir_z[l];
                const float t = std::min(std::max(along, p.tnear[l]), p.tfar[l]);
                const float dx = cx - t * p.dir_x[l], dy = cy - t * p.dir_y[l], dz = cz - t * p.dir_z[l];
                meets[l] |= int(!(dx * dx + dy * dy + dz * dz > r2));
            }
        }
        int any = 0;
        for (int l = 0; l < W; ++l) {
            valid[l] = meets[l] ? valid[l] : 0;
            any |= valid[l];
        }
        return any != 0;
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

    // A quad geometry from corner positions (4 per quad, in order around it).
    void addQuads(const std::vector<Vec3f>& corners, unsigned geomId, RTCBuildQuality quality, const char* what) {
        if (corners.empty()) return;
        const size_t quads = corners.size() / 4;
        EmbreeGeometry g(rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_QUAD));
        check("rtcNewGeometry(quad)");
        RTCGeometry geom = g.get();
        // Embree's own buffers keep the padding its 16-byte vertex loads need.
        auto* v = static_cast<float*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), corners.size()));
        auto* idx = static_cast<uint32_t*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(uint32_t), quads));
        check(what);
        for (size_t i = 0; i < corners.size(); ++i) {
            v[3 * i] = corners[i].x;
            v[3 * i + 1] = corners[i].y;
            v[3 * i + 2] = corners[i].z;
            idx[i] = static_cast<uint32_t>(i);
        }
        rtcSetGeometryBuildQuality(geom, quality);
        rtcCommitGeometry(geom);
        check(what);
        rtcAttachGeometryByID(rtcScene_.get(), geom, geomId);
        check(what);
        hasEmbreeGeometry_ = true;
    }

    // Each box as its six faces, corners transformed to world space (an
    // affine map keeps every face a planar parallelogram).
    void addBoxQuads(RTCBuildQuality quality) {
        static constexpr int kFaces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                                             {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
        std::vector<Vec3f> corners;
        for (size_t i = 0; i < scene_.boxes.size(); ++i) {
            const Box& b = scene_.boxes[i];
            if (b.lo.x > b.hi.x || b.lo.y > b.hi.y || b.lo.z > b.hi.z) continue;  // emptied by a singular transform
            Vec3f c[8];
            for (int k = 0; k < 8; ++k)
                c[k] = b.worldFromObject.applyPoint(
                    Vec3f{(k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z});
            for (const auto& face : kFaces) {
                for (int k : face) corners.push_back(c[k]);
                boxOfQuad_.push_back(static_cast<uint32_t>(i));
            }
        }
        addQuads(corners, kBoxGeomId, quality, "box quads setup");
    }

    // Each rectangle p0, p0 + a, p0 + a + b, p0 + b: Embree's quad (u, v) is then (s, t).
    void addRectangleQuads(RTCBuildQuality quality) {
        std::vector<Vec3f> corners;
        for (const Rectangle& q : scene_.rectangles)
            corners.insert(corners.end(), {q.p0, q.p0 + q.a, q.p0 + q.a + q.b, q.p0 + q.b});
        addQuads(corners, kRectangleGeomId, quality, "rectangle quads setup");
    }

    void attachMesh(const TriangleMesh& m, RTCScene target, unsigned geomId, RTCBuildQuality quality) {
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
        rtcAttachGeometryByID(target, geom, geomId);
        check(("rtcAttachGeometryByID(mesh '" + m.name + "')").c_str());
    }

    // The prototype's own scene, built on first use: instances share it.
    RTCScene prototypeScene(uint32_t index, RTCBuildQuality quality) {
        if (prototypeScenes_.empty()) prototypeScenes_.resize(scene_.prototypes.size());
        EmbreeScene& ps = prototypeScenes_[index];
        if (ps) return ps.get();
        const Prototype& p = scene_.prototypes[index];
        ps = EmbreeScene(rtcNewScene(device_.get()));
        check("rtcNewScene(prototype)");
        rtcSetSceneFlags(ps.get(), RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(ps.get(), quality);
        for (size_t k = 0; k < p.meshes.size(); ++k) attachMesh(p.meshes[k], ps.get(), static_cast<unsigned>(k), quality);
        rtcCommitScene(ps.get());
        check(("rtcCommitScene(prototype '" + p.name + "')").c_str());
        return ps.get();
    }

    void addInstance(size_t index, RTCBuildQuality quality) {
        const Instance& in = scene_.instances[index];
        RTCScene proto = prototypeScene(in.prototype, quality);
        EmbreeGeometry g(rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_INSTANCE));
        check("rtcNewGeometry(instance)");
        RTCGeometry geom = g.get();
        rtcSetGeometryInstancedScene(geom, proto);
        float m[3][4];
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) m[r][c] = in.worldFromObject(r, c);
        rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, &m[0][0]);
        rtcCommitGeometry(geom);
        check("instance setup");
        rtcAttachGeometryByID(rtcScene_.get(), geom, firstInstanceGeomId_ + static_cast<unsigned>(index));
        check("rtcAttachGeometryByID(instance)");
        hasEmbreeGeometry_ = true;
    }

    // Declared before the Embree handles so they outlive them: the device
    // calls back into these while it releases its memory.
    std::mutex errorMutex_;
    std::vector<std::string> errors_;
    std::atomic<int64_t> memoryBytes_{0};
    size_t memoryAfterCommit_ = 0;
    bool hasEmbreeGeometry_ = false;
    bool hasRootBounds_ = false;  // rootLo_/rootHi_ hold the padded bounds of the Embree geometry
    Vec3f rootLo_, rootHi_;
    ShapeBounds shapeBounds_{scene_};  // the occlusion packets' second pre-test (keepLanesMeetingShapes)
    std::vector<uint32_t> boxOfQuad_;  // box index of each box quad (primID)
    unsigned firstInstanceGeomId_ = kFirstMeshGeomId;

    EmbreeDevice device_;
    std::vector<EmbreeScene> prototypeScenes_;  // by prototype index; empty handles for unused ones
    EmbreeScene rtcScene_;
};

}  // namespace

std::unique_ptr<Accelerator> makeEmbreeAccelerator(const Scene& scene, BuildQuality quality) {
    return std::make_unique<EmbreeAccelerator>(scene, quality);
}

}  // namespace penumbra
