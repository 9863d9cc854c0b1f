// Shadow acne: surfaces far from the origin, lit by lights whose shadow rays
// start on them, must render without speckles.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "core/log.h"
#include "shading/renderer.h"
#include "support/both_accelerators.h"

using namespace penumbra;

namespace {

Logger quietLogger() { return Logger([](LogLevel, std::string_view) {}, LogLevel::Error); }

struct PixelStats {
    float min, max;
    double mean;
};

PixelStats stats(const Film& f) {
    std::vector<float> px = f.radianceBuffer(3);
    PixelStats s{px[0], px[0], 0.0};
    for (size_t i = 0; i < px.size(); i += 3) {
        s.min = std::min(s.min, px[i]);
        s.max = std::max(s.max, px[i]);
        s.mean += px[i];
    }
    s.mean /= double(px.size() / 3);
    return s;
}

// A diffuse plane (tilted, so hit points have full-precision coordinates in
// every axis) around `centre`, lit by a directional light; the camera looks
// straight at it so every pixel sees the plane. With no occluder the radiance
// is the same everywhere: kd/pi * E * cos.
Film renderPlane(const Vec3f& centre, ShapeKind kind, AcceleratorKind accelerator) {
    Scene s;
    Material m;
    m.kd = Rgb(0.8f);
    s.materials.push_back(m);
    const Vec3f n = normalize(Vec3f{0.3f, 1.f, 0.2f});
    if (kind == ShapeKind::Plane) {
        s.planes.push_back(Plane{centre, n, true, 0});
    } else {
        // The same plane as two big triangles.
        Frame f = Frame::fromNormal(n);
        TriangleMesh mesh;
        const float r = 400.f;
        for (Vec3f p : {centre - r * f.s - r * f.t, centre + r * f.s - r * f.t, centre + r * f.s + r * f.t,
                        centre - r * f.s + r * f.t})
            mesh.positions.push_back(p);
        mesh.indices = {0, 1, 2, 0, 2, 3};
        if (dot(cross(mesh.positions[1] - mesh.positions[0], mesh.positions[2] - mesh.positions[0]), n) < 0)
            mesh.indices = {0, 2, 1, 0, 3, 2};
        s.meshes.push_back(mesh);
    }
    s.directionalLights.push_back(DirectionalLight{-normalize(Vec3f{0.5f, 1.f, -0.3f}), Rgb(2.f)});
    PrepareOptions prep;
    prep.accelerator = accelerator;
    PreparedScene ps(std::move(s), prep, quietLogger());
    CameraDesc cam;
    cam.eye = centre + 60.f * normalize(Vec3f{0.1f, 1.f, 0.5f});
    cam.lookAt = centre;
    cam.vfovDegrees = 40.f;
    RenderSettings st;
    st.width = 64;
    st.height = 64;
    st.spp = 1;
    Film film = makeFilm(st);
    render(ps, cam, st, film);
    return film;
}

}  // namespace

// No acne whichever accelerator finds the hits.
class ShadowAcne : public test::ForBothAccelerators {};

TEST_P(ShadowAcne, LitPlaneFarFromTheOriginHasNoSpeckles) {
    const Vec3f n = normalize(Vec3f{0.3f, 1.f, 0.2f});
    const float expected = 0.8f / kPi * 2.f * dot(n, normalize(Vec3f{0.5f, 1.f, -0.3f}));
    for (ShapeKind kind : {ShapeKind::Plane, ShapeKind::Mesh}) {
        for (Vec3f centre : {Vec3f{0, 0, 0}, Vec3f{1e4f, 1e4f, -1e4f}, Vec3f{-2.3e4f, 1.7e4f, 3.1e4f}}) {
            PixelStats st = stats(renderPlane(centre, kind, GetParam()));
            SCOPED_TRACE(std::string(kind == ShapeKind::Plane ? "plane" : "mesh") + " at " + std::to_string(centre.x));
            // Every pixel lit: one speckle (a self-shadowed pixel) would pull the minimum to 0.
            EXPECT_NEAR(st.min, expected, 1e-3f * expected);
            EXPECT_NEAR(st.max, expected, 1e-3f * expected);
            EXPECT_NEAR(st.mean, expected, 1e-3 * expected);
        }
    }
}

PENUMBRA_FOR_BOTH_ACCELERATORS(ShadowAcne);
