// LightSet::firstEmitterHit, which lets a BRDF sample under MIS skip its
// closest-hit query where it meets no light, against the naive accelerator:
// the closest hit among the lights alone, whatever else lies in front.
// (Here, not in tests/lights, because the reference is an accelerator.)
#include <gtest/gtest.h>

#include <memory>

#include "accel/accelerator.h"
#include "core/multi_jitter.h"
#include "core/shapes.h"
#include "lights/light_set.h"

using namespace penumbra;

TEST(LightSet, FirstEmitterHitIsTheClosestHitAmongTheLightsAlone) {
    // Lights of every kind plus what is no light (a box, a plain rectangle, a
    // plain mesh triangle): firstEmitterHit must answer as the naive
    // accelerator does in the same scene with everything but the lights
    // removed, primitive, t, u and v alike, and name the light lightOf names.
    Scene s;
    Material plain, a, b;
    a.ke = Rgb(1.f);
    b.ke = Rgb(3.f);
    s.materials = {plain, a, b};
    s.rectangles.push_back(Rectangle{Vec3f{-1, 1, -1}, Vec3f{2, 0, 0}, Vec3f{0, 0, 2}, 1});
    s.rectangles.push_back(Rectangle{Vec3f{-3, 0.5f, -3}, Vec3f{6, 0, 0}, Vec3f{0, 0, 6}, 0});  // not a light
    s.spheres.push_back(Sphere{Vec3f{1.5f, 0, 0}, 0.5f, 2});
    s.disks.push_back(Disk{Vec3f{0, -1, 0}, Vec3f{0, 1, 0}, 1.f, 1});
    TriangleMesh m;
    for (Vec3f p : {Vec3f{-2, -2, -2}, Vec3f{2, -2, -2}, Vec3f{0, 2, -2}, Vec3f{0, 0, -1.5f}}) m.positions.push_back(p);
    m.indices = {0, 1, 2, 0, 1, 3, 1, 2, 3};
    m.faceMaterials = {2, 0, 2};  // the middle triangle is no light
    s.meshes.push_back(m);
    s.boxes.push_back(makeBox(Vec3f{-0.3f, -0.3f, -0.3f}, Vec3f{0.3f, 0.3f, 0.3f}));
    const LightSet lights(s);
    ASSERT_TRUE(lights.emittersTestable());

    Scene only = s;  // the lights alone, at the same indices
    only.boxes.clear();
    only.rectangles[1].p0 = Vec3f{1e3f, 1e3f, 1e3f};  // out of every ray's way
    only.meshes[0].indices = {0, 1, 2, 1, 2, 3};
    only.meshes[0].faceMaterials = {2, 2};
    const std::unique_ptr<Accelerator> naive = makeNaiveAccelerator(only);
    int hits = 0, blockedByNonLights = 0;
    const std::unique_ptr<Accelerator> all = makeNaiveAccelerator(s);
    for (uint32_t k = 0; k < 4096; ++k) {
        const Vec2f u = multiJitter2D(k, 4096, 11), w = multiJitter2D(k, 4096, 12);
        const Vec3f o = 4.f * Vec3f{2.f * u.x - 1.f, 2.f * u.y - 1.f, 2.f * w.x - 1.f};
        const Vec3f target{1.5f * (w.y - 0.5f), 2.f * (u.x - w.y), 0.7f * (w.x - 0.5f)};
        const Ray ray{o, normalize(target - o), 0.f, kInfinity};
        const auto e = lights.firstEmitterHit(ray);
        const auto expected = naive->intersectPrim(ray);
        ASSERT_EQ(e.has_value(), expected.has_value()) << "ray " << k;
        if (!e) continue;
        ++hits;
        EXPECT_EQ(e->ref, expected->ref) << "ray " << k;
        EXPECT_EQ(e->hit.t, expected->t) << "ray " << k;
        EXPECT_EQ(e->hit.u, expected->u) << "ray " << k;
        EXPECT_EQ(e->hit.v, expected->v) << "ray " << k;
        Hit h;
        h.ref = e->ref;
        h.material = e->ref.kind == ShapeKind::Mesh ? s.meshes[0].materialOf(e->ref.prim)
                     : e->ref.kind == ShapeKind::Sphere ? 2u
                                                        : 1u;
        EXPECT_EQ(lights.lightOf(h), std::optional<size_t>(e->light)) << "ray " << k;
        const auto first = all->intersectPrim(ray);
        blockedByNonLights += !(first && first->ref == e->ref);
    }
    EXPECT_GT(hits, 2000);               // the rays meet the lights often,
    EXPECT_GT(blockedByNonLights, 1000);  // and often behind something that is no light
}
