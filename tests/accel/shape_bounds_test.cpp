// ShapeBounds::segmentsClear, by which the integrator takes a shading point's
// shadow rays to a light as unoccluded without tracing them: wherever it says
// clear, no ray from the origin to a point of the light (stopping short of
// it, as shadow rays do) may be occluded, and in a room-like scene it must say
// so for most points that see the whole light.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include "accel/accelerator.h"
#include "accel/shape_bounds.h"
#include "core/log.h"
#include "core/sampling.h"
#include "core/scene.h"

using namespace penumbra;

namespace {

Logger quietLogger() { return Logger([](LogLevel, std::string_view) {}, LogLevel::Error); }

float uniform(std::mt19937& g) { return float(g() >> 8) * 0x1p-24f; }

}  // namespace

TEST(ShapeBounds, ClearSegmentsMeetNothingWhateverPointOfTheLightTheyEndAt) {
    for (const Vec3f offset : {Vec3f{0.f, 0.f, 0.f}, Vec3f{2e3f, -5e2f, 1e3f}}) {
        // A room of four wall boxes, a light just under its ceiling, two balls, a small one by the light and a small box.
        Scene s;
        s.boxes.push_back(makeBox(offset + Vec3f{0, -0.05f, 0}, offset + Vec3f{5.5f, 0, 5.5f}));
        s.boxes.push_back(makeBox(offset + Vec3f{0, 5.5f, 0}, offset + Vec3f{5.5f, 5.55f, 5.5f}));
        s.boxes.push_back(makeBox(offset + Vec3f{-0.05f, 0, 0}, offset + Vec3f{0, 5.5f, 5.5f}));
        s.spheres.push_back(Sphere{offset + Vec3f{3.9f, 1.1f, 3.6f}, 1.1f, 0});
        s.spheres.push_back(Sphere{offset + Vec3f{1.6f, 1.0f, 2.0f}, 1.0f, 0});
        s.spheres.push_back(Sphere{offset + Vec3f{4.2f, 5.f, 2.2f}, 0.2f, 0});  // beside the light, far from the floor
        s.boxes.push_back(makeBox(offset + Vec3f{4.f, 3.f, 1.f}, offset + Vec3f{4.5f, 3.5f, 1.5f}));
        const Rectangle light{offset + Vec3f{2.1f, 5.49f, 2.225f}, Vec3f{1.3f, 0, 0}, Vec3f{0, 0, 1.05f}, 0};
        s.rectangles.push_back(light);
        s.finalize(quietLogger());
        const ShapeBounds bounds(s);
        ASSERT_TRUE(bounds.available());
        const std::unique_ptr<Accelerator> naive = makeNaiveAccelerator(s), embree = makeEmbreeAccelerator(s);
        Bounds3f box = penumbra::bounds(light);
        const float pad = 2e-6f * std::max(1.f, std::max(maxAbsComponent(box.lo), maxAbsComponent(box.hi)));
        box = Bounds3f{box.lo - Vec3f(pad), box.hi + Vec3f(pad)};
        const ShapeBounds::Targets targets{box, box.center(), 0.5f * length(box.diagonal()) * (1.f + 1e-5f)};
        const PrimRef self{ShapeKind::Rectangle, 0, 0, 0};
        std::mt19937 g(5);
        int clear = 0, points = 0, raysChecked = 0, grazing = 0;
        for (int k = 0; k < 3000; ++k) {
            // A point on the floor, a wall or one of the balls, and its ray origin (spawnRayTo's).
            Vec3f p, n;
            const int where = k % 4;
            if (where == 0) {
                p = offset + Vec3f{5.5f * uniform(g), 0.f, 5.5f * uniform(g)}, n = Vec3f{0, 1, 0};
            } else if (where == 1) {
                p = offset + Vec3f{0.f, 5.5f * uniform(g), 5.5f * uniform(g)}, n = Vec3f{1, 0, 0};
            } else if (where == 2) {
                p = offset + Vec3f{5.5f * uniform(g), 5.5f * uniform(g), 0.f}, n = Vec3f{0, 0, 1};
            } else {
                const Sphere& b = s.spheres[k % 8 < 4 ? 0 : 1];
                n = squareToUniformSphere({uniform(g), uniform(g)});
                p = b.center + b.radius * n;
            }
            if (!(dot(targets.center - p, n) - targets.radius > 1e-3f)) continue;  // the light not wholly in front
            ++points;
            const Vec3f o = p + n * rayOffsetScale(p);
            if (!bounds.segmentsClear(o, targets, self)) continue;
            ++clear;
            // Rays to points all over the light, its corners and edges included.
            for (int i = 0; i < 40; ++i) {
                float u = uniform(g), v = uniform(g);
                if (i < 4) u = float(i & 1), v = float(i >> 1);
                if (i >= 4 && i < 12) (i & 1 ? u : v) = float((i >> 1) & 1);
                const Ray r = spawnRayTo(p, n, light.p0 + u * light.a + v * light.b);
                ASSERT_FALSE(naive->occluded(r)) << "point " << k << " sample " << i << " offset " << offset.x;
                ASSERT_FALSE(embree->occluded(r)) << "point " << k << " sample " << i << " offset " << offset.x;
                ++raysChecked;
            }
            // Clear points next to a ball's shadow: a ray just past its edge checks the cone's width.
            for (const Sphere& b : s.spheres) {
                const Vec3f toBall = b.center - o;
                grazing += length(cross(normalize(targets.center - o), toBall)) < b.radius * 1.3f;
            }
        }
        EXPECT_GT(points, 1500);
        EXPECT_GT(clear, points / 2) << clear << " of " << points << " points found clear";
        EXPECT_GT(grazing, 30);
        EXPECT_GT(raysChecked, 20000);
    }
}

TEST(ShapeBounds, NotKeptForManyShapesNorWithoutClearance) {
    Scene s;
    for (int i = 0; i < 9; ++i) s.spheres.push_back(Sphere{Vec3f{float(3 * i), 0, 0}, 1.f, 0});
    s.finalize(quietLogger());
    const ShapeBounds many(s);
    EXPECT_FALSE(many.available());
    const ShapeBounds::Targets t{Bounds3f{Vec3f{-1, 5, -1}, Vec3f{1, 5, 1}}, Vec3f{0, 5, 0}, 1.5f};
    EXPECT_FALSE(many.segmentsClear(Vec3f{0, 2, 0}, t, std::nullopt));
    // One ball between the origin and the targets; then beside them.
    Scene one;
    one.spheres.push_back(Sphere{Vec3f{0, 2.5f, 0}, 0.5f, 0});
    one.finalize(quietLogger());
    const ShapeBounds b(one);
    ASSERT_TRUE(b.available());
    EXPECT_FALSE(b.segmentsClear(Vec3f{0, 0, 0}, t, std::nullopt));
    const ShapeBounds::Targets beside{Bounds3f{Vec3f{3, 5, -1}, Vec3f{5, 5, 1}}, Vec3f{4, 5, 0}, 1.5f};
    EXPECT_TRUE(b.segmentsClear(Vec3f{4, 0, 0}, beside, std::nullopt));
    // An infinite plane between them is never clear; one below both is.
    Scene plane = one;
    plane.planes.push_back(Plane{Vec3f{0, 1, 0}, Vec3f{0, 1, 0}, true, 0});
    EXPECT_FALSE(ShapeBounds(plane).segmentsClear(Vec3f{4, 0, 0}, beside, std::nullopt));
    Scene below = one;
    below.planes.push_back(Plane{Vec3f{0, -1, 0}, Vec3f{0, 1, 0}, true, 0});
    EXPECT_TRUE(ShapeBounds(below).segmentsClear(Vec3f{4, 0, 0}, beside, std::nullopt));
}
