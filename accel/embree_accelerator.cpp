// The Embree accelerator's queries (Embree 3.13; accel/embree_bvh.h builds
// what they ask): single rays, batches as 4/8/16-wide packets, and the
// renderer's 16 lanes. Every ray is validated before Embree sees it; packets
// that can meet nothing (outside the root bounds, or, for occlusion and for
// rays leaving a convex mesh, clear of every other shape's bounds in a scene
// of few shapes) skip Embree's call.
//
// Planes, and the spheres and boxes of a scene of few shapes, stay out of
// Embree and are tested over the lanes here (accel/lane_shapes.h): after the
// Embree closest-hit query (with tfar clipped to the Embree hit) and before the
// occlusion query. Both accelerators therefore return identical hits on them.
//
// Where the scene has geometry that can cut out (AlphaTest::any), every ray's
// id field carries its alphaRayKey for the alpha filters (accel/embree_bvh.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "accel/accelerator.h"
#include "accel/embree_bvh.h"
#include "accel/embree_packets.h"
#include "accel/lane_shapes.h"
#include "accel/shape_bounds.h"
#include "core/lane_clones.h"

namespace penumbra {
namespace {

inline RTCRay toRtcRay(const Ray& r, float tfar, bool keyed) {
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
    ray.id = keyed ? alphaRayKey(r) : 0;
    ray.flags = 0;
    return ray;
}

class EmbreeAccelerator final : public Accelerator {
public:
    EmbreeAccelerator(const Scene& scene, BuildQuality quality, std::shared_ptr<const TextureCache> textures)
        : Accelerator(scene, std::move(textures)),
          quality_(quality),
          laneShapes_(scene, shapeBounds().available()),
          bvh_(scene, quality, alpha_, laneShapes_.holdsSpheresAndBoxes()) {
        takesLeavingHints_ = usesLeavingHints(scene);
    }
    EmbreeAccelerator(const EmbreeAccelerator& base, const Scene& scene, std::shared_ptr<const void> buffers)
        : Accelerator(scene, base.textures_),
          quality_(base.quality_),
          laneShapes_(scene, base.laneShapes_.holdsSpheresAndBoxes()),
          bvh_(base.bvh_, scene, std::move(buffers)) {
        takesLeavingHints_ = usesLeavingHints(scene);
    }

    std::unique_ptr<Accelerator> edited(const Scene& scene, std::shared_ptr<const void> buffers) const override {
        // The shared geometries carry the base's filters: edited materials
        // that change which geometry can cut out need a BVH of their own.
        if (!alpha_.sameGeometries(AlphaTest(scene, textures_)))
            return std::make_unique<EmbreeAccelerator>(scene, quality_, textures_);
        return std::make_unique<EmbreeAccelerator>(*this, scene, std::move(buffers));
    }

    std::optional<PrimIntersection> intersectPrim(const Ray& ray) const override {
        if (!acceptRay(ray)) return std::nullopt;
        if (!(ray.tfar > ray.tnear)) return std::nullopt;  // empty interval (tnear, tfar]
        std::optional<PrimIntersection> best;
        Ray r = ray;
        if (bvh_.hasGeometry()) {
            EmbreeQueryContext ctx(bvh_, alpha_);
            RTCRayHit rh;
            rh.ray = toRtcRay(ray, ray.tfar, alpha_.any());
            rh.hit.Ng_x = rh.hit.Ng_y = rh.hit.Ng_z = 0.f;
            rh.hit.u = rh.hit.v = 0.f;
            rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            for (unsigned& id : rh.hit.instID) id = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(bvh_.scene(), &ctx.embree, &rh);
            if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
                best = PrimIntersection{bvh_.refOf(rh.hit.geomID, rh.hit.primID, rh.hit.instID[0]), rh.ray.tfar,
                                        rh.hit.u, rh.hit.v};
                r.tfar = rh.ray.tfar;
            }
        }
        const int shape = laneShapes_.closest(r);
        if (shape >= 0) best = PrimIntersection{laneShapes_.ref(shape), r.tfar, 0.f, 0.f};
        return best;
    }

    // The virtual entry points hand over to non-virtual bodies compiled per ISA (core/lane_clones.h).
    void intersectPrimBatch(std::span<const Ray> rays, std::span<std::optional<PrimIntersection>> out, bool coherent,
                            std::span<const int32_t> leaving) const override {
        intersectPackets(rays, out, coherent, leaving.empty() ? nullptr : leaving.data());
    }

    PENUMBRA_LANE_CLONES void intersectPackets(std::span<const Ray> rays, std::span<std::optional<PrimIntersection>> out,
                                               bool coherent, const int32_t* leaving) const {
        // Packets as wide as the remaining rays need: 16, 8 or 4 lanes.
        for (size_t i = 0; i < rays.size();) {
            const size_t left = rays.size() - i;
            const int32_t* leave = leaving ? leaving + i : nullptr;
            if (left == 1) {
                out[i] = intersectPrim(rays[i]);
                i += 1;
            } else if (left <= 4) {
                i += intersectPacket<4>(rays.subspan(i), out.subspan(i), coherent, leave);
            } else if (left <= 8) {
                i += intersectPacket<8>(rays.subspan(i), out.subspan(i), coherent, leave);
            } else {
                i += intersectPacket<16>(rays.subspan(i), out.subspan(i), coherent, leave);
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

    // Writes up to W rays into a packet's lanes (idle rays after the last)
    // and marks in ok[] the lanes whose ray is valid (isValidRay), counting
    // the invalid ones; their lanes get the idle ray, so no invalid ray
    // reaches Embree. The tests run over the lanes as arrays (vectorised).
    template <int W, class PacketRay>
    void loadLanes(std::span<const Ray> rays, int n, PacketRay& p, int* ok) const {
        for (int l = 0; l < W; ++l) setLane(p, l, l < n ? rays[l] : kIdleLane);
        keyLanes<W>(p);
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
    // so no invalid ray reaches Embree; they miss, exactly as intersectPrim
    // says. leaving: null, or the hints of the packet's rays (intersectPrimBatch).
    template <int W>
    [[gnu::always_inline]] size_t intersectPacket(std::span<const Ray> rays,
                                                  std::span<std::optional<PrimIntersection>> out, bool coherent,
                                                  const int32_t* leaving) const {
        const int n = static_cast<int>(std::min<size_t>(W, rays.size()));
        alignas(64) int ok[W];
        alignas(64) typename Packet<W>::RayHit rh;
        loadLanes<W>(rays, n, rh.ray, ok);
        alignas(64) int32_t leave[W];
        const bool hinted = leaving && loadLeaving<W>(leaving, n, leave);
        answerPacket<W>(rh, ok, n, out.data(), coherent, hinted ? leave : nullptr);
        return size_t(n);
    }

    // The first n hints into a packet's W lanes (-1 beyond); whether any ray
    // leaves a convex mesh in a scene whose queries take hints.
    template <int W>
    [[gnu::always_inline]] bool loadLeaving(const int32_t* leaving, int n, int32_t* leave) const {
        int any = 0;
        for (int l = 0; l < W; ++l) {
            leave[l] = l < n ? leaving[l] : -1;
            any |= int(leave[l] >= 0);
        }
        return any && takesLeavingHints();
    }

    void intersectPrimLanes(const RayLanes& rays, std::optional<PrimIntersection>* out) const override {
        intersectRayLanes(rays, out);
    }

    PENUMBRA_LANE_CLONES void intersectRayLanes(const RayLanes& rays, std::optional<PrimIntersection>* out) const {
        alignas(64) int ok[RayLanes::kWidth];
        alignas(64) RTCRayHit16 rh;
        loadRayLanes(rays, rh.ray, ok);
        answerPacket<RayLanes::kWidth>(rh, ok, RayLanes::kWidth, out, true, nullptr);
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
    // the lanes run close together (a block of camera rays, or their mirror
    // rays: Accelerator::intersectPrimBatch), for Embree's coherent traversal
    // where sharesOneOctant allows it. leaving: null, or the lanes' hints
    // (intersectPrimBatch), some set, in a scene of few shapes: the lanes
    // that meet no shape Embree holds (their own convex mesh aside) skip it.
    template <int W>
    [[gnu::always_inline]] void answerPacket(typename Packet<W>::RayHit& rh, const int* ok, int n,
                                             std::optional<PrimIntersection>* out, bool coherent,
                                             const int32_t* leaving) const {
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
        if (any && bvh_.hasGeometry() && keepLanesInRootBounds<W>(rh.ray, query) &&
            (!leaving || keepLanesMeetingShapes<W>(rh.ray, query, leaving))) {
            EmbreeQueryContext ctx(bvh_, alpha_);
            if (coherent && sharesOneOctant<W>(rh.ray, query)) ctx.embree.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
            Packet<W>::intersect(query, bvh_.scene(), &ctx.embree, &rh);
        }
        // The shapes tested here after Embree, each against the lane's closest
        // hit so far (Embree shrank tfar to it).
        alignas(64) int shape[W];
        for (int l = 0; l < W; ++l) shape[l] = -1;
        laneShapes_.closest<W>(rh.ray, valid, shape);
        for (int l = 0; l < n; ++l) {
            if (!valid[l]) {
                out[l].reset();
            } else if (shape[l] >= 0) {
                out[l] = PrimIntersection{laneShapes_.ref(shape[l]), rh.ray.tfar[l], 0.f, 0.f};
            } else if (rh.hit.geomID[l] != RTC_INVALID_GEOMETRY_ID) {
                out[l] = PrimIntersection{bvh_.refOf(rh.hit.geomID[l], rh.hit.primID[l], rh.hit.instID[0][l]),
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
        occludedLoaded<W>(pr, ok, n, out.data(), nullptr);
        return size_t(n);
    }

    void occludedLanes(const RayLanes& rays, uint8_t* out, const int32_t* leaving) const override {
        occludedRayLanes(rays, out, leaving);
    }

    PENUMBRA_LANE_CLONES void occludedRayLanes(const RayLanes& rays, uint8_t* out, const int32_t* leaving) const {
        alignas(64) int ok[RayLanes::kWidth];
        alignas(64) RTCRay16 pr;
        loadRayLanes(rays, pr, ok);
        occludedLoaded<RayLanes::kWidth>(pr, ok, RayLanes::kWidth, out, leaving);
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
        keyLanes<W>(pr);
    }

    // The lanes' ids become their rays' alphaRayKey where the alpha filters read them.
    template <int W, class PacketRay>
    [[gnu::always_inline]] void keyLanes(PacketRay& p) const {
        if (!alpha_.any()) return;
        for (int l = 0; l < W; ++l)
            p.id[l] = alphaRayKey(p.org_x[l], p.org_y[l], p.org_z[l], p.dir_x[l], p.dir_y[l], p.dir_z[l]);
    }

    // The occlusion query of a loaded packet whose valid lanes ok[] marks
    // (the others hold the idle ray); writes the first n answers. leaving:
    // null, or the W lanes' hints (intersectPrimBatch).
    template <int W>
    [[gnu::always_inline]] void occludedLoaded(typename Packet<W>::RayOnly& pr, const int* ok, int n,
                                               uint8_t* out, const int32_t* leaving) const {
        alignas(64) int valid[W];
        alignas(64) int blocked[W];
        // The open interval (tnear, tfar), as in occluded(): every test here
        // accepts t <= tfar, so ask for the float just below tfar.
        for (int l = 0; l < W; ++l) pr.tfar[l] = nextFloatDown(pr.tfar[l]);
        for (int l = 0; l < W; ++l) blocked[l] = 0;
        laneShapes_.occlude<W>(pr, blocked);
        int any = 0;
        for (int l = 0; l < W; ++l) {
            const int open = ok[l] & (pr.tfar[l] > pr.tnear[l]);
            blocked[l] &= open;
            valid[l] = (open & !blocked[l] & int(bvh_.hasGeometry())) ? -1 : 0;
            any |= valid[l];
        }
        for (int l = 0; l < n; ++l) out[l] = static_cast<uint8_t>(blocked[l]);
        if (!any || !keepLanesInRootBounds<W>(pr, valid)) return;
        if (shapeBounds().available() && !keepLanesMeetingShapes<W>(pr, valid, leaving)) return;
        EmbreeQueryContext ctx(bvh_, alpha_);
        Packet<W>::occluded(valid, bvh_.scene(), &ctx.embree, &pr);
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
        if (laneShapes_.occludes(r)) return true;
        if (!bvh_.hasGeometry()) return false;
        EmbreeQueryContext ctx(bvh_, alpha_);
        RTCRay q = toRtcRay(r, r.tfar, alpha_.any());
        rtcOccluded1(bvh_.scene(), &ctx.embree, &q);
        return q.tfar == -kInfinity;
    }

    std::string name() const override { return "embree"; }

    size_t memoryBytes() const override { return bvh_.memoryBytes(); }

private:
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
        Vec3f lo, hi;
        const bool bounded = bvh_.rootBounds(lo, hi);
        int any = 0, outside = 0;
        for (int l = 0; l < W; ++l) {
            any |= valid[l];
            outside |= valid[l] & int(!(p.org_x[l] >= lo.x && p.org_x[l] <= hi.x && p.org_y[l] >= lo.y &&
                                         p.org_y[l] <= hi.y && p.org_z[l] >= lo.z && p.org_z[l] <= hi.z));
        }
        if (!bounded || !outside) return any != 0;
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
    // bounds of a shape Embree holds (accel/shape_bounds.h; not those of the
    // spheres and boxes laneShapes_ tests): slab tests against the boxes and
    // the closest approach to the spheres, over the lanes. Occlusion packets
    // and the closest-hit packets of rays that leave a convex mesh
    // (docs/accelerators.md says why not other closest-hit ones). As in
    // keepLanesInRootBounds, a NaN only keeps a lane. In a scene of a few
    // shapes most shadow rays cross open space between the surfaces (the
    // room: those from its walls to the light, past both spheres) and the
    // packet then skips Embree's call. leaving (null, or the W lanes' hints:
    // intersectPrimBatch): a lane does not meet the box of the convex mesh it
    // leaves. Returns whether any lane is left.
    template <int W, class PacketRay>
    [[gnu::always_inline]] bool keepLanesMeetingShapes(const PacketRay& p, int* valid, const int32_t* leaving) const {
        alignas(64) int meets[W];
        alignas(64) float ix[W], iy[W], iz[W];
        for (int l = 0; l < W; ++l) {
            meets[l] = 0;
            ix[l] = 1.f / (p.dir_x[l] != 0.f ? p.dir_x[l] : 1e-30f);
            iy[l] = 1.f / (p.dir_y[l] != 0.f ? p.dir_y[l] : 1e-30f);
            iz[l] = 1.f / (p.dir_z[l] != 0.f ? p.dir_z[l] : 1e-30f);
        }
        static constexpr int32_t kLeavingNone[16] = {-1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1};
        static_assert(W <= 16);
        const int32_t* leave = leaving ? leaving : kLeavingNone;
        const bool spheresAndBoxesHere = laneShapes_.holdsSpheresAndBoxes();
        for (const ShapeBounds::PaddedBox& b : shapeBounds().boxes()) {
            if (spheresAndBoxesHere && b.ref.kind == ShapeKind::Box) continue;
            const Vec3f lo = b.box.lo, hi = b.box.hi;
            const int32_t mesh = b.ref.kind == ShapeKind::Mesh ? int32_t(b.ref.object) : -2;
            for (int l = 0; l < W; ++l) {
                const float ax = (lo.x - p.org_x[l]) * ix[l], bx = (hi.x - p.org_x[l]) * ix[l];
                const float ay = (lo.y - p.org_y[l]) * iy[l], by = (hi.y - p.org_y[l]) * iy[l];
                const float az = (lo.z - p.org_z[l]) * iz[l], bz = (hi.z - p.org_z[l]) * iz[l];
                const float t0 =
                    std::max(std::max(p.tnear[l], std::min(ax, bx)), std::max(std::min(ay, by), std::min(az, bz)));
                const float t1 =
                    std::min(std::min(p.tfar[l], std::max(ax, bx)), std::min(std::max(ay, by), std::max(az, bz)));
                // A few ulps of t: the slab test's rounding. A lane does not meet the mesh it leaves.
                meets[l] |= int(!(t0 > t1 + 1e-6f * std::fabs(t1))) & int(leave[l] != mesh);
            }
        }
        for (const Sphere& s : spheresAndBoxesHere ? std::span<const Sphere>() : std::span(shapeBounds().spheres())) {
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

    // The hints are used where the shapes' bounds are kept (keepLanesMeetingShapes) and some mesh is convex.
    bool usesLeavingHints(const Scene& scene) const {
        return scene.convexMeshes() != nullptr && shapeBounds().available();
    }

    BuildQuality quality_;
    LaneShapes laneShapes_;  // before bvh_: it says what the BVH leaves out
    EmbreeBvh bvh_;
};

}  // namespace

std::unique_ptr<Accelerator> makeEmbreeAccelerator(const Scene& scene, BuildQuality quality,
                                                   std::shared_ptr<const TextureCache> textures) {
    return std::make_unique<EmbreeAccelerator>(scene, quality, std::move(textures));
}

}  // namespace penumbra
