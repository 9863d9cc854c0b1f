// The integrator against values known in closed form.
#include <gtest/gtest.h>

#include <cmath>

#include "core/log.h"
#include "core/multi_jitter.h"
#include "shading/whitted_integrator.h"
#include "shading/renderer.h"
#include "support/both_accelerators.h"

using namespace penumbra;

namespace {

Logger quietLogger() { return Logger([](LogLevel, std::string_view) {}, LogLevel::Error); }

uint32_t addMaterial(Scene& s, Material m) {
    s.materials.push_back(m);
    return uint32_t(s.materials.size() - 1);
}

Material diffuse(float kd) {
    Material m;
    m.kd = Rgb(kd);
    return m;
}

Material emitter(float le, bool twoSided = false) {
    Material m;
    m.kd = Rgb(0.f);
    m.ke = Rgb(le);
    m.twoSidedEmission = twoSided;
    return m;
}

// Radiance along one ray, estimated with `lightSamples` multi-jittered light samples.
Rgb radianceAlong(const PreparedScene& ps, const Ray& ray, int lightSamples, int maxDepth = 10) {
    RenderSettings st;
    st.lightSamples = lightSamples;
    st.maxDepth = maxDepth;
    WhittedIntegrator integ({ps.scene(), ps.accelerator(), ps.lights(), ps.textures(), st});
    RayCounts counts;
    return integ.Li(ray, SampleKey{pixelSampleKey(1, 0), 0}, counts, nullptr);
}

// Irradiance at x (normal n) from a uniform polygon of radiance 1 (Lambert's
// formula): E = 1/2 sum_i beta_i (n . (R_i x R_i+1) / |R_i x R_i+1|).
double lambertPolygonIrradiance(const Vec3f& x, const Vec3f& n, const std::vector<Vec3f>& poly) {
    double e = 0;
    for (size_t i = 0; i < poly.size(); ++i) {
        Vec3f a = normalize(poly[i] - x), b = normalize(poly[(i + 1) % poly.size()] - x);
        double beta = std::acos(std::clamp(double(dot(a, b)), -1.0, 1.0));
        Vec3f c = normalize(cross(a, b));
        e += beta * dot(n, c);
    }
    return std::fabs(0.5 * e);
}

// The closed forms hold whichever accelerator finds the hits.
class Radiometry : public test::ForBothAccelerators {
protected:
    PrepareOptions prep() const {
        PrepareOptions o;
        o.accelerator = GetParam();
        return o;
    }
};

}  // namespace

TEST_P(Radiometry, LambertianPlaneUnderRectangleMatchesLambertsFormula) {
    Scene s;
    uint32_t floor = addMaterial(s, diffuse(0.5f));
    uint32_t light = addMaterial(s, emitter(3.f));
    s.planes.push_back(Plane{Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, true, floor});
    // 1 x 1 light at height 1, facing down: cross(a, b) = cross(z, x) = +y... use a = x, b = z -> cross = -y.
    Rectangle r{Vec3f{-0.5f, 1.f, -0.5f}, Vec3f{1, 0, 0}, Vec3f{0, 0, 1}, light};
    ASSERT_LT(rectangleNormal(r).y, 0.f);
    s.rectangles.push_back(r);
    PreparedScene ps(std::move(s), prep(), quietLogger());
    std::vector<Vec3f> poly{{-0.5f, 1, -0.5f}, {0.5f, 1, -0.5f}, {0.5f, 1, 0.5f}, {-0.5f, 1, 0.5f}};
    for (Vec3f x : {Vec3f{0, 0, 0}, Vec3f{0.4f, 0, 0.2f}, Vec3f{1.5f, 0, -0.7f}, Vec3f{3.f, 0, 0}}) {
        Ray ray{x + Vec3f{0.05f, 0.5f, 0}, normalize(Vec3f{-0.05f, -0.5f, 0}), 0.f, kInfinity};
        double E = lambertPolygonIrradiance(x, Vec3f{0, 1, 0}, poly) * 3.0;
        double expected = 0.5 / M_PI * E;
        Rgb L = radianceAlong(ps, ray, 4096);
        std::cout << "[ measured ] x=(" << x.x << "," << x.z << ") L=" << L.r << " expected " << expected << "\n";
        EXPECT_NEAR(L.r, expected, 0.003 * expected + 1e-6) << "at x = " << x.x << "," << x.z;
    }
}

TEST_P(Radiometry, ConvexDiffuseObjectInsideClosedEmitterReflectsKdTimesLe) {
    // Furnace: a diffuse sphere inside a two-sided emissive sphere of radiance Le.
    Scene s;
    uint32_t inner = addMaterial(s, diffuse(0.6f));
    uint32_t shell = addMaterial(s, emitter(2.f, true));
    s.spheres.push_back(Sphere{Vec3f{0, 0, 0}, 1.f, inner});
    s.spheres.push_back(Sphere{Vec3f{0, 0, 0}, 10.f, shell});
    PreparedScene ps(std::move(s), prep(), quietLogger());
    for (Vec3f dir : {Vec3f{0, -1, 0}, normalize(Vec3f{1, -1, 0.5f}), normalize(Vec3f{-0.2f, 0.3f, -1.f})}) {
        Ray ray{-4.f * dir, dir, 0.f, kInfinity};
        Rgb L = radianceAlong(ps, ray, 4096);
        EXPECT_NEAR(L.g, 0.6f * 2.f, 0.01f * 1.2f) << "direction " << dir.x << "," << dir.y << "," << dir.z;
    }
}

TEST_P(Radiometry, MirrorShowsKrTimesLeAndMaxDepthCutsReflectionsOff) {
    Scene s;
    Material mirror;
    mirror.kd = Rgb(0.f);
    mirror.kr = Rgb(0.8f, 0.5f, 0.25f);
    uint32_t mm = addMaterial(s, mirror);
    uint32_t light = addMaterial(s, emitter(5.f));
    // Mirror plane y = 0 facing up; emitter disk at height 2 facing down.
    s.planes.push_back(Plane{Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, true, mm});
    s.disks.push_back(Disk{Vec3f{0, 2, 0}, Vec3f{0, -1, 0}, 0.5f, light});
    PreparedScene ps(std::move(s), prep(), quietLogger());
    // A steep ray: it reflects at (0,0,0) and reaches the disk at (-0.2, 2, 0).
    Ray ray{Vec3f{0.1f, 1.f, 0}, normalize(Vec3f{-0.1f, -1.f, 0}), 0.f, kInfinity};
    Rgb L = radianceAlong(ps, ray, 16, 10);
    EXPECT_NEAR(L.r, 0.8f * 5.f, 1e-4f);
    EXPECT_NEAR(L.g, 0.5f * 5.f, 1e-4f);
    EXPECT_NEAR(L.b, 0.25f * 5.f, 1e-4f);
    Rgb cut = radianceAlong(ps, ray, 16, 0);
    EXPECT_EQ(cut.r, 0.f) << "max depth 0: no reflection rays, the mirror (kd 0) is black";
}

TEST_P(Radiometry, MaxDepthCountsBouncesExactly) {
    // A mirror wall at x = -1 facing +x and a two-sided emitter disk at x = 0:
    // a ray from between them towards the mirror sees the emitter after one bounce.
    Scene s;
    Material mirror;
    mirror.kd = Rgb(0.f);
    mirror.kr = Rgb(0.5f);
    uint32_t mm = addMaterial(s, mirror);
    uint32_t light = addMaterial(s, emitter(1.f, true));
    s.rectangles.push_back(Rectangle{Vec3f{-1, -10, -10}, Vec3f{0, 20, 0}, Vec3f{0, 0, 20}, mm});
    s.disks.push_back(Disk{Vec3f{0, 0, 0.5f}, Vec3f{1, 0, 0}, 0.2f, light});
    PreparedScene ps(std::move(s), prep(), quietLogger());
    Ray ray{Vec3f{-0.5f, 0, 0.5f}, Vec3f{-1, 0, 0}, 0.f, kInfinity};
    EXPECT_NEAR(radianceAlong(ps, ray, 4, 1).r, 0.5f, 1e-5f);
    EXPECT_EQ(radianceAlong(ps, ray, 4, 0).r, 0.f);
}

TEST_P(Radiometry, ClassicPointLightReproducesTheLectureFormula) {
    Scene s;
    Material m;
    m.kd = Rgb(0.5f);
    m.ks = Rgb(0.3f);
    m.exponent = 10.f;
    m.ka = Rgb(0.2f);
    m.model = PhongModel::Classic;
    uint32_t id = addMaterial(s, m);
    s.planes.push_back(Plane{Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, true, id});
    s.pointLights.push_back(PointLight{Vec3f{0, 2, 0}, Rgb(4.f)});
    s.ambient = Rgb(0.5f);
    PreparedScene ps(std::move(s), prep(), quietLogger());
    // Hit point x = (1, 0, 0) seen from eye (3, 1, 0).
    Vec3f x{1, 0, 0}, eye{3, 1, 0};
    Ray ray{eye, normalize(x - eye), 0.f, kInfinity};
    Rgb L = radianceAlong(ps, ray, 1);
    // By hand: s = (-1,2,0)/sqrt5, n.s = 2/sqrt5, Lj = 4/5. r = 2(n.s)n - s = (1,2,0)/sqrt5.
    // v = (2,1,0)/sqrt5, v.r = 4/5. L = ka La + kd Lj (n.s) + ks Lj (v.r)^10.
    const double ns = 2 / std::sqrt(5.0), Lj = 0.8, vr = 0.8;
    const double expected = 0.2 * 0.5 + 0.5 * Lj * ns + 0.3 * Lj * std::pow(vr, 10);
    EXPECT_NEAR(L.r, expected, 1e-5);
    EXPECT_NEAR(L.r, 0.1 + 0.357771 + 0.025770, 1e-5);
}

TEST_P(Radiometry, EmitterIsOneSidedUnlessMarkedTwoSided) {
    for (bool twoSided : {false, true}) {
        Scene s;
        uint32_t light = addMaterial(s, emitter(2.f, twoSided));
        s.rectangles.push_back(Rectangle{Vec3f{-1, 0, -1}, Vec3f{2, 0, 0}, Vec3f{0, 0, 2}, light});  // faces -y
        PreparedScene ps(std::move(s), prep(), quietLogger());
        Rgb below = radianceAlong(ps, Ray{Vec3f{0, -1, 0}, Vec3f{0, 1, 0}, 0.f, kInfinity}, 1);
        Rgb above = radianceAlong(ps, Ray{Vec3f{0, 1, 0}, Vec3f{0, -1, 0}, 0.f, kInfinity}, 1);
        EXPECT_EQ(below.r, 2.f);
        EXPECT_EQ(above.r, twoSided ? 2.f : 0.f);
    }
}

TEST_P(Radiometry, BackgroundForRaysThatLeaveTheScene) {
    Scene s;
    s.background = Rgb(0.15f);
    PreparedScene ps(std::move(s), prep(), quietLogger());
    Rgb L = radianceAlong(ps, Ray{Vec3f{0, 0, 0}, Vec3f{0, 0, -1}, 0.f, kInfinity}, 1);
    EXPECT_EQ(L.r, 0.15f);
}

PENUMBRA_FOR_BOTH_ACCELERATORS(Radiometry);
