// The automatic camera (frameBounds, core/io/scene_loader.h) for models seen
// edge-on from the front: a plane lying flat, a thin slab standing sideways
// are framed from a raised three-quarter view, whole, and a box that is not
// flat keeps the front view (obj_loader_test.cpp checks that one in detail).
#include <gtest/gtest.h>

#include <cmath>

#include "core/io/scene_loader.h"

namespace penumbra {
namespace {

/// Whether every corner of b projects inside the image of camera c.
bool seesEveryCorner(const CameraDesc& c, const Bounds3f& b, float aspect) {
    const Vec3f w = normalize(c.eye - c.lookAt), u = normalize(cross(c.up, w)), v = cross(w, u);
    const float tanV = std::tan(0.5f * c.vfovDegrees * kPi / 180.f), tanH = tanV * aspect;
    for (int i = 0; i < 8; ++i) {
        const Vec3f p{i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z};
        const Vec3f d = p - c.eye;
        const float depth = -dot(d, w);
        if (!(depth > 0.f) || std::fabs(dot(d, u)) / depth > tanH || std::fabs(dot(d, v)) / depth > tanV) return false;
    }
    return true;
}

TEST(AutoCamera, FlatModelsAreSeenFromARaisedThreeQuarterView) {
    Bounds3f lying;  // TwoSidedPlane: 2 x 2 in the y = 0 plane
    lying.extend({-1, 0, -1});
    lying.extend({1, 0, 1});
    Bounds3f sideways;  // a slab facing +x
    sideways.extend({-0.05f, -1, -2});
    sideways.extend({0.05f, 1, 2});
    for (const Bounds3f& b : {lying, sideways})
        for (float aspect : {0.5f, 1.f, 2.f}) {
            const CameraDesc c = frameBounds(b, 40.f, aspect);
            const Vec3f toEye = normalize(c.eye - c.lookAt);
            EXPECT_NEAR(toEye.y, 0.5f, 1e-5f) << "30 degrees up";
            EXPECT_NEAR(toEye.x, toEye.z, 1e-5f) << "45 degrees round from +z towards +x";
            EXPECT_GT(toEye.x, 0.f);
            EXPECT_EQ(c.lookAt, b.center());
            EXPECT_TRUE(seesEveryCorner(c, b, aspect)) << aspect;
            validateCamera(c);
        }
}

TEST(AutoCamera, BoxesThatAreNotFlatKeepTheFrontView) {
    Bounds3f room;  // a Cornell box: open towards +z
    room.extend({-1, 0, -1});
    room.extend({1, 2, 1});
    Bounds3f wall;  // flat, but facing +z: seen face on from the front
    wall.extend({-2, -1, 0});
    wall.extend({2, 1, 0});
    for (const Bounds3f& b : {room, wall}) {
        const CameraDesc c = frameBounds(b, 40.f, 1.f);
        EXPECT_EQ(c.eye.x, b.center().x);
        EXPECT_EQ(c.eye.y, b.center().y);
        EXPECT_GT(c.eye.z, b.hi.z);
        EXPECT_TRUE(seesEveryCorner(c, b, 1.f));
    }
}

}  // namespace
}  // namespace penumbra
