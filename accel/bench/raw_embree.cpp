// The raw Embree ceiling (see raw_embree.h): deliberately the least code that
// can answer a ray with Embree, so the benchmark's renderer/raw ratio measures
// the renderer's own overhead and nothing of this harness.
#include "accel/bench/raw_embree.h"

#include "accel/embree_packets.h"

#include <atomic>
#include <chrono>
#include <string>

#include "accel/embree_device.h"
#include "core/error.h"

namespace penumbra {
namespace {

using Clock = std::chrono::steady_clock;

RTCBuildQuality toEmbreeQuality(BuildQuality q) {
    switch (q) {
        case BuildQuality::Low: return RTC_BUILD_QUALITY_LOW;
        case BuildQuality::Medium: return RTC_BUILD_QUALITY_MEDIUM;
        case BuildQuality::High: return RTC_BUILD_QUALITY_HIGH;
    }
    return RTC_BUILD_QUALITY_HIGH;
}

}  // namespace

struct RawEmbreeScene::Impl {
    // Declared before the handles: the device reports frees into it while it is released.
    std::atomic<int64_t> memory{0};
    size_t memoryAfterCommit = 0;
    double deviceSeconds = 0.0;
    double buildSeconds = 0.0;
    size_t triangles = 0;
    bool coversScene = false;
    bool native[3] = {false, false, false};  // 4, 8, 16
    EmbreeDevice device;
    EmbreeScene scene;

    static bool memoryMonitor(void* user, ssize_t bytes, bool /*post*/) {
        static_cast<Impl*>(user)->memory.fetch_add(bytes, std::memory_order_relaxed);
        return true;
    }

    void check(const char* what) const {
        const RTCError e = rtcGetDeviceError(device.get());
        if (e != RTC_ERROR_NONE)
            throw Error(ErrorCode::Embree, std::string("raw Embree scene: error ") + std::to_string(int(e)) +
                                               " during " + what);
    }

    template <int W>
    void intersectPackets(const Ray* rays, size_t count, RawHit* out) const {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        alignas(64) int valid[W];
        alignas(64) typename Packet<W>::RayHit rh;
        for (size_t base = 0; base < count; base += W) {
            const int n = static_cast<int>(std::min<size_t>(W, count - base));
            for (int l = 0; l < W; ++l) {
                valid[l] = l < n ? -1 : 0;
                setLane(rh.ray, l, rays[base + size_t(l < n ? l : 0)]);
                rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
                rh.hit.primID[l] = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
            }
            Packet<W>::intersect(valid, scene.get(), &ctx, &rh);
            for (int l = 0; l < n; ++l)
                out[base + size_t(l)] = RawHit{rh.hit.geomID[l] == RTC_INVALID_GEOMETRY_ID ? kRawMiss : rh.hit.geomID[l],
                                               rh.hit.primID[l], rh.ray.tfar[l]};
        }
    }

    template <int W>
    void occludedPackets(const Ray* rays, size_t count, uint8_t* out) const {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        alignas(64) int valid[W];
        alignas(64) typename Packet<W>::RayOnly r;
        for (size_t base = 0; base < count; base += W) {
            const int n = static_cast<int>(std::min<size_t>(W, count - base));
            for (int l = 0; l < W; ++l) {
                valid[l] = l < n ? -1 : 0;
                setLane(r, l, rays[base + size_t(l < n ? l : 0)]);
            }
            Packet<W>::occluded(valid, scene.get(), &ctx, &r);
            for (int l = 0; l < n; ++l) out[base + size_t(l)] = r.tfar[l] == -kInfinity ? 1 : 0;
        }
    }
};

RawEmbreeScene::RawEmbreeScene(const Scene& scene, const RawEmbreeOptions& options) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    auto t0 = Clock::now();
    m.device = EmbreeDevice(rtcNewDevice(nullptr));
    if (!m.device) throw Error(ErrorCode::Embree, "raw Embree scene: rtcNewDevice failed");
    rtcSetDeviceMemoryMonitorFunction(m.device.get(), &Impl::memoryMonitor, &m);
    m.deviceSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
    m.native[0] = rtcGetDeviceProperty(m.device.get(), RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED) != 0;
    m.native[1] = rtcGetDeviceProperty(m.device.get(), RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) != 0;
    m.native[2] = rtcGetDeviceProperty(m.device.get(), RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) != 0;
    m.check("device setup");

    const RTCBuildQuality quality = toEmbreeQuality(options.quality);
    t0 = Clock::now();
    m.scene = EmbreeScene(rtcNewScene(m.device.get()));
    if (options.robust) rtcSetSceneFlags(m.scene.get(), RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(m.scene.get(), quality);
    for (size_t i = 0; i < scene.meshes.size(); ++i) {
        const TriangleMesh& mesh = scene.meshes[i];
        EmbreeGeometry g(rtcNewGeometry(m.device.get(), RTC_GEOMETRY_TYPE_TRIANGLE));
        rtcSetSharedGeometryBuffer(g.get(), RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, mesh.positions.data(), 0,
                                   sizeof(Vec3f), mesh.positions.size());
        rtcSetSharedGeometryBuffer(g.get(), RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(), 0,
                                   3 * sizeof(uint32_t), mesh.triangleCount());
        rtcSetGeometryBuildQuality(g.get(), quality);
        rtcCommitGeometry(g.get());
        rtcAttachGeometryByID(m.scene.get(), g.get(), static_cast<unsigned>(i));
        m.triangles += mesh.triangleCount();
    }
    rtcCommitScene(m.scene.get());
    m.buildSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
    m.check("scene build");
    m.memoryAfterCommit = static_cast<size_t>(std::max<int64_t>(0, m.memory.load()));
    m.coversScene = scene.spheres.empty() && scene.planes.empty() && scene.boxes.empty() && scene.rectangles.empty() &&
                    scene.disks.empty();
}

RawEmbreeScene::~RawEmbreeScene() {
    if (impl_) {
        impl_->scene.reset();
        impl_->device.reset();
    }
}

double RawEmbreeScene::deviceSeconds() const { return impl_->deviceSeconds; }
double RawEmbreeScene::buildSeconds() const { return impl_->buildSeconds; }
size_t RawEmbreeScene::memoryBytes() const { return impl_->memoryAfterCommit; }
size_t RawEmbreeScene::triangleCount() const { return impl_->triangles; }
bool RawEmbreeScene::coversScene() const { return impl_->coversScene; }

bool RawEmbreeScene::nativePacket(int width) const {
    switch (width) {
        case 4: return impl_->native[0];
        case 8: return impl_->native[1];
        case 16: return impl_->native[2];
        default: return false;
    }
}

void RawEmbreeScene::intersect1(const Ray* rays, size_t count, RawHit* out) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCScene scene = impl_->scene.get();
    RTCRayHit rh;
    for (size_t i = 0; i < count; ++i) {
        const Ray& r = rays[i];
        rh.ray.org_x = r.o.x;
        rh.ray.org_y = r.o.y;
        rh.ray.org_z = r.o.z;
        rh.ray.tnear = r.tnear;
        rh.ray.dir_x = r.d.x;
        rh.ray.dir_y = r.d.y;
        rh.ray.dir_z = r.d.z;
        rh.ray.time = 0.f;
        rh.ray.tfar = r.tfar;
        rh.ray.mask = ~0u;
        rh.ray.id = 0;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ctx, &rh);
        out[i] = RawHit{rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? kRawMiss : rh.hit.geomID, rh.hit.primID, rh.ray.tfar};
    }
}

void RawEmbreeScene::occluded1(const Ray* rays, size_t count, uint8_t* out) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCScene scene = impl_->scene.get();
    RTCRay q;
    for (size_t i = 0; i < count; ++i) {
        const Ray& r = rays[i];
        q.org_x = r.o.x;
        q.org_y = r.o.y;
        q.org_z = r.o.z;
        q.tnear = r.tnear;
        q.dir_x = r.d.x;
        q.dir_y = r.d.y;
        q.dir_z = r.d.z;
        q.time = 0.f;
        q.tfar = r.tfar;
        q.mask = ~0u;
        q.id = 0;
        q.flags = 0;
        rtcOccluded1(scene, &ctx, &q);
        out[i] = q.tfar == -kInfinity ? 1 : 0;
    }
}

void RawEmbreeScene::intersectPackets(int width, const Ray* rays, size_t count, RawHit* out) const {
    switch (width) {
        case 4: impl_->intersectPackets<4>(rays, count, out); return;
        case 8: impl_->intersectPackets<8>(rays, count, out); return;
        case 16: impl_->intersectPackets<16>(rays, count, out); return;
        default: throw Error(ErrorCode::InvalidArgument, "packet width must be 4, 8 or 16, not " + std::to_string(width));
    }
}

void RawEmbreeScene::occludedPackets(int width, const Ray* rays, size_t count, uint8_t* out) const {
    switch (width) {
        case 4: impl_->occludedPackets<4>(rays, count, out); return;
        case 8: impl_->occludedPackets<8>(rays, count, out); return;
        case 16: impl_->occludedPackets<16>(rays, count, out); return;
        default: throw Error(ErrorCode::InvalidArgument, "packet width must be 4, 8 or 16, not " + std::to_string(width));
    }
}

}  // namespace penumbra
