// Accelerator behaviour beyond agreement: invalid rays, rays spawned far from
// the origin, empty and plane-only scenes, meshes without triangles, the
// factory, names, memory, and hit completion for every shape kind.
#include <gtest/gtest.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "accel/accelerator.h"
#include "core/error.h"
#include "core/sampling.h"
#include "core/scene.h"
#include "core/transform.h"
#include "support/both_accelerators.h"

namespace penumbra {
namespace {

Logger quietLogger() {
    return Logger([](LogLevel, std::string_view) {});
}

// What every accelerator must do alike runs once per accelerator.
class EachAccelerator : public test::ForBothAccelerators {};

TriangleMesh triangleCube(const Vec3f& lo, const Vec3f& hi) {
    TriangleMesh m;
    m.name = "cube";
    for (int i = 0; i < 8; ++i) m.positions.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    m.indices = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 4, 6, 0, 6, 2,
                 1, 3, 7, 1, 7, 5, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3};
    return m;
}

// One primitive of every kind, in front of a camera at z = 10 looking down -z.
Scene smallScene() {
    Scene s;
    s.spheres.push_back(Sphere{{-3.f, 0.f, 0.f}, 1.f, 0});
    s.boxes.push_back(makeBox({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}, Transform::translate({0.f, 0.f, 0.f})));
    s.rectangles.push_back(Rectangle{{2.f, -1.f, 0.f}, {2.f, 0.f, 0.f}, {0.f, 2.f, 0.f}, 0});
    s.disks.push_back(Disk{{0.f, 3.f, 0.f}, {0.f, 0.f, 1.f}, 1.f, 0});
    s.planes.push_back(Plane{{0.f, 0.f, -5.f}, {0.f, 0.f, 1.f}, true, 0});
    TriangleMesh tri;
    tri.positions.push_back({-1.f, -4.f, 0.f});
    tri.positions.push_back({1.f, -4.f, 0.f});
    tri.positions.push_back({0.f, -2.f, 0.f});
    tri.indices = {0, 1, 2};
    s.meshes.push_back(tri);
    s.finalize(quietLogger());
    return s;
}

TEST(AcceleratorTest, NamesFactoryAndMemory) {
    Scene scene = smallScene();
    auto naive = makeAccelerator(AcceleratorKind::Naive, scene);
    auto embree = makeAccelerator(AcceleratorKind::Embree, scene, BuildQuality::Low);
    EXPECT_EQ(naive->name(), "naive");
    EXPECT_EQ(embree->name(), "embree");
    EXPECT_EQ(naive->memoryBytes(), 0u);
    EXPECT_GT(embree->memoryBytes(), 0u);
    EXPECT_LT(embree->memoryBytes(), size_t(64) << 20);  // a handful of primitives: far below 64 MiB
    EXPECT_EQ(&embree->scene(), &scene);
    try {
        makeAccelerator(static_cast<AcceleratorKind>(2), scene);
        FAIL() << "expected an Error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("accelerator 2 is not an AcceleratorKind"), std::string::npos) << e.what();
    }
}

TEST_P(EachAccelerator, EveryKindIsFoundWithTheSameCompletedHit) {
    Scene scene = smallScene();
    struct Expect {
        Vec3f target;
        ShapeKind kind;
        float t;
        Vec3f ng;
    };
    const std::vector<Expect> cases = {
        {{-3.f, 0.f, 0.f}, ShapeKind::Sphere, 9.f, {0.f, 0.f, 1.f}},
        {{0.f, 0.f, 0.f}, ShapeKind::Box, 9.5f, {0.f, 0.f, 1.f}},
        {{3.f, 0.f, 0.f}, ShapeKind::Rectangle, 10.f, {0.f, 0.f, 1.f}},
        {{0.f, 3.f, 0.f}, ShapeKind::Disk, 10.f, {0.f, 0.f, 1.f}},
        {{0.f, -3.f, 0.f}, ShapeKind::Mesh, 10.f, {0.f, 0.f, 1.f}},
        {{6.f, 6.f, 0.f}, ShapeKind::Plane, 15.f, {0.f, 0.f, 1.f}},
    };
    {
        const auto acc = makeAccelerator(GetParam(), scene);
        for (const auto& c : cases) {
            Ray r{{c.target.x, c.target.y, 10.f}, {0.f, 0.f, -1.f}, 0.f, kInfinity};
            auto h = acc->intersect(r);
            ASSERT_TRUE(h) << acc->name() << " kind " << int(c.kind);
            EXPECT_EQ(h->ref.kind, c.kind) << acc->name();
            EXPECT_EQ(h->ref.object, 0u) << acc->name();
            EXPECT_NEAR(h->t, c.t, 1e-5f) << acc->name() << " kind " << int(c.kind);
            EXPECT_NEAR(h->ng.z, c.ng.z, 1e-6f) << acc->name();
            EXPECT_TRUE(acc->occluded(r)) << acc->name();
            // tfar is inclusive for intersect, exclusive for occluded.
            Ray upTo = r;
            upTo.tfar = c.t;
            EXPECT_TRUE(acc->intersect(upTo)) << acc->name() << " kind " << int(c.kind);
            EXPECT_FALSE(acc->occluded(upTo)) << acc->name() << " kind " << int(c.kind);
            upTo.tfar = c.t * 1.001f;
            EXPECT_TRUE(acc->occluded(upTo)) << acc->name() << " kind " << int(c.kind);
        }
        // Triangle (u, v) are the barycentrics of p1 and p2.
        auto tri = acc->intersectPrim(Ray{{0.f, -3.f, 10.f}, {0.f, 0.f, -1.f}, 0.f, kInfinity});
        ASSERT_TRUE(tri);
        EXPECT_NEAR(tri->u, 0.25f, 1e-6f) << acc->name();
        EXPECT_NEAR(tri->v, 0.5f, 1e-6f) << acc->name();
        // Rectangle (u, v) come from the analytic routine through Embree too.
        auto rect = acc->intersectPrim(Ray{{3.5f, 0.5f, 10.f}, {0.f, 0.f, -1.f}, 0.f, kInfinity});
        ASSERT_TRUE(rect);
        EXPECT_NEAR(rect->u, 0.75f, 1e-6f) << acc->name();
        EXPECT_NEAR(rect->v, 0.75f, 1e-6f) << acc->name();
        // Closest of several along one ray: the box in front of the plane.
        auto closest = acc->intersectPrim(Ray{{0.f, 0.f, 20.f}, {0.f, 0.f, -1.f}, 0.f, kInfinity});
        ASSERT_TRUE(closest);
        EXPECT_EQ(closest->ref.kind, ShapeKind::Box);
        EXPECT_FLOAT_EQ(closest->t, 19.5f);
        // Starting past the box: the plane behind it.
        auto behind = acc->intersectPrim(Ray{{0.f, 0.f, 20.f}, {0.f, 0.f, -1.f}, 21.f, kInfinity});
        ASSERT_TRUE(behind);
        EXPECT_EQ(behind->ref.kind, ShapeKind::Plane);
        EXPECT_FLOAT_EQ(behind->t, 25.f);
    }
}

TEST_P(EachAccelerator, InvalidRaysAreCountedMissesWithEmbreeToo) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    Scene scene = smallScene();
    const std::vector<Ray> invalid = {
        Ray{{nan, 0.f, 10.f}, {0.f, 0.f, -1.f}, 0.f, kInfinity},      // NaN origin
        Ray{{0.f, 0.f, 10.f}, {0.f, 0.f, -kInfinity}, 0.f, kInfinity},  // infinite direction
        Ray{{0.f, 0.f, 10.f}, {nan, 0.f, -1.f}, 0.f, kInfinity},      // NaN direction
        Ray{{0.f, 0.f, 2e18f}, {0.f, 0.f, -1.f}, 0.f, kInfinity},     // |origin| > 1.8e18
        Ray{{0.f, 0.f, kInfinity}, {0.f, 0.f, -1.f}, 0.f, kInfinity},  // infinite origin
        Ray{{0.f, 0.f, 10.f}, {0.f, 0.f, -1.f}, 0.f, nan},            // NaN tfar
        Ray{{0.f, 0.f, 10.f}, {0.f, 0.f, -1.f}, -1.f, kInfinity},     // negative tnear
        Ray{{0.f, 0.f, 10.f}, {0.f, 0.f, -1.f}, nan, kInfinity},      // NaN tnear
        Ray{{0.f, 0.f, 10.f}, {0.f, 0.f, 0.f}, 0.f, kInfinity},       // no direction
    };
    {
        const auto acc = makeAccelerator(GetParam(), scene);
        for (const Ray& r : invalid) {
            EXPECT_FALSE(acc->intersectPrim(r)) << acc->name();
            EXPECT_FALSE(acc->intersect(r)) << acc->name();
            EXPECT_FALSE(acc->occluded(r)) << acc->name();
        }
        EXPECT_EQ(acc->invalidRayCount(), 3 * invalid.size()) << acc->name();
        // Still working, and valid rays are not counted.
        Ray ok{{0.f, 0.f, 10.f}, {0.f, 0.f, -1.f}, 0.f, kInfinity};
        EXPECT_TRUE(acc->intersect(ok)) << acc->name();
        EXPECT_TRUE(acc->occluded(ok)) << acc->name();
        // A large but allowed origin, and an empty interval, are valid misses.
        EXPECT_FALSE(acc->intersect(Ray{{0.f, 1e18f, 0.f}, {0.f, 1.f, 0.f}, 0.f, kInfinity})) << acc->name();
        EXPECT_FALSE(acc->occluded(Ray{{0.f, 0.f, 10.f}, {0.f, 0.f, -1.f}, 5.f, 1.f})) << acc->name();
        EXPECT_FALSE(acc->intersect(Ray{{0.f, 0.f, 10.f}, {0.f, 0.f, -1.f}, 5.f, 1.f})) << acc->name();
        EXPECT_FALSE(acc->occluded(Ray{{0.f, 0.f, 10.f}, {0.f, 0.f, -1.f}, 0.f, 0.f})) << acc->name();
        EXPECT_EQ(acc->invalidRayCount(), 3 * invalid.size()) << acc->name();

        // The packet paths (their validity tests run over the lanes as arrays): each invalid
        // kind in a packet beside valid rays that hit, as 16, 8 and 4 lanes.
        for (const size_t width : {16u, 8u, 4u}) {
            for (const Ray& bad : invalid) {
                std::vector<Ray> rays(width, ok);
                rays[width / 2] = bad;
                std::vector<std::optional<PrimIntersection>> hits(width);
                std::vector<uint8_t> blocked(width, 7);
                const uint64_t before = acc->invalidRayCount();
                acc->intersectPrimBatch(rays, hits);
                acc->occludedBatch(rays, blocked);
                EXPECT_EQ(acc->invalidRayCount() - before, 2u) << acc->name() << " width " << width;
                for (size_t l = 0; l < width; ++l) {
                    const bool isBad = l == width / 2;
                    EXPECT_EQ(hits[l].has_value(), !isBad) << acc->name() << " width " << width << " lane " << l;
                    EXPECT_EQ(blocked[l], isBad ? 0 : 1) << acc->name() << " width " << width << " lane " << l;
                }
            }
        }
    }
}

TEST_P(EachAccelerator, RayLanesAnswerAsOccludedAndIntersectDoAndIdleLanesAreNotCounted) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    Scene scene = smallScene();
    const auto acc = makeAccelerator(GetParam(), scene);
    // Rays towards every shape, past them, short of them, across the plane, and two invalid ones.
    std::vector<Ray> rays;
    for (const Vec3f target : {Vec3f{-3, 0, 0}, Vec3f{0, 0, 0}, Vec3f{3, 0, 0}, Vec3f{0, 3, 0}, Vec3f{0, -3, 0}})
        for (const float far : {3.f, 9.5f, 20.f})
            rays.push_back(Ray{{0, 0, 10}, normalize(target - Vec3f{0, 0, 10}), 0.f, far});
    rays.push_back(Ray{{8, 8, 10}, {0, 0, -1}, 0.f, kInfinity});        // only the plane
    rays.push_back(Ray{{8, 8, 10}, {0, 0, 1}, 0.f, kInfinity});         // nothing
    rays.push_back(Ray{{nan, 0, 10}, {0, 0, -1}, 0.f, kInfinity});       // invalid
    rays.push_back(Ray{{0, 0, 10}, {0, 0, 0}, 0.f, kInfinity});          // invalid: no direction
    ASSERT_GT(rays.size(), size_t(RayLanes::kWidth));
    // Every ray in every lane position, with idle lanes between them.
    for (size_t first = 0; first < rays.size(); first += 3) {
        RayLanes lanes;
        std::vector<int> index(RayLanes::kWidth, -1);
        for (int l = 0; l < RayLanes::kWidth; ++l) {
            lanes.active[l] = l % 4 != 3;
            index[l] = lanes.active[l] ? int((first + size_t(l)) % rays.size()) : -1;
            // Idle lanes hold garbage that must not be read, counted or traced.
            lanes.set(l, lanes.active[l] ? rays[size_t(index[l])] : Ray{{nan, nan, nan}, {0, 0, 0}, -1.f, nan});
        }
        alignas(64) uint8_t out[RayLanes::kWidth];
        std::fill(out, out + RayLanes::kWidth, uint8_t(7));
        uint64_t expectedInvalid = 0;
        for (int l = 0; l < RayLanes::kWidth; ++l)
            if (index[l] >= 0) expectedInvalid += isValidRay(rays[size_t(index[l])]) ? 0 : 1;
        const uint64_t before = acc->invalidRayCount();
        acc->occludedLanes(lanes, out);
        EXPECT_EQ(acc->invalidRayCount() - before, expectedInvalid) << acc->name();
        int blocked = 0;
        for (int l = 0; l < RayLanes::kWidth; ++l) {
            const bool want = index[l] >= 0 && acc->occluded(rays[size_t(index[l])]);
            EXPECT_EQ(out[l], want ? 1 : 0) << acc->name() << " lane " << l;
            blocked += out[l];
        }
        EXPECT_GT(blocked, 0);

        // Closest hits: the completed hit of intersect(), nothing for idle lanes.
        EmptyOptionals<Hit, RayLanes::kWidth> hits;
        for (int l = 0; l < RayLanes::kWidth; ++l) hits[l].emplace();  // stale answers to be replaced
        const uint64_t beforeHits = acc->invalidRayCount();
        Ray asRays[RayLanes::kWidth];
        acc->intersectLanes(lanes, std::span<std::optional<Hit>>(hits.data(), RayLanes::kWidth), asRays);
        EXPECT_EQ(acc->invalidRayCount() - beforeHits, expectedInvalid) << acc->name();
        int found = 0;
        for (int l = 0; l < RayLanes::kWidth; ++l) {
            const Ray& r = asRays[l];
            const Ray lane = lanes.ray(l);
            EXPECT_EQ(std::memcmp(&r, &lane, sizeof(Ray)), 0) << acc->name() << " lane " << l
                                                              << ": the ray handed back is the lane's, bit for bit";
            const std::optional<Hit> want = index[l] >= 0 ? acc->intersect(rays[size_t(index[l])]) : std::nullopt;
            ASSERT_EQ(hits[l].has_value(), want.has_value()) << acc->name() << " lane " << l;
            if (!want) continue;
            ++found;
            EXPECT_EQ(hits[l]->ref, want->ref) << acc->name() << " lane " << l;
            EXPECT_EQ(hits[l]->t, want->t) << acc->name() << " lane " << l;
            EXPECT_EQ(hits[l]->p, want->p) << acc->name() << " lane " << l;
            EXPECT_EQ(hits[l]->ns, want->ns) << acc->name() << " lane " << l;
        }
        EXPECT_GT(found, 0);
    }
}

// Shoots rays at a scene ~1e4 from the origin, then a secondary ray from each
// hit (spawnRay: reflected away from the surface) and a shadow ray towards a
// point outside; a convex object must never be hit again by either.
struct SelfHitCount {
    int primaryHits = 0, reHits = 0, shadowBlocked = 0;
};

SelfHitCount shootSelfHitRays(const Accelerator& acc, const Vec3f& center, uint32_t seed) {
    std::mt19937 g(seed);
    auto uni = [&] { return static_cast<float>(g() >> 8) * 0x1p-24f; };
    SelfHitCount c;
    for (int i = 0; i < 400; ++i) {
        Vec3f w = squareToUniformSphere({uni(), uni()});
        if (w.y < 0.2f) w.y = -w.y + 0.2f;  // stay above the plane through the centre
        w = normalize(w);
        Vec3f eye = center + 300.f * w;
        Vec3f aim = center + Vec3f{uni() * 100.f - 50.f, uni() * 20.f - 10.f, uni() * 100.f - 50.f};
        Ray r{eye, normalize(aim - eye), 0.f, kInfinity};
        auto h = acc.intersect(r);
        if (!h) continue;
        ++c.primaryHits;
        Vec3f refl = normalize(reflect(r.d, h->ng));
        Ray second = spawnRay(h->p, h->ng, refl);
        if (acc.intersect(second) || acc.occluded(second)) ++c.reHits;
        Ray shadow = spawnRayTo(h->p, h->ng, h->p + 500.f * normalize(h->ng + 0.3f * w));
        if (acc.occluded(shadow)) ++c.shadowBlocked;
    }
    return c;
}

// FTZ/DAZ as in render threads, restored on exit.
class FlushDenormalsScope {
public:
    FlushDenormalsScope() : ftz_(_MM_GET_FLUSH_ZERO_MODE()), daz_(_MM_GET_DENORMALS_ZERO_MODE()) {
        _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
        _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
    }
    ~FlushDenormalsScope() {
        _MM_SET_FLUSH_ZERO_MODE(ftz_);
        _MM_SET_DENORMALS_ZERO_MODE(daz_);
    }
    FlushDenormalsScope(const FlushDenormalsScope&) = delete;
    FlushDenormalsScope& operator=(const FlushDenormalsScope&) = delete;

private:
    unsigned ftz_, daz_;
};

TEST_P(EachAccelerator, RaysSpawnedFarFromTheOriginDoNotReHitTheirSurface) {
    FlushDenormalsScope ftz;
    const Vec3f c{1e4f, 1e4f, -1e4f};
    std::vector<Scene> scenes(5);
    scenes[0].planes.push_back(Plane{c, normalize(Vec3f{0.1f, 1.f, -0.05f}), false, 0});
    scenes[1].boxes.push_back(makeBox({-40.f, -40.f, -40.f}, {40.f, 40.f, 40.f}, Transform::translate(c)));
    scenes[2].boxes.push_back(makeBox({-40.f, -40.f, -40.f}, {40.f, 40.f, 40.f},
                                      Transform::translate(c) * Transform::rotate(33.f, {1.f, 2.f, 0.5f})));
    scenes[3].spheres.push_back(Sphere{c, 45.f, 0});
    scenes[4].meshes.push_back(triangleCube(c - Vec3f(40.f), c + Vec3f(40.f)));
    for (size_t k = 0; k < scenes.size(); ++k) {
        scenes[k].finalize(quietLogger());
        {
            const auto acc = makeAccelerator(GetParam(), scenes[k]);
            SelfHitCount n = shootSelfHitRays(*acc, c, 17 + uint32_t(k));
            EXPECT_GT(n.primaryHits, 100) << "scene " << k << " " << acc->name();
            EXPECT_EQ(n.reHits, 0) << "scene " << k << " " << acc->name();
            EXPECT_EQ(n.shadowBlocked, 0) << "scene " << k << " " << acc->name();
        }
    }
}

TEST_P(EachAccelerator, EmptySceneBuildsAndMissesEverything) {
    Scene scene;
    scene.finalize(quietLogger());
    ASSERT_EQ(scene.primitiveCount(), 0u);
    {
        const auto acc = makeAccelerator(GetParam(), scene);
        for (Vec3f d : {Vec3f{0.f, 0.f, -1.f}, Vec3f{1.f, 1.f, 1.f}, Vec3f{0.f, -1.f, 0.f}}) {
            Ray r{{0.f, 0.f, 0.f}, d, 0.f, kInfinity};
            EXPECT_FALSE(acc->intersect(r)) << acc->name();
            EXPECT_FALSE(acc->occluded(r)) << acc->name();
        }
        EXPECT_EQ(acc->invalidRayCount(), 0u);
    }
}

TEST_P(EachAccelerator, PlaneOnlySceneNeedsNoEmbreeGeometry) {
    Scene scene;
    scene.planes.push_back(Plane{{0.f, -1.f, 0.f}, {0.f, 1.f, 0.f}, false, 0});
    scene.planes.push_back(Plane{{0.f, 0.f, -4.f}, {0.f, 0.f, 1.f}, true, 0});
    scene.finalize(quietLogger());
    {
        const auto acc = makeAccelerator(GetParam(), scene);
        auto down = acc->intersectPrim(Ray{{0.f, 1.f, 0.f}, {0.f, -1.f, 0.f}, 0.f, kInfinity});
        ASSERT_TRUE(down);
        EXPECT_EQ(down->ref, (PrimRef{ShapeKind::Plane, 0, 0}));
        EXPECT_FLOAT_EQ(down->t, 2.f);
        auto fwd = acc->intersectPrim(Ray{{0.f, 0.f, 0.f}, {0.f, -1.f, -1.f}, 0.f, kInfinity});
        ASSERT_TRUE(fwd);
        EXPECT_EQ(fwd->ref.object, 0u);  // the floor (t = 1) before the back wall (t = 4)
        EXPECT_FLOAT_EQ(fwd->t, 1.f);
        EXPECT_FALSE(acc->intersect(Ray{{0.f, -2.f, 0.f}, {0.f, -1.f, 0.f}, 0.f, kInfinity}));  // below, one-sided
        EXPECT_TRUE(acc->occluded(Ray{{0.f, 0.f, 0.f}, {0.f, 0.f, -1.f}, 0.f, 5.f}));
        EXPECT_FALSE(acc->occluded(Ray{{0.f, 0.f, 0.f}, {0.f, 0.f, -1.f}, 0.f, 4.f}));
    }
}

TEST(AcceleratorTest, LargeMeshHitsTheTriangleUnderTheRay) {
    // 80,000 triangles: the geomID/primID mapping must name the right one.
    Scene scene;
    TriangleMesh m;
    const int n = 200;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) m.positions.push_back({float(i), 0.01f * float((i * 7 + j * 13) % 5), float(j)});
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
        }
    }
    scene.meshes.push_back(std::move(m));
    scene.finalize(quietLogger());
    auto embree = makeEmbreeAccelerator(scene);
    auto hit = embree->intersectPrim(Ray{{10.25f, 5.f, 20.5f}, {0.f, -1.f, 0.f}, 0.f, kInfinity});
    ASSERT_TRUE(hit);
    EXPECT_EQ(hit->ref.kind, ShapeKind::Mesh);
    EXPECT_NEAR(hit->t, 5.f, 0.05f);
    // The hit point lies in the cell (10, 20): triangle 2 * (20 * n + 10) or the next one.
    EXPECT_EQ(hit->ref.prim / 2, 20u * n + 10u);
    EXPECT_GT(embree->memoryBytes(), 0u);
}

TEST_P(EachAccelerator, MeshWithoutTrianglesIsNotAnEmbreeError) {
    // Embree reports errors through the device callback, which the
    // accelerator turns into Error(ErrorCode::Embree) after the failing build
    // call. Well-formed input never triggers one: a mesh without triangles
    // (finalize() would drop it) must build, and the mesh after it must keep
    // its own index.
    Scene scene;
    TriangleMesh empty;
    empty.name = "no-triangles";
    empty.positions.push_back({0.f, 0.f, 0.f});
    scene.meshes.push_back(empty);
    scene.meshes.push_back(triangleCube({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}));
    {
        const auto acc = makeAccelerator(GetParam(), scene);
        auto h = acc->intersectPrim(Ray{{0.2f, 0.3f, 5.f}, {0.f, 0.f, -1.f}, 0.f, kInfinity});
        ASSERT_TRUE(h) << acc->name();
        EXPECT_EQ(h->ref.kind, ShapeKind::Mesh);
        EXPECT_EQ(h->ref.object, 1u) << acc->name();
        EXPECT_TRUE(h->ref.prim == 2u || h->ref.prim == 3u) << acc->name();  // the +z face
        EXPECT_FLOAT_EQ(h->t, 4.f);
    }
}

TEST_P(EachAccelerator, ShapesBeyondTheRepresentableRangeAreDroppedAlike) {
    // Embree drops a primitive reaching beyond +-1.844e18 without a word; the
    // scene drops it first, so the naive loop does not show what Embree cannot.
    Scene scene;
    scene.disks.push_back(Disk{{0.f, 5.f, 0.f}, {0.f, -1.f, 0.f}, 1e19f, 0});
    scene.spheres.push_back(Sphere{{0.f, 0.f, 0.f}, 1.f, 0});
    TriangleMesh far;
    for (Vec3f p : {Vec3f{-1.f, 8.f, -1.f}, Vec3f{2e18f, 8.f, -1.f}, Vec3f{-1.f, 8.f, 2e18f}}) far.positions.push_back(p);
    far.indices = {0, 1, 2};
    scene.meshes.push_back(far);
    scene.finalize(quietLogger());
    const auto acc = makeAccelerator(GetParam(), scene);
    EXPECT_FALSE(acc->intersect(Ray{{3.f, 0.f, 3.f}, {0.f, 1.f, 0.f}, 0.f, kInfinity})) << acc->name();
    EXPECT_FALSE(acc->occluded(Ray{{3.f, 0.f, 3.f}, {0.f, 1.f, 0.f}, 0.f, kInfinity})) << acc->name();
    auto h = acc->intersect(Ray{{0.f, 0.f, 5.f}, {0.f, 0.f, -1.f}, 0.f, kInfinity});
    ASSERT_TRUE(h) << acc->name();
    EXPECT_EQ(h->ref.kind, ShapeKind::Sphere);
}

PENUMBRA_FOR_BOTH_ACCELERATORS(EachAccelerator);

}  // namespace
}  // namespace penumbra
