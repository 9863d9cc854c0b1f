// The Embree side of the Embree accelerator, built once from a finalized
// scene: the device, the scene and its geometries, the prototypes' scenes,
// and what the queries (accel/embree_accelerator.cpp) need to map a hit back
// to the scene's arrays and to skip packets that can meet nothing.
//
// Geometry layout, attached by ID so hits map back to the Scene's arrays:
//   geomID 0      spheres (user geometry, callbacks over the packet lanes as
//                 arrays), primID = index in Scene::spheres; none where the
//                 accelerator tests the spheres and boxes itself (below)
//   geomID 1      boxes as native quads, 6 per box; boxOfQuad_[primID] = box;
//                 none where the accelerator tests them itself
//   geomID 2      rectangles as native quads, primID = index in Scene::rectangles
//   geomID 3      disks (user geometry), primID = index in Scene::disks
//   geomID 4 + i  scene.meshes[i] as a native triangle mesh, primID = triangle
//
// A scene with instances has two levels: everything above lives in a world
// scene of its own, placed in the top-level scene by an identity instance
// (top-level geomID 0), and scene.instances[j] is top-level geomID 1 + j, an
// Embree instance of its prototype's scene; a hit has instID[0] = that geomID,
// geomID = the mesh within the prototype, primID = triangle. So an edit that
// moves instances (EmbreeBvh's editing constructor) commits a new top level
// over the same world and prototype scenes, and rebuilds neither. A scene
// without instances keeps one level: the world scene is the top level, so it
// pays no instance indirection. (Spheres and disks report no instID; an
// identity transform leaves every ray coordinate as it was.)
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
// out of Embree: the queries test them analytically. So do the spheres and
// boxes of a scene of few shapes (accel/lane_shapes.h).
//
// Alpha: the meshes and rectangles whose materials can cut out (AlphaTest)
// get intersection and occlusion filter functions that ask AlphaTest::present
// of each candidate hit; opaque geometry gets none and pays nothing. The
// filters read the rule and this BVH through the query's context
// (EmbreeQueryContext), and the Blend key of each ray from its id field,
// which Embree carries unchanged into instances.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "accel/accelerator.h"
#include "accel/embree_device.h"

namespace penumbra {

class EmbreeBvh;

/// The context every query hands Embree: Embree's own first (the filters get
/// a pointer to it), then what the alpha filters read.
struct EmbreeQueryContext {
    RTCIntersectContext embree;
    const EmbreeBvh* bvh;
    const AlphaTest* alpha;

    EmbreeQueryContext(const EmbreeBvh& b, const AlphaTest& a) : bvh(&b), alpha(&a) { rtcInitIntersectContext(&embree); }
};

class EmbreeBvh {
public:
    /// Builds every geometry and commits the scene. Throws Error(Embree) with
    /// the device's messages when Embree reports an error. The scene must
    /// outlive the BVH (its mesh buffers are shared with Embree, not copied).
    /// `alpha` says which geometries get the alpha filters (only read here).
    /// withoutSpheresAndBoxes: the queries test those themselves (LaneShapes).
    EmbreeBvh(const Scene& scene, BuildQuality quality, const AlphaTest& alpha, bool withoutSpheresAndBoxes);
    /// The BVH of `scene`, which is base's scene with instances moved (and
    /// lights changed, and materials that leave the alpha filters as they
    /// were: the accelerator checks, AlphaTest::sameGeometries): shares base's
    /// device, world and prototype scenes, and commits a new top level (or
    /// shares base's whole scene when it has no instances). `buffers` owns
    /// the scene whose buffers those shared scenes read.
    EmbreeBvh(const EmbreeBvh& base, const Scene& scene, std::shared_ptr<const void> buffers);
    ~EmbreeBvh();
    // The device calls back into this object: it stays where it was built.
    EmbreeBvh(const EmbreeBvh&) = delete;
    EmbreeBvh& operator=(const EmbreeBvh&) = delete;

    /// The committed scene; answer queries only where hasGeometry().
    RTCScene scene() const { return rtcScene_.get(); }
    /// Whether anything but planes went into Embree.
    bool hasGeometry() const { return hasGeometry_; }

    /// A hit of Embree's as the scene's PrimRef (the layout above).
    PrimRef refOf(unsigned geomID, unsigned primID, unsigned instID) const {
        if (instID != RTC_INVALID_GEOMETRY_ID && instID != kWorldInstanceGeomId)
            return PrimRef{ShapeKind::Instance, instID - kFirstInstanceGeomId, primID, geomID};
        if (geomID >= kFirstMeshGeomId) return PrimRef{ShapeKind::Mesh, geomID - kFirstMeshGeomId, primID};
        if (geomID == kBoxGeomId) return PrimRef{ShapeKind::Box, boxOfQuad_[primID], 0};
        return PrimRef{kKindOfGeom[geomID], primID, 0};
    }

    /// The box every Embree geometry lies in (rtcGetSceneBounds), grown by a
    /// margin far above the rounding of the hits and of a slab test, so that a
    /// ray that misses it can meet nothing Embree holds. False where there is
    /// no such finite box (then every ray must be asked).
    bool rootBounds(Vec3f& lo, Vec3f& hi) const {
        lo = rootLo_;
        hi = rootHi_;
        return hasRootBounds_;
    }

    /// Bytes Embree's device held after the commit (its memory monitor;
    /// edited scenes share their base's device, and this counts it all).
    size_t memoryBytes() const { return memoryAfterCommit_; }

private:
    static constexpr unsigned kBoxGeomId = 1, kRectangleGeomId = 2, kFirstMeshGeomId = 4;
    static constexpr unsigned kWorldInstanceGeomId = 0, kFirstInstanceGeomId = 1;  // top level, two levels
    static constexpr ShapeKind kKindOfGeom[4] = {ShapeKind::Sphere, ShapeKind::Box, ShapeKind::Rectangle,
                                                 ShapeKind::Disk};

    // What the device's callbacks write: shared by every BVH on the device.
    struct DeviceLog {
        std::mutex mutex;
        std::vector<std::string> errors;
        std::atomic<int64_t> memoryBytes{0};
    };
    static void errorCallback(void* userPtr, RTCError code, const char* str);
    static bool memoryCallback(void* userPtr, ssize_t bytes, bool post);
    void check(const char* what);
    void build(RTCBuildQuality quality, const AlphaTest& alpha);
    static void alphaFilter(const RTCFilterFunctionNArguments* args);
    static void setAlphaFilter(RTCGeometry geom, bool cuts);
    EmbreeScene newScene(RTCBuildQuality quality, const char* what);
    void buildWorld(RTCScene target, RTCBuildQuality quality, const AlphaTest& alpha);
    void commitTop(RTCBuildQuality quality);
    void setRootBounds();
    template <class Shape>
    void addUserGeometry(RTCScene target, RTCBuildQuality quality);
    void addQuads(RTCScene target, const std::vector<Vec3f>& corners, unsigned geomId, RTCBuildQuality quality,
                  const char* what, bool cuts = false);
    void addBoxQuads(RTCScene target, RTCBuildQuality quality);
    void addRectangleQuads(RTCScene target, RTCBuildQuality quality, bool cuts);
    void attachMesh(const TriangleMesh& m, RTCScene target, unsigned geomId, RTCBuildQuality quality, bool cuts);
    RTCScene prototypeScene(uint32_t index, RTCBuildQuality quality, const AlphaTest& alpha);
    void addInstance(RTCScene target, unsigned geomId, RTCScene prototype, const Transform& worldFromObject);

    const Scene& sceneData_;
    // Declared before the Embree handles so it outlives them: the device
    // calls back into it while it releases its memory.
    std::shared_ptr<DeviceLog> log_ = std::make_shared<DeviceLog>();
    std::shared_ptr<const void> buffers_;  // an edited BVH's: the scene its shared scenes read
    RTCBuildQuality quality_ = RTC_BUILD_QUALITY_HIGH;
    bool withoutSpheresAndBoxes_ = false;
    size_t memoryAfterCommit_ = 0;
    bool hasGeometry_ = false;
    bool hasRootBounds_ = false;  // rootLo_/rootHi_ hold the padded bounds of the Embree geometry
    Vec3f rootLo_, rootHi_;
    std::vector<uint32_t> boxOfQuad_;  // box index of each box quad (primID)
    bool worldHasGeometry_ = false;

    EmbreeDevice device_;
    std::vector<EmbreeScene> prototypeScenes_;  // by prototype index; empty handles for unused ones
    EmbreeScene worldScene_;                    // the world scene when the scene has instances
    EmbreeScene rtcScene_;
};

}  // namespace penumbra
