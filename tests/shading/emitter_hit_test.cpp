// LightSet::firstEmitterHit, which lets a BRDF sample under MIS skip its
// closest-hit query where it meets no light, against the naive accelerator:
// the closest hit among the lights alone, whatever else lies in front.
// (Here, not in tests/lights, because the reference is an accelerator.)
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

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
    for (Vec3f p : {Vec3f{-2, -2, -2}, Vec3f{2, -2, -2}, Vec3f{0, 2, -2}, Vec3f{0.5f, 0, 0.5f}}) m.positions.push_back(p);
    m.indices = {0, 1, 2, 0, 1, 3, 1, 2, 3};
    m.faceMaterials = {2, 0, 2};  // the middle triangle is no light
    s.meshes.push_back(m);
    s.boxes.push_back(makeBox(Vec3f{-0.3f, -0.3f, -0.3f}, Vec3f{0.3f, 0.3f, 0.3f}));
    const LightSet lights(s);
    ASSERT_TRUE(lights.emittersTestable());

    Scene only = s;  // the lights alone, at the same indices
    only.boxes.clear();
    only.rectangles[1].p0 = Vec3f{1e3f, 1e3f, 1e3f};  // out of every ray's way
    only.meshes[0].indices = {0, 1, 2, 0, 0, 0, 1, 2, 3};  // the plain triangle degenerate: no ray meets it
    const std::unique_ptr<Accelerator> naive = makeNaiveAccelerator(only);
    int hits = 0, blockedByNonLights = 0, meshHits[3] = {};
    const std::unique_ptr<Accelerator> all = makeNaiveAccelerator(s);
    const auto check = [&](const Ray& ray, uint32_t k) {
        const auto e = lights.firstEmitterHit(ray);
        const auto expected = naive->intersectPrim(ray);
        ASSERT_EQ(e.has_value(), expected.has_value()) << "ray " << k;
        if (!e) return;
        ++hits;
        if (e->ref.kind == ShapeKind::Mesh) ++meshHits[e->ref.prim];
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
    };
    for (uint32_t k = 0; k < 4096; ++k) {
        const Vec2f u = multiJitter2D(k, 4096, 11), w = multiJitter2D(k, 4096, 12);
        const Vec3f o = 4.f * Vec3f{2.f * u.x - 1.f, 2.f * u.y - 1.f, 2.f * w.x - 1.f};
        const Vec3f target{1.5f * (w.y - 0.5f), 2.f * (u.x - w.y), 0.7f * (w.x - 0.5f)};
        check(Ray{o, normalize(target - o), 0.f, kInfinity}, k);
    }
    // Rays that graze each light's edge from all sides: where its bounding
    // sphere is tight (a sphere; a rectangle's corners), a skip that is not
    // conservative would lose their hits.
    std::vector<Vec3f> edges;
    const Rectangle& q = s.rectangles[0];
    for (float a : {1e-3f, 1.f - 1e-3f})
        for (float b : {1e-3f, 1.f - 1e-3f}) edges.push_back(q.p0 + a * q.a + b * q.b);
    for (int i = 0; i < 16; ++i) {
        const float phi = 2.f * kPi * float(i) / 16.f;
        const Vec3f c = s.spheres[0].center, d = s.disks[0].center;
        edges.push_back(c + 0.999f * s.spheres[0].radius * Vec3f{std::cos(phi), std::sin(phi), 0.f});
        edges.push_back(c + 0.999f * s.spheres[0].radius * Vec3f{0.f, std::cos(phi), std::sin(phi)});
        edges.push_back(d + 0.999f * s.disks[0].radius * Vec3f{std::cos(phi), 0.f, std::sin(phi)});
    }
    for (uint32_t t : {0u, 2u}) {  // the emissive triangles' corners, a little inside
        Vec3f p0, p1, p2;
        m.vertices(t, p0, p1, p2);
        const Vec3f centroid = (p0 + p1 + p2) * (1.f / 3.f);
        for (const Vec3f& p : {p0, p1, p2}) edges.push_back(0.999f * p + 0.001f * centroid);
    }
    uint32_t k = 4096;
    for (const Vec3f& p : edges)
        for (int i = 0; i < 27; ++i) {
            const Vec3f side{float(i % 3) - 1.f, float(i / 3 % 3) - 1.f, float(i / 9) - 1.f};
            if (side == Vec3f{}) continue;  // 26 directions
            check(Ray{p + 6.f * normalize(side), normalize(-side), 0.f, kInfinity}, k++);
        }
    EXPECT_GT(hits, 2000);               // the rays meet the lights often,
    EXPECT_GT(blockedByNonLights, 1000);  // and often behind something that is no light,
    EXPECT_GT(meshHits[0], 20);           // both emissive triangles among them
    EXPECT_GT(meshHits[2], 20);
    EXPECT_EQ(meshHits[1], 0);
}
