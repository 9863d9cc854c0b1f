// The preview's camera moves and the camera written as options.
#include "orbit_camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace penumbra::preview {
namespace {

double distance(const pnb::Vec3& a, const pnb::Vec3& b) {
    return std::sqrt(double(a.x - b.x) * (a.x - b.x) + double(a.y - b.y) * (a.y - b.y) + double(a.z - b.z) * (a.z - b.z));
}

pnb::Camera frontCamera() {
    pnb::Camera c;
    c.eye = {0.f, 1.f, 5.f};
    c.lookAt = {0.f, 1.f, 0.f};
    c.up = {0.f, 1.f, 0.f};
    c.vfovDegrees = 90.f;
    return c;
}

void expectNear(const pnb::Vec3& a, const pnb::Vec3& b, double tolerance = 1e-5) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(OrbitCamera, YawTurnsTheEyeAboutUpThroughTheLookAtPoint) {
    const pnb::Camera c = orbit(frontCamera(), 90.0, 0.0);
    // Counter-clockwise seen from above: from +z to +x.
    expectNear(c.eye, {5.f, 1.f, 0.f});
    expectNear(c.lookAt, frontCamera().lookAt, 0.0);
    expectNear(c.up, frontCamera().up, 0.0);
    expectNear(orbit(frontCamera(), 360.0, 0.0).eye, frontCamera().eye);
}

TEST(OrbitCamera, PitchRaisesTheEyeAndKeepsItsDistance) {
    const pnb::Camera c = orbit(frontCamera(), 0.0, 30.0);
    EXPECT_NEAR(c.eye.y - 1.f, 5.0 * std::sin(30.0 * M_PI / 180.0), 1e-5);
    EXPECT_NEAR(distance(c.eye, c.lookAt), 5.0, 1e-5);
    expectNear(orbit(c, 0.0, -30.0).eye, frontCamera().eye);
}

TEST(OrbitCamera, PitchStopsOneDegreeShortOfThePoles) {
    for (double pitch : {200.0, -200.0}) {
        const pnb::Camera c = orbit(frontCamera(), 0.0, pitch);
        const double along = (c.eye.y - c.lookAt.y) / distance(c.eye, c.lookAt);
        EXPECT_NEAR(std::acos(along) * 180.0 / M_PI, pitch > 0 ? 1.0 : 179.0, 1e-3) << pitch;
        EXPECT_NO_THROW(pnb::validate(c));
    }
}

TEST(OrbitCamera, ZoomScalesTheDistanceAndAnExplicitFocusDistance) {
    pnb::Camera lens = frontCamera();
    lens.aperture = 0.1f;
    lens.focusDistance = 4.f;
    const pnb::Camera c = zoom(lens, 0.5);
    expectNear(c.eye, {0.f, 1.f, 2.5f});
    EXPECT_FLOAT_EQ(c.focusDistance, 2.f);
    EXPECT_FLOAT_EQ(zoom(frontCamera(), 3.0).focusDistance, 0.f);  // 0: the look-at distance, whatever it is
}

TEST(OrbitCamera, PanSlidesEyeAndLookAtByViewHeights) {
    // 90 degrees at distance 5: the view is 10 high at the look-at point.
    const pnb::Camera c = pan(frontCamera(), 0.5, -0.25);
    expectNear(c.eye, {5.f, -1.5f, 5.f});
    expectNear(c.lookAt, {5.f, -1.5f, 0.f});
    expectNear(c.up, frontCamera().up, 0.0);
}

// What CLI11 and the command's parser make of the text: std::stod, then float.
float readBack(const std::string& text) { return float(std::stod(text)); }

TEST(OrbitCamera, OptionsReadBackAsTheSameFloats) {
    pnb::Camera c = orbit(zoom(frontCamera(), 0.37), 33.3, -12.7);
    c.vfovDegrees = 37.123457f;
    EXPECT_EQ(cameraOptions(c).find("--aperture"), std::string::npos);
    c.aperture = 0.0125f;
    c.focusDistance = 3.3333333f;
    const std::string options = cameraOptions(c);
    std::istringstream in(options);
    std::vector<float> values;
    for (std::string word; in >> word;) {
        std::stringstream numbers(word.substr(word.find('=') + 1));
        for (std::string n; std::getline(numbers, n, ',');) values.push_back(readBack(n));
    }
    const std::vector<float> expected = {c.eye.x, c.eye.y, c.eye.z, c.lookAt.x, c.lookAt.y, c.lookAt.z,
                                         c.up.x,  c.up.y,  c.up.z,  c.vfovDegrees, c.aperture, c.focusDistance};
    ASSERT_EQ(values.size(), expected.size()) << options;
    for (size_t i = 0; i < values.size(); ++i) EXPECT_EQ(std::memcmp(&values[i], &expected[i], sizeof(float)), 0) << options;
    EXPECT_EQ(options.rfind("--eye=", 0), 0u) << options;
}

}  // namespace
}  // namespace penumbra::preview
