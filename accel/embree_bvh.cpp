// The Embree BVH of accel/embree_bvh.h: the device and its callbacks, every
// geometry of the layout described there, the prototypes' scenes, the root
// bounds. The user geometries' callbacks (spheres and disks) are here too:
// they call the same core/shapes.h routines as the naive loop.
#include "accel/embree_bvh.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <type_traits>

#include "core/error.h"
#include "core/lane_clones.h"

namespace penumbra {
namespace {

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

}  // namespace

EmbreeBvh::EmbreeBvh(const Scene& scene, BuildQuality quality, const AlphaTest& alpha, bool withoutSpheresAndBoxes)
    : sceneData_(scene), quality_(toEmbree(quality)), withoutSpheresAndBoxes_(withoutSpheresAndBoxes) {
    build(quality_, alpha);
}

EmbreeBvh::EmbreeBvh(const EmbreeBvh& base, const Scene& scene, std::shared_ptr<const void> buffers)
    : sceneData_(scene),
      log_(base.log_),
      buffers_(std::move(buffers)),
      quality_(base.quality_),
      withoutSpheresAndBoxes_(base.withoutSpheresAndBoxes_),
      hasGeometry_(base.hasGeometry_),
      boxOfQuad_(base.boxOfQuad_),
      worldHasGeometry_(base.worldHasGeometry_) {
    rtcRetainDevice(base.device_.get());
    device_ = EmbreeDevice(base.device_.get());
    if (scene.instances.empty()) {
        // One level: nothing Embree holds has changed.
        rtcRetainScene(base.rtcScene_.get());
        rtcScene_ = EmbreeScene(base.rtcScene_.get());
        memoryAfterCommit_ = base.memoryAfterCommit_;
        hasRootBounds_ = base.hasRootBounds_;
        rootLo_ = base.rootLo_;
        rootHi_ = base.rootHi_;
        return;
    }
    for (const EmbreeScene& p : base.prototypeScenes_) {
        if (p) rtcRetainScene(p.get());
        prototypeScenes_.emplace_back(p.get());
    }
    if (base.worldScene_) {
        rtcRetainScene(base.worldScene_.get());
        worldScene_ = EmbreeScene(base.worldScene_.get());
    }
    commitTop(quality_);
}

EmbreeBvh::~EmbreeBvh() {
    // Release the scene before the device, while the device's callbacks can
    // still reach the log; the instances hold references to the world and
    // prototype scenes, so those go after.
    rtcScene_.reset();
    worldScene_.reset();
    prototypeScenes_.clear();
    device_.reset();
}

void EmbreeBvh::errorCallback(void* userPtr, RTCError code, const char* str) {
    auto* log = static_cast<DeviceLog*>(userPtr);
    std::lock_guard<std::mutex> lock(log->mutex);
    log->errors.push_back(std::string(errorName(code)) + (str && *str ? std::string(": ") + str : ""));
}

bool EmbreeBvh::memoryCallback(void* userPtr, ssize_t bytes, bool /*post*/) {
    static_cast<DeviceLog*>(userPtr)->memoryBytes.fetch_add(bytes, std::memory_order_relaxed);
    return true;  // never veto an allocation: out-of-memory is Embree's to report
}

// Turns errors the device reported during the last call into an Error.
void EmbreeBvh::check(const char* what) {
    std::lock_guard<std::mutex> lock(log_->mutex);
    if (log_->errors.empty()) return;
    std::string msg = std::string("Embree error during ") + what + ": ";
    for (size_t i = 0; i < log_->errors.size(); ++i) msg += (i ? "; " : "") + log_->errors[i];
    log_->errors.clear();
    throw Error(ErrorCode::Embree, msg);
}

// Rejects the candidate hits of the valid lanes where the alpha rule says
// the surface is not there (both the intersection and the occlusion filter).
void EmbreeBvh::alphaFilter(const RTCFilterFunctionNArguments* args) {
    const auto* ctx = reinterpret_cast<const EmbreeQueryContext*>(args->context);
    const unsigned n = args->N;
    RTCRayN* rays = args->ray;
    RTCHitN* hits = args->hit;
    for (unsigned i = 0; i < n; ++i) {
        if (args->valid[i] == 0) continue;
        const PrimRef ref = ctx->bvh->refOf(RTCHitN_geomID(hits, n, i), RTCHitN_primID(hits, n, i),
                                            RTCHitN_instID(hits, n, i, 0));
        // Embree has set tfar to the candidate's distance.
        if (!ctx->alpha->present(rayFromN(rays, n, i), ref, RTCRayN_tfar(rays, n, i), RTCHitN_u(hits, n, i),
                                 RTCHitN_v(hits, n, i), RTCRayN_id(rays, n, i)))
            args->valid[i] = 0;
    }
}

void EmbreeBvh::setAlphaFilter(RTCGeometry geom, bool cuts) {
    if (!cuts) return;
    rtcSetGeometryIntersectFilterFunction(geom, &alphaFilter);
    rtcSetGeometryOccludedFilterFunction(geom, &alphaFilter);
}

void EmbreeBvh::build(RTCBuildQuality quality, const AlphaTest& alpha) {
    // PENUMBRA_EMBREE_CONFIG, when set, is Embree's device configuration
    // string (for instance "isa=avx2"): for measuring ISAs, not for use.
    device_ = EmbreeDevice(rtcNewDevice(std::getenv("PENUMBRA_EMBREE_CONFIG")));
    if (!device_) {
        throw Error(ErrorCode::Embree,
                    std::string("Embree error during rtcNewDevice: ") + errorName(rtcGetDeviceError(nullptr)));
    }
    rtcSetDeviceErrorFunction(device_.get(), &errorCallback, log_.get());
    rtcSetDeviceMemoryMonitorFunction(device_.get(), &memoryCallback, log_.get());
    check("device setup");

    if (sceneData_.instances.empty()) {
        rtcScene_ = newScene(quality, "rtcNewScene");
        buildWorld(rtcScene_.get(), quality, alpha);
        rtcCommitScene(rtcScene_.get());
        check("rtcCommitScene");
        memoryAfterCommit_ = static_cast<size_t>(std::max<int64_t>(0, log_->memoryBytes.load()));
        if (hasGeometry_) setRootBounds();
        return;
    }
    worldScene_ = newScene(quality, "rtcNewScene(world)");
    buildWorld(worldScene_.get(), quality, alpha);
    if (worldHasGeometry_) {
        rtcCommitScene(worldScene_.get());
        check("rtcCommitScene(world)");
    } else {
        worldScene_.reset();
    }
    prototypeScenes_.resize(sceneData_.prototypes.size());
    for (const Instance& in : sceneData_.instances) prototypeScene(in.prototype, quality, alpha);
    commitTop(quality);
}

EmbreeScene EmbreeBvh::newScene(RTCBuildQuality quality, const char* what) {
    EmbreeScene scene(rtcNewScene(device_.get()));
    check(what);
    rtcSetSceneFlags(scene.get(), RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene.get(), quality);
    check("scene setup");
    return scene;
}

// Every shape and mesh of Scene's own arrays (not the instances), into `target`.
void EmbreeBvh::buildWorld(RTCScene target, RTCBuildQuality quality, const AlphaTest& alpha) {
    const bool before = hasGeometry_;
    hasGeometry_ = false;
    if (!withoutSpheresAndBoxes_) {
        addUserGeometry<Sphere>(target, quality);
        addBoxQuads(target, quality);
    }
    addRectangleQuads(target, quality, alpha.rectanglesCutOut());
    addUserGeometry<Disk>(target, quality);
    for (size_t i = 0; i < sceneData_.meshes.size(); ++i)
        attachMesh(sceneData_.meshes[i], target, kFirstMeshGeomId + static_cast<unsigned>(i), quality,
                   alpha.meshCutsOut(sceneData_.meshes[i]));
    worldHasGeometry_ = hasGeometry_ || !sceneData_.meshes.empty();
    hasGeometry_ = before || worldHasGeometry_;
}

// The top level of a scene with instances: the world scene, then each
// instance, committed. The only part an edit that moves instances builds.
void EmbreeBvh::commitTop(RTCBuildQuality quality) {
    rtcScene_ = newScene(quality, "rtcNewScene(top level)");
    if (worldScene_) addInstance(rtcScene_.get(), kWorldInstanceGeomId, worldScene_.get(), Transform());
    for (size_t j = 0; j < sceneData_.instances.size(); ++j) {
        const Instance& in = sceneData_.instances[j];
        addInstance(rtcScene_.get(), kFirstInstanceGeomId + static_cast<unsigned>(j),
                    prototypeScenes_[in.prototype].get(), in.worldFromObject);
    }
    hasGeometry_ = true;
    rtcCommitScene(rtcScene_.get());
    check("rtcCommitScene");
    memoryAfterCommit_ = static_cast<size_t>(std::max<int64_t>(0, log_->memoryBytes.load()));
    setRootBounds();
}

// The box every Embree geometry lies in (rtcGetSceneBounds), grown by a
// margin far above the rounding of the hits and of the slab test, so that
// the packet pre-test (keepLanesInRootBounds) passes every ray Embree could hit.
void EmbreeBvh::setRootBounds() {
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

template <class Shape>
void EmbreeBvh::addUserGeometry(RTCScene target, RTCBuildQuality quality) {
    const auto& shapes = ShapeTraits<Shape>::of(sceneData_);
    if (shapes.empty()) return;
    EmbreeGeometry g(rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_USER));
    check("rtcNewGeometry(user)");
    RTCGeometry geom = g.get();
    rtcSetGeometryUserPrimitiveCount(geom, static_cast<unsigned>(shapes.size()));
    // Callbacks only read the scene.
    rtcSetGeometryUserData(geom, const_cast<Scene*>(&sceneData_));
    rtcSetGeometryBoundsFunction(geom, &UserShapeCallbacks<Shape>::boundsFn, nullptr);
    rtcSetGeometryIntersectFunction(geom, &UserShapeCallbacks<Shape>::intersectFn);
    rtcSetGeometryOccludedFunction(geom, &UserShapeCallbacks<Shape>::occludedFn);
    rtcSetGeometryBuildQuality(geom, quality);
    rtcCommitGeometry(geom);
    check("user geometry setup");
    rtcAttachGeometryByID(target, geom, ShapeTraits<Shape>::kGeomId);
    check("rtcAttachGeometryByID(user)");
    hasGeometry_ = true;
}

// A quad geometry from corner positions (4 per quad, in order around it).
void EmbreeBvh::addQuads(RTCScene target, const std::vector<Vec3f>& corners, unsigned geomId, RTCBuildQuality quality,
                         const char* what, bool cuts) {
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
    setAlphaFilter(geom, cuts);
    rtcSetGeometryBuildQuality(geom, quality);
    rtcCommitGeometry(geom);
    check(what);
    rtcAttachGeometryByID(target, geom, geomId);
    check(what);
    hasGeometry_ = true;
}

// Each box as its six faces, corners transformed to world space (an
// affine map keeps every face a planar parallelogram).
void EmbreeBvh::addBoxQuads(RTCScene target, RTCBuildQuality quality) {
    static constexpr int kFaces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                                         {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
    std::vector<Vec3f> corners;
    for (size_t i = 0; i < sceneData_.boxes.size(); ++i) {
        const Box& b = sceneData_.boxes[i];
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
    addQuads(target, corners, kBoxGeomId, quality, "box quads setup");
}

// Each rectangle p0, p0 + a, p0 + a + b, p0 + b: Embree's quad (u, v) is then (s, t).
void EmbreeBvh::addRectangleQuads(RTCScene target, RTCBuildQuality quality, bool cuts) {
    std::vector<Vec3f> corners;
    for (const Rectangle& q : sceneData_.rectangles)
        corners.insert(corners.end(), {q.p0, q.p0 + q.a, q.p0 + q.a + q.b, q.p0 + q.b});
    addQuads(target, corners, kRectangleGeomId, quality, "rectangle quads setup", cuts);
}

void EmbreeBvh::attachMesh(const TriangleMesh& m, RTCScene target, unsigned geomId, RTCBuildQuality quality,
                           bool cuts) {
    EmbreeGeometry g(rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_TRIANGLE));
    check("rtcNewGeometry(triangle)");
    RTCGeometry geom = g.get();
    // Shared, not copied: the Scene outlives the accelerator, and
    // PositionBuffer keeps the padding Embree's 16-byte loads need.
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, m.positions.data(), 0,
                               sizeof(Vec3f), m.positions.size());
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, m.indices.data(), 0,
                               3 * sizeof(uint32_t), m.triangleCount());
    setAlphaFilter(geom, cuts);
    rtcSetGeometryBuildQuality(geom, quality);
    rtcCommitGeometry(geom);
    check(("mesh '" + m.name + "' setup").c_str());
    rtcAttachGeometryByID(target, geom, geomId);
    check(("rtcAttachGeometryByID(mesh '" + m.name + "')").c_str());
}

// The prototype's own scene, built on first use: instances share it.
RTCScene EmbreeBvh::prototypeScene(uint32_t index, RTCBuildQuality quality, const AlphaTest& alpha) {
    EmbreeScene& ps = prototypeScenes_[index];
    if (ps) return ps.get();
    const Prototype& p = sceneData_.prototypes[index];
    ps = newScene(quality, "rtcNewScene(prototype)");
    for (size_t k = 0; k < p.meshes.size(); ++k)
        attachMesh(p.meshes[k], ps.get(), static_cast<unsigned>(k), quality,
                   alpha.prototypeMeshCutsOut(index, static_cast<uint32_t>(k)));
    rtcCommitScene(ps.get());
    check(("rtcCommitScene(prototype '" + p.name + "')").c_str());
    return ps.get();
}

void EmbreeBvh::addInstance(RTCScene target, unsigned geomId, RTCScene prototype, const Transform& worldFromObject) {
    EmbreeGeometry g(rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_INSTANCE));
    check("rtcNewGeometry(instance)");
    RTCGeometry geom = g.get();
    rtcSetGeometryInstancedScene(geom, prototype);
    float m[3][4];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) m[r][c] = worldFromObject(r, c);
    rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, &m[0][0]);
    rtcCommitGeometry(geom);
    check("instance setup");
    rtcAttachGeometryByID(target, geom, geomId);
    check("rtcAttachGeometryByID(instance)");
}

}  // namespace penumbra
