// Camera rays: the lanes (generateRayLanes, whose pinhole loop vectorises)
// hold exactly generateRay's rays, and those rays go where the camera looks.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "core/camera.h"
#include "core/hash.h"

using namespace penumbra;

namespace {

bool sameRay(const Ray& a, const Ray& b) {
    return std::memcmp(&a.o, &b.o, sizeof a.o) == 0 && std::memcmp(&a.d, &b.d, sizeof a.d) == 0 &&
           a.tnear == b.tnear && a.tfar == b.tfar;
}

CameraDesc lookingAtOrigin(float aperture) {
    CameraDesc d;
    d.eye = {1.f, 2.f, 9.f};
    d.lookAt = {0.f, 0.f, 0.f};
    d.up = {0.f, 1.f, 0.f};
    d.vfovDegrees = 40.f;
    d.aperture = aperture;
    return d;
}

}  // namespace

TEST(Camera, RayLanesAreGenerateRayBitForBit) {
    for (const float aperture : {0.f, 0.25f}) {
        const Camera camera(lookingAtOrigin(aperture), 64, 48);
        // Full and partial sets of lanes, edges of the film included.
        for (const int n : {16, 11, 1}) {
            float filmX[RayLanes::kWidth], filmY[RayLanes::kWidth];
            Vec2f lens[RayLanes::kWidth];
            for (int l = 0; l < n; ++l) {
                const uint32_t i = uint32_t(l + 16 * n);
                filmX[l] = 64.f * toUnitFloat(mix64(i));
                filmY[l] = 48.f * toUnitFloat(mix64(i + 1000));
                lens[l] = Vec2f{toUnitFloat(mix64(i + 2000)), toUnitFloat(mix64(i + 3000))};
            }
            filmX[0] = filmY[0] = 0.f;
            if (n > 1) filmX[1] = 64.f, filmY[1] = 48.f;
            RayLanes lanes;
            camera.generateRayLanes(filmX, filmY, aperture > 0.f ? lens : nullptr, n, lanes);
            for (int l = 0; l < RayLanes::kWidth; ++l) {
                EXPECT_EQ(lanes.active[l], l < n ? 1 : 0) << "lane " << l;
                if (l >= n) continue;
                const Ray one = camera.generateRay(filmX[l], filmY[l], lens[l]);
                EXPECT_TRUE(sameRay(lanes.ray(l), one)) << "aperture " << aperture << ", lane " << l << " of " << n;
                EXPECT_NEAR(length(lanes.ray(l).d), 1.f, 1e-6f);
            }
        }
    }
}

TEST(Camera, CentreRayLooksAtTheTarget) {
    const Camera camera(lookingAtOrigin(0.f), 64, 48);
    const float x = 32.f, y = 24.f;
    RayLanes lanes;
    camera.generateRayLanes(&x, &y, nullptr, 1, lanes);
    const Ray r = lanes.ray(0);
    const Vec3f toTarget = normalize(Vec3f{-1.f, -2.f, -9.f});
    EXPECT_NEAR(r.d.x, toTarget.x, 1e-6f);
    EXPECT_NEAR(r.d.y, toTarget.y, 1e-6f);
    EXPECT_NEAR(r.d.z, toTarget.z, 1e-6f);
    EXPECT_EQ(r.o, (Vec3f{1.f, 2.f, 9.f}));
}
