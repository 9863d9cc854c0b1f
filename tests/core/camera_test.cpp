// Camera rays: the batch (generateRays, whose pinhole loops vectorise) gives
// exactly generateRay's rays, and those rays go where the camera looks.
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

TEST(Camera, BatchOfRaysIsGenerateRayBitForBit) {
    for (const float aperture : {0.f, 0.25f}) {
        const Camera camera(lookingAtOrigin(aperture), 64, 48);
        // 37 positions: two full chunks of 16 and a partial one, edges included.
        std::vector<Vec2f> film, lens;
        for (uint32_t i = 0; i < 37; ++i) {
            film.push_back(Vec2f{64.f * toUnitFloat(mix64(i)), 48.f * toUnitFloat(mix64(i + 1000))});
            lens.push_back(Vec2f{toUnitFloat(mix64(i + 2000)), toUnitFloat(mix64(i + 3000))});
        }
        film[0] = {0.f, 0.f};
        film[1] = {64.f, 48.f};
        std::vector<Ray> batch(film.size());
        camera.generateRays(film, lens, batch);
        for (size_t i = 0; i < film.size(); ++i) {
            const Ray one = camera.generateRay(film[i].x, film[i].y, lens[i]);
            EXPECT_TRUE(sameRay(batch[i], one)) << "aperture " << aperture << ", ray " << i;
            EXPECT_NEAR(length(batch[i].d), 1.f, 1e-6f);
        }
    }
}

TEST(Camera, CentreRayLooksAtTheTarget) {
    const Camera camera(lookingAtOrigin(0.f), 64, 48);
    const Vec2f centre{32.f, 24.f};
    Ray r;
    camera.generateRays(std::span<const Vec2f>(&centre, 1), std::span<const Vec2f>(), std::span<Ray>(&r, 1));
    const Vec3f toTarget = normalize(Vec3f{-1.f, -2.f, -9.f});
    EXPECT_NEAR(r.d.x, toTarget.x, 1e-6f);
    EXPECT_NEAR(r.d.y, toTarget.y, 1e-6f);
    EXPECT_NEAR(r.d.z, toTarget.z, 1e-6f);
    EXPECT_EQ(r.o, (Vec3f{1.f, 2.f, 9.f}));
}
