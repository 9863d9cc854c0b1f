// Whitted rays through glass at any --max-depth: beyond the default depth a
// dielectric no longer splits a lane's ray in two and branches of low
// throughput take Russian roulette, so no setting makes a small image run
// without end, and the estimate stays the same in expectation.
#include <gtest/gtest.h>

#include <cmath>

#include "core/log.h"
#include "shading/bsdf/dielectric.h"
#include "shading/renderer.h"
#include "shading/whitted_integrator.h"

using namespace penumbra;

namespace {

Logger quietLogger() { return Logger([](LogLevel, std::string_view) {}, LogLevel::Error); }

Material glass(float ior) {
    Material m;
    m.kd = Rgb(0.f);
    m.kt = Rgb(1.f);
    m.ior = ior;
    return m;
}

struct Rendered {
    double mean;
    RenderStats stats;
};

Rendered renderWhitted(const PreparedScene& ps, const CameraDesc& camera, int size, int spp, int maxDepth) {
    RenderSettings st;
    st.width = st.height = size;
    st.spp = spp;
    st.lightSamples = 1;
    st.maxDepth = maxDepth;
    st.threads = 2;
    Film film = makeFilm(st);
    const RenderStats stats = render(ps, camera, st, film).stats;
    double sum = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) sum += film.radiance(film.index(x, y)).g;
    return {sum / (size * size), stats};
}

}  // namespace

// A closed glass shell (a glass sphere with an air cavity) around the camera,
// 4x4 pixels, 1 sample each. Every glass hit splits a ray in two and most
// branches stay inside, so traced in full the work grows geometrically with
// the depth; the rays traced must stay bounded at any --max-depth
// (docs/rendering.md, "Beyond the default depth").
TEST(DeepGlass, AClosedGlassShellAroundTheCameraEndsAtAnyMaxDepth) {
    Scene s;
    s.materials = {glass(1.5f), glass(1.f / 1.5f)};
    s.spheres.push_back(Sphere{Vec3f{0, 0, 0}, 2.f, 0});
    s.spheres.push_back(Sphere{Vec3f{0, 0, 0}, 1.8f, 1});  // the cavity: air inside glass
    s.background = Rgb(1.f);
    const PreparedScene ps(std::move(s), {}, quietLogger());
    CameraDesc cam;
    cam.eye = Vec3f{0.3f, 0.2f, 0.1f};
    cam.lookAt = Vec3f{0, 0, -1};
    // Up to the exact depth a camera sample traces at most a full binary tree
    // of rays (2^11 - 2 beyond the camera ray); beyond it each branch goes on
    // as one ray that soon leaves the shell or loses the roulette.
    constexpr uint64_t kBound = 16 * (uint64_t(1) << 11);
    for (int maxDepth : {24, 1000000}) {
        const Rendered r = renderWhitted(ps, cam, 4, 1, maxDepth);
        const uint64_t bounced = r.stats.reflectionRays + r.stats.transmissionRays;
        EXPECT_LT(bounced, kBound) << "max depth " << maxDepth;
        // No light is lost in clear glass: everything the camera sees is the background.
        EXPECT_NEAR(r.mean, 1.0, 0.01) << "max depth " << maxDepth;
    }
}

// A glass ball (ior 10: 67% reflected at normal incidence) with the camera at
// its centre, inside a sphere emitting 1: every camera ray crosses the ball
// along a diameter, and the k-th time it meets the surface it leaves with
// weight F^k (1 - F) 100 (the radiance gained entering air from n = 10), so
// with D bounces the pixel is 100 (1 - F^D). At the default depth that is
// exact (every branch traced); at depth 60 the branches beyond the default
// depth are sampled and roulette'd, and the mean must still be 100 (1 - F^60).
TEST(DeepGlass, SampledBranchesBeyondTheExactDepthKeepTheExpectedValue) {
    Scene s;
    Material lamp;
    lamp.kd = Rgb(0.f);
    lamp.ke = Rgb(1.f);
    lamp.twoSidedEmission = true;
    s.materials = {glass(10.f), lamp};
    s.spheres.push_back(Sphere{Vec3f{0, 0, 0}, 1.f, 0});
    s.spheres.push_back(Sphere{Vec3f{0, 0, 0}, 5.f, 1});
    const PreparedScene ps(std::move(s), {}, quietLogger());
    CameraDesc cam;
    cam.eye = Vec3f{0, 0, 0};
    cam.lookAt = Vec3f{0, 0, -1};
    const double F = fresnelDielectric(1.f, 0.1f);
    ASSERT_NEAR(F, 0.669, 1e-3);
    const int exact = WhittedIntegrator::kExactDepth;
    const Rendered atExact = renderWhitted(ps, cam, 8, 1, exact);
    EXPECT_NEAR(atExact.mean, 100.0 * (1.0 - std::pow(F, exact)), 1e-3);
    // Beyond it, one branch per lane: at most one ray more per bounce and sample.
    const Rendered deep = renderWhitted(ps, cam, 64, 4, 60);
    const uint64_t samples = 64 * 64 * 4;
    EXPECT_LE(deep.stats.reflectionRays + deep.stats.transmissionRays,
              samples * (2 * uint64_t(exact) + uint64_t(60 - exact)));
    // Per sample, what lies beyond the exact depth is 0 or 100 / 16 (the
    // roulette's threshold carried out of the ball), with mean 100 F^10: a
    // standard deviation of 2.8, 0.022 for the mean of 16384 samples.
    const double expected = 100.0 * (1.0 - std::pow(F, 60));
    EXPECT_NEAR(deep.mean, expected, 0.11);
    EXPECT_GT(deep.mean - atExact.mean, 1.5);  // the deep bounces are there (100 F^10 = 1.8)
}
