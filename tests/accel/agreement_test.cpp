// Embree against the naive reference: a random scene mixing every shape kind
// and two meshes, shot with coherent (camera) and incoherent (random) rays,
// plus shadow rays; and watertightness of closed meshes at shared edges and
// vertices. The measured agreement is printed and recorded as test properties.
#include <gtest/gtest.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <limits>
#include <span>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "accel/accelerator.h"
#include "core/ray_lanes.h"
#include "core/texture_cache.h"
#include "core/sampling.h"
#include "core/scene.h"
#include "core/transform.h"
#include "support/both_accelerators.h"
#include "support/test_meshes.h"
#include "support/test_support.h"

namespace penumbra {
namespace {

using test::makeIcosphere;
using test::makeTriangleCube;

// Render threads run with flush-to-zero and denormals-are-zero; so do these
// tests (restoring the previous mode afterwards).
class FlushDenormalsScope {
public:
    FlushDenormalsScope() : ftz_(_MM_GET_FLUSH_ZERO_MODE()), daz_(_MM_GET_DENORMALS_ZERO_MODE()) {
        _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
        _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
    }
    ~FlushDenormalsScope() {
        _MM_SET_FLUSH_ZERO_MODE(ftz_);
        _MM_SET_DENORMALS_ZERO_MODE(daz_);
    }
    FlushDenormalsScope(const FlushDenormalsScope&) = delete;
    FlushDenormalsScope& operator=(const FlushDenormalsScope&) = delete;

private:
    unsigned ftz_, daz_;
};

// Deterministic uniform floats (std::mt19937's output is fully specified;
// the standard distributions are not).
class Rng {
public:
    explicit Rng(uint32_t seed) : g_(seed) {}
    float uniform() { return static_cast<float>(g_() >> 8) * 0x1p-24f; }
    float range(float lo, float hi) { return lo + (hi - lo) * uniform(); }
    Vec3f inBox(float lo, float hi) { return {range(lo, hi), range(lo, hi), range(lo, hi)}; }
    Vec3f direction() { return squareToUniformSphere({uniform(), uniform()}); }

private:
    std::mt19937 g_;
};

Logger quietLogger() {
    return Logger([](LogLevel, std::string_view) {});
}

// Rays first .. first + 15 (fewer at the end) as a packet's lanes, the rest idle.
RayLanes lanesOf(const std::vector<Ray>& rays, size_t first) {
    RayLanes lanes;
    const size_t n = std::min<size_t>(RayLanes::kWidth, rays.size() - first);
    for (size_t l = 0; l < size_t(RayLanes::kWidth); ++l) {
        lanes.active[l] = l < n;
        if (l < n) lanes.set(int(l), rays[first + l]);
    }
    return lanes;
}

// A bumpy terrain grid of n x n cells (2 n^2 triangles) over [-10, 10]^2.
TriangleMesh makeHeightField(int n, float y0, Rng& rng) {
    TriangleMesh m;
    m.name = "terrain";
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            float x = -10.f + 20.f * i / n, z = -10.f + 20.f * j / n;
            m.positions.push_back({x, y0 + 1.5f * std::sin(0.7f * x) * std::cos(0.5f * z) + rng.range(-0.2f, 0.2f), z});
        }
    }
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            uint32_t a = j * (n + 1) + i, b = a + 1, c = a + (n + 1), d = c + 1;
            m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
        }
    }
    return m;
}

// A few thousand primitives of every kind in [-10, 10]^3.
Scene makeRandomScene(uint32_t seed) {
    Rng rng(seed);
    Scene s;
    for (int i = 0; i < 200; ++i) s.spheres.push_back(Sphere{rng.inBox(-10.f, 10.f), rng.range(0.1f, 0.8f), 0});
    for (int i = 0; i < 150; ++i) {
        Vec3f h{rng.range(0.1f, 0.7f), rng.range(0.1f, 0.7f), rng.range(0.1f, 0.7f)};
        Transform place = Transform::translate(rng.inBox(-10.f, 10.f));
        if (i % 2) place = place * Transform::rotate(rng.range(0.f, 360.f), rng.direction());
        s.boxes.push_back(makeBox(-1.f * h, h, place));
    }
    for (int i = 0; i < 150; ++i) {
        s.rectangles.push_back(Rectangle{rng.inBox(-10.f, 10.f), rng.range(0.2f, 1.5f) * rng.direction(),
                                         rng.range(0.2f, 1.5f) * rng.direction(), 0});
    }
    for (int i = 0; i < 150; ++i)
        s.disks.push_back(Disk{rng.inBox(-10.f, 10.f), rng.direction(), rng.range(0.1f, 0.8f), 0});
    s.planes.push_back(Plane{{0.f, -9.f, 0.f}, {0.f, 1.f, 0.f}, false, 0});
    s.planes.push_back(Plane{{0.f, 0.f, -11.f}, normalize(Vec3f{0.2f, 0.1f, 1.f}), true, 0});
    s.meshes.push_back(makeIcosphere({1.f, 0.5f, -1.f}, 3.5f, 3));
    s.meshes.push_back(makeHeightField(16, -6.f, rng));
    // Instances of a group (a small icosphere and a cube) and of a lone cube:
    // rotated, non-uniformly scaled, some mirrored, one prototype overriding its material.
    s.prototypes.push_back(Prototype{"group", {makeIcosphere({0.f, 0.f, 0.f}, 0.6f, 1),
                                               makeTriangleCube({0.3f, -0.2f, -0.2f}, {0.9f, 0.4f, 0.4f})}});
    s.prototypes.push_back(Prototype{"cube", {makeTriangleCube({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f})}});
    for (int i = 0; i < 30; ++i) {
        Vec3f scale{rng.range(0.5f, 1.5f), rng.range(0.5f, 1.5f), rng.range(0.5f, 1.5f)};
        if (i % 5 == 0) scale.x = -scale.x;
        const Transform place = Transform::translate(rng.inBox(-10.f, 10.f)) *
                                Transform::rotate(rng.range(0.f, 360.f), rng.direction()) * Transform::scale(scale);
        s.instances.push_back(makeInstance(uint32_t(i % 2), place, i % 4 == 3 ? 0u : kNoMaterialOverride));
    }
    s.finalize(quietLogger());
    return s;
}

// Pinhole camera rays, one jittered ray per pixel.
std::vector<Ray> cameraRays(int w, int h, Vec3f eye, Vec3f lookAt, Rng& rng) {
    const Vec3f wv = normalize(eye - lookAt);
    const Vec3f uv = normalize(cross(Vec3f{0.f, 1.f, 0.f}, wv));
    const Vec3f vv = cross(wv, uv);
    const float tanHalf = std::tan(0.5f * 45.f * kPi / 180.f), aspect = float(w) / float(h);
    std::vector<Ray> rays;
    rays.reserve(size_t(w) * h);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            float sx = (2.f * (x + rng.uniform()) / w - 1.f) * tanHalf * aspect;
            float sy = (1.f - 2.f * (y + rng.uniform()) / h) * tanHalf;
            rays.push_back(Ray{eye, normalize(-1.f * wv + sx * uv + sy * vv), 0.f, kInfinity});
        }
    }
    return rays;
}

std::vector<Ray> randomRays(size_t n, Rng& rng) {
    std::vector<Ray> rays;
    rays.reserve(n);
    for (size_t i = 0; i < n; ++i) rays.push_back(Ray{rng.inBox(-12.f, 12.f), rng.direction(), 0.f, kInfinity});
    return rays;
}

// Runs body(i) for i in [0, n) on all cores: the naive reference is O(N) per
// ray, and both accelerators promise thread-safe queries anyway. Each thread
// sets FTZ/DAZ like a render thread when `flushDenormals` is true.
template <class Body>
void parallelFor(size_t n, bool flushDenormals, Body body) {
    const size_t threads = std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
    std::vector<std::thread> pool;
    for (size_t k = 0; k < threads; ++k) {
        pool.emplace_back([=, &body] {
            std::optional<FlushDenormalsScope> ftz;
            if (flushDenormals) ftz.emplace();
            for (size_t i = k; i < n; i += threads) body(i);
        });
    }
    for (auto& t : pool) t.join();
}

bool denormalsFlushed() { return _MM_GET_FLUSH_ZERO_MODE() == _MM_FLUSH_ZERO_ON; }

struct IntersectStats {
    size_t rays = 0, naiveHits = 0, agree = 0;
    double maxRelT = 0.0;
    double naiveSeconds = 0.0, embreeSeconds = 0.0;
    std::vector<std::optional<PrimIntersection>> naive;  // the reference answers, for the shadow rays
};

constexpr double kRelTolerance = 1e-4;

double seconds(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

IntersectStats compareIntersect(const Accelerator& naive, const Accelerator& embree, const std::vector<Ray>& rays) {
    IntersectStats s;
    s.rays = rays.size();
    s.naive.resize(rays.size());
    std::vector<std::optional<PrimIntersection>> fast(rays.size());
    auto t0 = std::chrono::steady_clock::now();
    const bool ftz = denormalsFlushed();
    parallelFor(rays.size(), ftz, [&](size_t i) { s.naive[i] = naive.intersectPrim(rays[i]); });
    auto t1 = std::chrono::steady_clock::now();
    parallelFor(rays.size(), ftz, [&](size_t i) { fast[i] = embree.intersectPrim(rays[i]); });
    auto t2 = std::chrono::steady_clock::now();
    s.naiveSeconds = seconds(t0, t1);
    s.embreeSeconds = seconds(t1, t2);
    for (size_t i = 0; i < rays.size(); ++i) {
        const auto &a = s.naive[i], &b = fast[i];
        if (a) ++s.naiveHits;
        if (!a && !b) {
            ++s.agree;
            continue;
        }
        if (!a || !b || !(a->ref == b->ref)) continue;
        // Relative to t with a floor of one scene unit (as in the ray offset
        // rule): a triangle hit's error scales with the coordinates, so rays
        // starting next to a surface would otherwise inflate it.
        double rel = std::fabs(double(a->t) - double(b->t)) / std::max(double(a->t), 1.0);
        if (rel <= kRelTolerance) ++s.agree;
        s.maxRelT = std::max(s.maxRelT, rel);
    }
    return s;
}

struct OcclusionStats {
    size_t rays = 0, naiveOccluded = 0, agree = 0;
    double naiveSeconds = 0.0, embreeSeconds = 0.0;
};

OcclusionStats compareOccluded(const Accelerator& naive, const Accelerator& embree, const std::vector<Ray>& rays) {
    OcclusionStats s;
    s.rays = rays.size();
    std::vector<char> a(rays.size()), b(rays.size());
    auto t0 = std::chrono::steady_clock::now();
    const bool ftz = denormalsFlushed();
    parallelFor(rays.size(), ftz, [&](size_t i) { a[i] = naive.occluded(rays[i]); });
    auto t1 = std::chrono::steady_clock::now();
    parallelFor(rays.size(), ftz, [&](size_t i) { b[i] = embree.occluded(rays[i]); });
    auto t2 = std::chrono::steady_clock::now();
    s.naiveSeconds = seconds(t0, t1);
    s.embreeSeconds = seconds(t1, t2);
    for (size_t i = 0; i < rays.size(); ++i) {
        s.naiveOccluded += a[i] ? 1 : 0;
        s.agree += a[i] == b[i] ? 1 : 0;
    }
    return s;
}

// Shadow rays as the renderer makes them: from each primary hit towards a
// point on an area-light-like region, or towards a distant light; rays that
// missed become random finite segments, and so do hits far out on the
// infinite planes: a shadow ray from 1e9 units away has an origin whose float
// spacing exceeds the primitives' size, so whether it grazes a small box is
// noise in both accelerators (their BVH and loop see different noise).
std::vector<Ray> shadowRays(const Scene& scene, const std::vector<Ray>& primary,
                            const std::vector<std::optional<PrimIntersection>>& hits, Rng& rng) {
    std::vector<Ray> rays;
    rays.reserve(primary.size());
    for (size_t i = 0; i < primary.size(); ++i) {
        if (hits[i] && hits[i]->t < 1e3f) {
            Hit h = scene.completeHit(primary[i], hits[i]->ref, hits[i]->t, hits[i]->u, hits[i]->v);
            if (i % 4 == 0) {
                rays.push_back(spawnRay(h.p, h.ng, normalize(Vec3f{0.3f, 1.f, 0.2f})));
            } else {
                Vec3f light{rng.range(-8.f, 8.f), 12.f, rng.range(-8.f, 8.f)};
                rays.push_back(spawnRayTo(h.p, h.ng, light));
            }
        } else {
            Vec3f o = rng.inBox(-12.f, 12.f), target = rng.inBox(-12.f, 12.f);
            rays.push_back(Ray{o, normalize(target - o), 0.f, length(target - o)});
        }
    }
    return rays;
}

std::string percent(size_t part, size_t whole) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(4) << 100.0 * double(part) / double(whole);
    return os.str();
}

void report(const std::string& label, const IntersectStats& is, const OcclusionStats& os) {
    std::cout << "[agreement] " << label << ": intersect " << is.agree << "/" << is.rays << " rays agree ("
              << percent(is.agree, is.rays) << "%), naive hits " << is.naiveHits << ", max rel t error "
              << std::scientific << std::setprecision(3) << is.maxRelT << std::defaultfloat << "; occluded "
              << os.agree << "/" << os.rays << " (" << percent(os.agree, os.rays) << "%), naive occluded "
              << os.naiveOccluded << "; time naive " << std::setprecision(3) << is.naiveSeconds + os.naiveSeconds
              << " s, embree " << is.embreeSeconds + os.embreeSeconds << " s (" << std::thread::hardware_concurrency()
              << " threads)\n";
    ::testing::Test::RecordProperty(label + "_intersect_agreement_pct", percent(is.agree, is.rays));
    std::ostringstream rel;
    rel << std::scientific << std::setprecision(3) << is.maxRelT;
    ::testing::Test::RecordProperty(label + "_max_rel_t_error", rel.str());
    ::testing::Test::RecordProperty(label + "_occluded_agreement_pct", percent(os.agree, os.rays));
}

TEST(AcceleratorAgreementTest, EmbreeMatchesNaiveOnRandomScene) {
    FlushDenormalsScope ftz;
    const Scene scene = makeRandomScene(7);
    ASSERT_GE(scene.primitiveCount(), 2000u);
    ASSERT_EQ(scene.meshes.size(), 2u);
    ASSERT_EQ(scene.instances.size(), 30u);
    auto naive = makeNaiveAccelerator(scene);
    auto embree = makeEmbreeAccelerator(scene);
    std::cout << "[agreement] scene: " << scene.primitiveCount() << " primitives (" << scene.triangleCount()
              << " triangles), embree memory " << embree->memoryBytes() << " bytes\n";

    Rng rng(11);
    const std::vector<Ray> coherent = cameraRays(250, 200, {0.f, 3.f, 28.f}, {0.f, 0.f, 0.f}, rng);
    const std::vector<Ray> incoherent = randomRays(50000, rng);
    ASSERT_EQ(coherent.size() + incoherent.size(), 100000u);

    size_t totalRays = 0, totalAgree = 0, totalShadow = 0, totalShadowAgree = 0;
    for (const auto& [label, rays] : {std::pair{std::string("coherent"), &coherent},
                                      std::pair{std::string("incoherent"), &incoherent}}) {
        IntersectStats is = compareIntersect(*naive, *embree, *rays);
        std::vector<Ray> shadow = shadowRays(scene, *rays, is.naive, rng);
        OcclusionStats os = compareOccluded(*naive, *embree, shadow);
        report(label, is, os);
        // The rays must actually exercise the scene, not fly past it.
        EXPECT_GT(is.naiveHits, rays->size() / 2) << label;
        EXPECT_GT(os.naiveOccluded, shadow.size() / 10) << label;
        EXPECT_LT(os.naiveOccluded, shadow.size() * 9 / 10) << label;
        EXPECT_LE(is.maxRelT, 1e-3) << label;
        totalRays += is.rays;
        totalAgree += is.agree;
        totalShadow += os.rays;
        totalShadowAgree += os.agree;
    }
    EXPECT_GE(double(totalAgree), 0.9999 * double(totalRays));
    EXPECT_GE(double(totalShadowAgree), 0.9999 * double(totalShadow));
}

TEST(AcceleratorAgreementTest, AgreementHoldsWithoutFlushToZeroAndForEveryBuildQuality) {
    const Scene scene = makeRandomScene(23);
    auto naive = makeNaiveAccelerator(scene);
    Rng rng(5);
    const std::vector<Ray> rays = randomRays(4000, rng);
    IntersectStats reference;
    for (BuildQuality q : {BuildQuality::Low, BuildQuality::Medium, BuildQuality::High}) {
        auto embree = makeEmbreeAccelerator(scene, q);
        IntersectStats is = compareIntersect(*naive, *embree, rays);
        // Few rays here: allow one disagreement in 4000 (0.025 %).
        EXPECT_GE(is.agree + 1, is.rays) << "quality " << int(q);
        EXPECT_GT(is.naiveHits, rays.size() / 2);
        std::vector<Ray> shadow = shadowRays(scene, rays, is.naive, rng);
        OcclusionStats os = compareOccluded(*naive, *embree, shadow);
        EXPECT_GE(os.agree + 1, os.rays) << "quality " << int(q);
    }
}

// ---------------------------------------------------------------- alpha cutouts

// A 16 x 16 RGBA checkerboard (white, alpha 255 or 0) written as a PNG.
std::string writeAlphaChecker() {
    const std::string path = (test::tempDir() / "checker.png").string();
    std::vector<unsigned char> px;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) px.insert(px.end(), {255, 255, 255, (x + y) % 2 ? (unsigned char)0 : (unsigned char)255});
    auto out = OIIO::ImageOutput::create(path);
    OIIO::ImageSpec spec(16, 16, 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, px.data())) return {};
    out->close();
    return path;
}

// The random scene with alpha: the icosphere and the odd rectangles Blend at
// 0.5, the terrain (given uvs) and the cube prototype cut by the checker, the
// instances that override their material Blend at 0.3.
Scene makeAlphaScene(uint32_t seed, const std::string& checker) {
    Scene s = makeRandomScene(seed);
    auto add = [&](AlphaMode mode, float opacity, bool textured) {
        Material m;
        m.alphaMode = mode;
        m.opacity = opacity;
        if (textured) {
            m.diffuseTexture = checker;
            bindTextures(m, [&](std::string& path, TextureColorSpace space) { return s.addTexture({path, space}); });
        }
        s.materials.push_back(m);
        return uint32_t(s.materials.size() - 1);
    };
    const uint32_t half = add(AlphaMode::Blend, 0.5f, false), cut = add(AlphaMode::Mask, 1.f, true),
                   faint = add(AlphaMode::Blend, 0.3f, false);
    s.meshes[0].material = half;
    TriangleMesh& terrain = s.meshes[1];
    for (const Vec3f& p : terrain.positions) terrain.uvs.push_back({(p.x + 10.f) / 5.f, (p.z + 10.f) / 5.f});
    terrain.material = cut;
    for (size_t i = 1; i < s.rectangles.size(); i += 2) s.rectangles[i].material = half;
    s.prototypes[1].meshes[0].material = cut;
    for (Instance& in : s.instances)
        if (in.material != kNoMaterialOverride) in.material = faint;
    s.finalize(quietLogger());
    return s;
}

TEST(AcceleratorAgreementTest, AlphaCutoutsAgreeHitForHit) {
    FlushDenormalsScope ftz;
    const std::string checker = writeAlphaChecker();
    ASSERT_FALSE(checker.empty());
    const Scene scene = makeAlphaScene(7, checker);
    const auto textures = std::make_shared<const TextureCache>(scene.textures, quietLogger());
    auto naive = makeNaiveAccelerator(scene, textures);
    auto embree = makeEmbreeAccelerator(scene, BuildQuality::High, textures);
    ASSERT_TRUE(embree->alphaTest().any());
    auto opaque = makeEmbreeAccelerator(scene);  // no textures: only the Blend factors cut out
    Rng rng(11);
    const std::vector<Ray> coherent = cameraRays(120, 100, {0.f, 3.f, 28.f}, {0.f, 0.f, 0.f}, rng);
    const std::vector<Ray> incoherent = randomRays(12000, rng);
    for (const auto& [label, rays] : {std::pair{std::string("alpha coherent"), &coherent},
                                      std::pair{std::string("alpha incoherent"), &incoherent}}) {
        IntersectStats is = compareIntersect(*naive, *embree, *rays);
        std::vector<Ray> shadow = shadowRays(scene, *rays, is.naive, rng);
        OcclusionStats os = compareOccluded(*naive, *embree, shadow);
        report(label, is, os);
        EXPECT_GE(double(is.agree), 0.9999 * double(is.rays)) << label;
        EXPECT_GE(double(os.agree), 0.9999 * double(os.rays)) << label;
        // The cutouts change what many rays meet (the checker is not read without textures).
        size_t changed = 0, batchSame = 0;
        std::vector<std::optional<PrimIntersection>> batch(rays->size());
        embree->intersectPrimBatch(*rays, batch);
        for (size_t i = 0; i < rays->size(); ++i) {
            const auto a = is.naive[i], b = opaque->intersectPrim((*rays)[i]);
            changed += a.has_value() != b.has_value() || (a && !(a->ref == b->ref));
            const auto one = embree->intersectPrim((*rays)[i]);
            batchSame += one.has_value() == batch[i].has_value() && (!one || one->ref == batch[i]->ref);
        }
        std::cout << "[agreement] " << label << ": the checker changed " << changed << " of " << rays->size()
                  << " closest hits\n";
        EXPECT_GT(changed, rays->size() / 50) << label;
        EXPECT_GE(double(batchSame), 0.9999 * double(rays->size())) << label;
    }
}

// ---------------------------------------------------------------- watertightness

struct WatertightCount {
    size_t rays = 0, hits = 0;
};

void shoot(const Accelerator& acc, const Ray& r, WatertightCount& c) {
    ++c.rays;
    c.hits += acc.intersectPrim(r) ? 1 : 0;
}

// Watertightness and batching hold for each accelerator on its own.
class EachAcceleratorWatertight : public test::ForBothAccelerators {};
class EachAcceleratorBatch : public test::ForBothAccelerators {};

// A ray from outside towards `target` on the surface, arriving from the
// random outward direction w, which must satisfy `entering` so that the ray
// truly enters the mesh there rather than grazing it.
template <class Entering>
Ray rayFromOutside(const Vec3f& target, Entering entering, Rng& rng) {
    Vec3f w;
    do {
        w = rng.direction();
    } while (!entering(w));
    Vec3f o = target + rng.range(0.5f, 6.f) * w;
    return Ray{o, normalize(target - o), 0.f, kInfinity};
}

TEST_P(EachAcceleratorWatertight, RaysAtSharedEdgesAndVerticesOfAnIcosphereAlwaysHit) {
    FlushDenormalsScope ftz;
    const Vec3f center{0.3f, -0.2f, 0.1f};
    Scene scene;
    scene.meshes.push_back(makeIcosphere(center, 2.f, 2));
    scene.finalize(quietLogger());
    ASSERT_EQ(scene.triangleCount(), 320u);
    const auto acc = makeAccelerator(GetParam(), scene);
    const TriangleMesh& m = scene.meshes[0];

    // Targets: every vertex, and points along every edge (each edge once).
    std::vector<Vec3f> targets(m.positions.begin(), m.positions.end());
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        for (int e = 0; e < 3; ++e) {
            uint32_t a = m.indices[3 * t + e], b = m.indices[3 * t + (e + 1) % 3];
            if (a > b) continue;
            for (float s : {0.125f, 0.5f, 0.8f}) targets.push_back((1.f - s) * m.positions[a] + s * m.positions[b]);
        }
    }
    Rng rng(3);
    WatertightCount c;
    for (const Vec3f& target : targets) {
        shoot(*acc, Ray{center, target - center, 0.f, kInfinity}, c);  // from inside
        const Vec3f n = normalize(target - center);
        // Within about 70 degrees of the radial direction; the faces around a
        // vertex tilt only about 10 degrees away from the tangent plane.
        auto entering = [&](const Vec3f& w) { return dot(w, n) > 0.35f; };
        for (int k = 0; k < 8; ++k) shoot(*acc, rayFromOutside(target, entering, rng), c);
    }
    std::cout << "[watertight] icosphere: " << c.rays << " rays at edges/vertices, " << acc->name() << " hits " << c.hits
              << "\n";
    EXPECT_GT(c.rays, 4000u);
    EXPECT_EQ(c.hits, c.rays);
}

TEST_P(EachAcceleratorWatertight, RaysAtTheDiagonalsEdgesAndCornersOfATriangleCubeAlwaysHit) {
    FlushDenormalsScope ftz;
    Scene scene;
    scene.meshes.push_back(makeTriangleCube({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}));
    scene.finalize(quietLogger());
    const auto acc = makeAccelerator(GetParam(), scene);
    const TriangleMesh& m = scene.meshes[0];

    // The face diagonals are the edges shared inside each face; the cube's
    // own edges and corners are shared between faces.
    std::vector<Vec3f> targets(m.positions.begin(), m.positions.end());
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        for (int e = 0; e < 3; ++e) {
            const Vec3f &a = m.positions[m.indices[3 * t + e]], &b = m.positions[m.indices[3 * t + (e + 1) % 3]];
            for (int k = 1; k < 8; ++k) targets.push_back(a + (k / 8.f) * (b - a));
        }
    }
    Rng rng(9);
    WatertightCount c;
    for (const Vec3f& target : targets) {
        shoot(*acc, Ray{{0.f, 0.f, 0.f}, target, 0.f, kInfinity}, c);  // from the centre
        // Arrive from outside every face the point lies on (all three at a
        // corner, two on a cube edge, one on a face diagonal).
        auto entering = [&](const Vec3f& w) {
            for (int i = 0; i < 3; ++i)
                if (std::fabs(target[i]) == 1.f && !(w[i] * target[i] > 0.25f)) return false;
            return true;
        };
        for (int k = 0; k < 8; ++k) shoot(*acc, rayFromOutside(target, entering, rng), c);
        // Axis-aligned rays straight down onto the points inside the top face.
        if (target.y == 1.f && std::fabs(target.x) < 1.f && std::fabs(target.z) < 1.f)
            shoot(*acc, Ray{target + Vec3f{0.f, 3.f, 0.f}, {0.f, -1.f, 0.f}, 0.f, kInfinity}, c);
    }
    std::cout << "[watertight] cube: " << c.rays << " rays at edges/corners, " << acc->name() << " hits " << c.hits
              << "\n";
    EXPECT_GT(c.rays, 2000u);
    EXPECT_EQ(c.hits, c.rays);
}

// Packets first test their lanes against the bounds of the Embree geometry and
// skip the lanes (and packets) that miss them. At the edges and corners of
// those bounds (a cube's), rays arriving from outside, rays along the axes
// (zero direction components) grazing or crossing its faces, and shadow rays
// that stop just past the surface or just short of it answer in 16-wide
// packets exactly as single rays do, near the origin and far from it, with
// flush-to-zero as in render threads and without it (axial rays whose other
// components are denormal rather than zero).
TEST_P(EachAcceleratorWatertight, PacketsAnswerAsSingleRaysAtTheEdgesOfTheSceneBounds) {
    for (const bool flush : {true, false}) {
        std::optional<FlushDenormalsScope> ftz;
        if (flush) ftz.emplace();
        const float zero = flush ? 0.f : 1e-40f;  // a denormal: the slab test's reciprocal overflows
        for (const Vec3f offset : {Vec3f{0.f, 0.f, 0.f}, Vec3f{1e4f, -2e3f, 5e2f}}) {
            Scene scene;
            scene.meshes.push_back(makeTriangleCube(offset + Vec3f{-1.f, -1.f, -1.f}, offset + Vec3f{1.f, 1.f, 1.f}));
            scene.finalize(quietLogger());
            const auto acc = makeAccelerator(GetParam(), scene);
            Rng rng(17);
            std::vector<Ray> arriving, axial, pastShadow, shortShadow;
            for (int corner = 0; corner < 8; ++corner) {
                const Vec3f c{corner & 1 ? 1.f : -1.f, corner & 2 ? 1.f : -1.f, corner & 4 ? 1.f : -1.f};
                for (int axis = 0; axis < 3; ++axis) {
                    // Points along the cube edge from this corner along `axis`, the corner itself included.
                    for (int k = 0; k < 4; ++k) {
                        Vec3f local = c;
                        local[axis] = c[axis] * (1.f - 0.5f * float(k));
                        const Vec3f target = offset + local;
                        auto entering = [&](const Vec3f& w) {
                            for (int i = 0; i < 3; ++i)
                                if (std::fabs(local[i]) == 1.f && !(w[i] * local[i] > 0.25f)) return false;
                            return true;
                        };
                        const Ray r = rayFromOutside(target, entering, rng);
                        arriving.push_back(r);
                        const float d = length(target - r.o);
                        pastShadow.push_back(Ray{r.o, r.d, 0.f, d * (1.f + 1e-4f)});
                        shortShadow.push_back(Ray{r.o, r.d, 0.f, d * (1.f - 1e-3f)});
                        for (int a = 0; a < 3; ++a) {
                            Vec3f dir{zero, zero, zero};
                            dir[a] = local[a] == 0.f ? 1.f : -local[a];
                            const Vec3f o = target - 3.f * dir;
                            axial.push_back(Ray{o, dir, 0.f, kInfinity});
                            axial.push_back(Ray{o, dir, 0.f, 3.f * (1.f + 1e-4f)});  // stops just past the target
                        }
                    }
                }
            }
            std::vector<Ray> all = arriving;
            all.insert(all.end(), axial.begin(), axial.end());
            std::vector<std::optional<PrimIntersection>> batch(all.size());
            for (size_t b = 0; b < all.size(); b += 16) {
                const size_t n = std::min<size_t>(16, all.size() - b);
                acc->intersectPrimBatch(std::span(all).subspan(b, n), std::span(batch).subspan(b, n));
            }
            size_t arrivingHits = 0;
            for (size_t i = 0; i < all.size(); ++i) {
                const std::optional<PrimIntersection> single = acc->intersectPrim(all[i]);
                ASSERT_EQ(single.has_value(), batch[i].has_value())
                    << "ray " << i << " offset " << offset.x << " flush " << flush;
                if (single) {
                    EXPECT_EQ(single->ref, batch[i]->ref);
                    EXPECT_EQ(single->t, batch[i]->t);
                }
                if (i < arriving.size()) arrivingHits += single ? 1 : 0;
            }
            EXPECT_EQ(arrivingHits, arriving.size());

            std::vector<Ray> shadow = pastShadow;
            shadow.insert(shadow.end(), shortShadow.begin(), shortShadow.end());
            std::vector<uint8_t> blocked(shadow.size());
            for (size_t b = 0; b < shadow.size(); b += 16) {
                const size_t n = std::min<size_t>(16, shadow.size() - b);
                acc->occludedBatch(std::span(shadow).subspan(b, n), std::span(blocked).subspan(b, n));
            }
            for (size_t i = 0; i < shadow.size(); ++i) {
                const std::string where = "shadow ray " + std::to_string(i) + " offset " + std::to_string(offset.x) +
                                          (flush ? " (flush-to-zero)" : "");
                EXPECT_EQ(blocked[i] != 0, acc->occluded(shadow[i])) << where;
                EXPECT_EQ(blocked[i] != 0, i < pastShadow.size()) << where;
            }
        }
    }
}

// Occlusion packets skip Embree for the lanes that meet no shape's bounds
// (in scenes of a few shapes): shadow rays leaving a box face, a sphere and
// a rectangle towards a rectangle light, stopping short of it as the
// integrator's do, rays that pass a sphere just outside and just inside its
// radius, and rays that stop just short of a shape or just past it must
// answer in 16-wide packets as single rays and the naive accelerator do,
// near the origin and far from it.
TEST(AcceleratorAgreementTest, OcclusionPacketsAnswerAsSingleRaysAtEveryShapesBounds) {
    for (const Vec3f offset : {Vec3f{0.f, 0.f, 0.f}, Vec3f{3e3f, -1e3f, 2e2f}}) {
        Scene scene;
        scene.boxes.push_back(makeBox(offset + Vec3f{-3.f, -0.1f, -3.f}, offset + Vec3f{3.f, 0.f, 3.f}));  // a floor
        scene.boxes.push_back(makeBox(Vec3f{-0.3f, -0.3f, -0.3f}, Vec3f{0.3f, 0.3f, 0.3f},
                                      Transform::translate(offset + Vec3f{-1.5f, 0.8f, 0.5f}) *
                                          Transform::rotate(30.f, normalize(Vec3f{1.f, 2.f, 0.5f}))));
        scene.spheres.push_back(Sphere{offset + Vec3f{1.f, 0.7f, 0.f}, 0.7f, 0});
        const Rectangle light{offset + Vec3f{-0.6f, 2.5f, -0.5f}, Vec3f{1.2f, 0.f, 0.f}, Vec3f{0.f, 0.f, 1.f}, 0};
        scene.rectangles.push_back(light);
        scene.disks.push_back(Disk{offset + Vec3f{0.f, 1.2f, 1.5f}, normalize(Vec3f{0.2f, 1.f, -0.3f}), 0.4f, 0});
        TriangleMesh tri;
        for (Vec3f v : {Vec3f{-2.f, 1.f, -1.f}, Vec3f{-1.f, 1.5f, -1.5f}, Vec3f{-1.5f, 2.f, -0.5f}})
            tri.positions.push_back(offset + v);
        tri.indices = {0, 1, 2};
        scene.meshes.push_back(tri);
        scene.finalize(quietLogger());
        const auto embree = makeAccelerator(AcceleratorKind::Embree, scene);
        const auto naive = makeAccelerator(AcceleratorKind::Naive, scene);
        Rng rng(23);
        std::vector<Ray> rays;
        const auto onLight = [&] { return light.p0 + rng.uniform() * light.a + rng.uniform() * light.b; };
        const Sphere& ball = scene.spheres[0];
        for (int k = 0; k < 400; ++k) {
            // Leaving the floor's top face, the sphere and the light's own plane (from below it).
            const Vec3f floorPoint = offset + Vec3f{rng.range(-2.9f, 2.9f), 0.f, rng.range(-2.9f, 2.9f)};
            rays.push_back(spawnRayTo(floorPoint, Vec3f{0.f, 1.f, 0.f}, onLight()));
            const Vec3f n = rng.direction();
            rays.push_back(spawnRayTo(ball.center + ball.radius * n, n, onLight()));
            const Vec3f underLight = offset + Vec3f{rng.range(-3.f, 3.f), 2.5f - 1e-3f, rng.range(-3.f, 3.f)};
            rays.push_back(spawnRayTo(underLight, Vec3f{0.f, -1.f, 0.f}, floorPoint));
            // Passing the sphere at (1 -+ 1e-5) and (1 -+ 1e-3) of its radius, stopping past it.
            const Vec3f d = rng.direction();
            Vec3f side = normalize(cross(d, rng.direction()));
            for (const float f : {1.f - 1e-3f, 1.f - 1e-5f, 1.f + 1e-5f, 1.f + 1e-3f}) {
                const Vec3f o = ball.center + f * ball.radius * side - 3.f * d;
                rays.push_back(Ray{o, d, 0.f, 6.f});
            }
            // Stopping just short of a point on a shape or just past it.
            const Vec3f targets[] = {onLight(), ball.center + ball.radius * rng.direction(),
                                     scene.disks[0].center, offset + Vec3f{-1.5f, 1.5f, -1.f}};
            for (const Vec3f& t : targets) {
                const Vec3f o = offset + 4.f * rng.direction() + Vec3f{0.f, 1.f, 0.f};
                const float dist = length(t - o);
                const Vec3f dir = (t - o) / dist;
                rays.push_back(Ray{o, dir, 0.f, dist * (1.f - 1e-5f)});
                rays.push_back(Ray{o, dir, 0.f, dist * (1.f + 1e-5f)});
            }
        }
        size_t blocked = 0;
        for (size_t b = 0; b < rays.size(); b += 16) {
            const RayLanes lanes = lanesOf(rays, b);
            const int n = int(std::min<size_t>(16, rays.size() - b));
            uint8_t out[16];
            embree->occludedLanes(lanes, out);
            for (int l = 0; l < n; ++l) {
                const Ray& r = rays[b + size_t(l)];
                ASSERT_EQ(out[l] != 0, embree->occluded(r)) << "ray " << b + size_t(l) << " offset " << offset.x;
                ASSERT_EQ(out[l] != 0, naive->occluded(r)) << "ray " << b + size_t(l) << " offset " << offset.x;
                blocked += out[l];
            }
        }
        // Both answers are common: the packets are a mix of lanes Embree is asked about and lanes it is not.
        EXPECT_GT(blocked, rays.size() / 10);
        EXPECT_LT(blocked, rays.size() * 9 / 10);
    }
}

// A scene of few shapes (8, planes aside), whose spheres and boxes the
// Embree accelerator tests over the lanes itself (accel/lane_shapes.h), with
// the rectangle, the disk and the mesh in Embree; and the same scene with one
// sphere more, past the limit, where Embree holds them all. Single rays,
// packets of every width, camera packets and occlusion agree with the naive
// loop; on the lane-tested shapes the hits are the naive loop's bit for bit
// (the very same routines; Embree's box quads round differently).
TEST(AcceleratorAgreementTest, FewSpheresAndBoxesTestedOverTheLanesAgreeWithTheNaiveLoop) {
    FlushDenormalsScope ftz;
    for (const bool overLimit : {false, true}) {
        Rng rng(31);
        Scene scene;
        for (int i = 0; i < 3; ++i) scene.spheres.push_back(Sphere{rng.inBox(-6.f, 6.f), rng.range(0.5f, 2.f), 0});
        if (overLimit) scene.spheres.push_back(Sphere{{0.f, 6.f, 0.f}, 1.f, 0});
        for (int i = 0; i < 2; ++i) {
            const Vec3f h{rng.range(1.f, 3.f), rng.range(1.f, 3.f), rng.range(1.f, 3.f)};
            Transform place = Transform::translate(rng.inBox(-6.f, 6.f));
            if (i % 2) place = place * Transform::rotate(rng.range(0.f, 360.f), rng.direction());
            scene.boxes.push_back(makeBox(-1.f * h, h, place));
        }
        scene.rectangles.push_back(Rectangle{{-3.f, 2.f, -3.f}, {2.f, 0.f, 0.f}, {0.f, 0.5f, 2.f}, 0});
        scene.disks.push_back(Disk{{3.f, -2.f, 2.f}, normalize(Vec3f{0.3f, 1.f, 0.2f}), 1.5f, 0});
        scene.planes.push_back(Plane{{0.f, -8.f, 0.f}, {0.f, 1.f, 0.f}, false, 0});
        scene.meshes.push_back(makeIcosphere({-2.f, -1.f, 3.f}, 2.f, 2));
        scene.finalize(quietLogger());
        ASSERT_EQ(ShapeBounds(scene).available(), !overLimit);
        const auto naive = makeNaiveAccelerator(scene);
        const auto embree = makeEmbreeAccelerator(scene);
        const std::string label = overLimit ? "nine shapes" : "eight shapes";

        std::vector<Ray> rays = cameraRays(96, 64, {0.f, 2.f, 22.f}, {0.f, 0.f, 0.f}, rng);
        const std::vector<Ray> random = randomRays(6000, rng);
        rays.insert(rays.end(), random.begin(), random.end());
        for (size_t i = 0; i < 2000; ++i) {  // along the axes, from planes through the boxes' centres
            const Box& b = scene.boxes[i % scene.boxes.size()];
            const Vec3f c = b.worldFromObject.applyPoint({0.f, 0.f, 0.f});
            Vec3f o = rng.inBox(-9.f, 9.f), d{0.f, 0.f, 0.f};
            (&o.x)[i % 3] = (&c.x)[i % 3];
            (&d.x)[(i + 1) % 3] = i % 2 ? 1.f : -1.f;
            rays.push_back(Ray{o, d, 0.f, kInfinity});
        }
        IntersectStats is = compareIntersect(*naive, *embree, rays);
        EXPECT_GE(double(is.agree), 0.9999 * double(is.rays)) << label;
        EXPECT_GT(is.naiveHits, rays.size() / 3) << label;
        size_t analytic = 0;
        std::vector<std::optional<PrimIntersection>> batch(rays.size());
        embree->intersectPrimBatch(rays, batch, false);
        for (size_t i = 0; i < rays.size(); ++i) {
            const std::optional<PrimIntersection> single = embree->intersectPrim(rays[i]);
            ASSERT_EQ(batch[i].has_value(), single.has_value()) << label << " ray " << i;
            if (!single) continue;
            EXPECT_EQ(batch[i]->ref, single->ref) << label << " ray " << i;
            const ShapeKind kind = single->ref.kind;
            if (overLimit || (kind != ShapeKind::Sphere && kind != ShapeKind::Box && kind != ShapeKind::Plane)) continue;
            // Lane-tested shapes: the naive loop's hit, bit for bit, in packets and alone.
            ASSERT_TRUE(is.naive[i]) << label << " ray " << i;
            EXPECT_EQ(single->ref, is.naive[i]->ref) << label << " ray " << i;
            EXPECT_EQ(single->t, is.naive[i]->t) << label << " ray " << i;
            EXPECT_EQ(batch[i]->t, single->t) << label << " ray " << i;
            ++analytic;
        }
        if (!overLimit) {
            EXPECT_GT(analytic, rays.size() / 5);
        }
        // The camera rays as the renderer's 16-lane packets.
        for (size_t b = 0; b + RayLanes::kWidth <= 96 * 64; b += RayLanes::kWidth) {
            RayLanes lanes;
            for (int l = 0; l < RayLanes::kWidth; ++l) {
                lanes.set(l, rays[b + size_t(l)]);
                lanes.active[l] = 1;
            }
            std::optional<PrimIntersection> got[RayLanes::kWidth];
            embree->intersectPrimLanes(lanes, got);
            for (int l = 0; l < RayLanes::kWidth; ++l) {
                const std::optional<PrimIntersection>& want = is.naive[b + size_t(l)];
                ASSERT_EQ(got[l].has_value(), want.has_value()) << label << " lane ray " << b + size_t(l);
                if (!want) continue;
                EXPECT_EQ(got[l]->ref, want->ref) << label << " lane ray " << b + size_t(l);
                EXPECT_NEAR(got[l]->t, want->t, 1e-5f * std::max(want->t, 1.f)) << label;
            }
        }
        std::vector<Ray> shadow = shadowRays(scene, rays, is.naive, rng);
        OcclusionStats os = compareOccluded(*naive, *embree, shadow);
        report(label, is, os);
        EXPECT_GE(double(os.agree), 0.9999 * double(os.rays)) << label;
        EXPECT_GT(os.naiveOccluded, shadow.size() / 10) << label;
        std::vector<uint8_t> occBatch(shadow.size());
        embree->occludedBatch(shadow, occBatch);
        size_t same = 0;
        for (size_t i = 0; i < shadow.size(); ++i) same += (occBatch[i] != 0) == embree->occluded(shadow[i]);
        EXPECT_EQ(same, shadow.size()) << label;
    }
}

// Packets (intersectPrimBatch / occludedBatch, 16, 8, 4 and 1 lanes) give the
// answers of the single-ray queries, invalid rays included.
TEST_P(EachAcceleratorBatch, BatchedQueriesMatchSingleRays) {
    FlushDenormalsScope ftz;
    const Scene scene = makeRandomScene(3);
    const auto acc = makeAccelerator(GetParam(), scene);
    Rng rng(5);
    std::vector<Ray> rays = cameraRays(120, 100, {0.f, 3.f, 28.f}, {0.f, 0.f, 0.f}, rng);
    const std::vector<Ray> random = randomRays(8000, rng);
    rays.insert(rays.end(), random.begin(), random.end());
    // Invalid rays sprinkled in: they must miss, be counted, and never reach Embree.
    for (size_t i = 7; i < rays.size(); i += 997) rays[i].o.x = std::numeric_limits<float>::quiet_NaN();
    const size_t invalid = (rays.size() - 7 + 996) / 997;

    {
        const Accelerator* accel = acc.get();
        std::vector<std::optional<PrimIntersection>> single(rays.size()), batch(rays.size());
        const uint64_t before = accel->invalidRayCount();
        for (size_t i = 0; i < rays.size(); ++i) single[i] = accel->intersectPrim(rays[i]);
        EXPECT_EQ(accel->invalidRayCount() - before, invalid);
        // Batches of every width the implementation picks: 1..16 and longer
        // runs; then again as coherent batches (Embree's frustum traversal
        // where a packet's rays share an octant: the camera rays here).
        size_t pos = 0, same = 0;  // the last pass's count is printed below
        for (const bool coherent : {false, true}) {
            pos = 0;
            for (size_t len = 1; pos < rays.size(); len = len % 23 + 1) {
                const size_t n = std::min(len, rays.size() - pos);
                accel->intersectPrimBatch(std::span(rays).subspan(pos, n), std::span(batch).subspan(pos, n), coherent);
                pos += n;
            }
            EXPECT_EQ(accel->invalidRayCount() - before, (coherent ? 3 : 2) * invalid);
            same = 0;
            for (size_t i = 0; i < rays.size(); ++i) {
                const bool ok =
                    single[i].has_value() == batch[i].has_value() &&
                    (!single[i] || (single[i]->ref == batch[i]->ref &&
                                    std::fabs(single[i]->t - batch[i]->t) <= 1e-4f * std::max(single[i]->t, 1.f)));
                same += ok;
            }
            EXPECT_GE(double(same), 0.9999 * double(rays.size())) << accel->name() << " coherent " << coherent;
        }

        std::vector<Ray> shadow = shadowRays(scene, rays, single, rng);
        for (size_t i = 11; i < shadow.size(); i += 991) shadow[i].tfar = std::numeric_limits<float>::quiet_NaN();
        std::vector<uint8_t> occSingle(shadow.size()), occBatch(shadow.size());
        for (size_t i = 0; i < shadow.size(); ++i) occSingle[i] = accel->occluded(shadow[i]) ? 1 : 0;
        pos = 0;
        for (size_t len = 1; pos < shadow.size(); len = len % 19 + 1) {
            const size_t n = std::min(len, shadow.size() - pos);
            accel->occludedBatch(std::span(shadow).subspan(pos, n), std::span(occBatch).subspan(pos, n));
            pos += n;
        }
        size_t sameOcc = 0, occludedCount = 0;
        for (size_t i = 0; i < shadow.size(); ++i) {
            sameOcc += occSingle[i] == occBatch[i];
            occludedCount += occSingle[i];
        }
        EXPECT_GE(double(sameOcc), 0.9999 * double(shadow.size())) << accel->name();
        EXPECT_GT(occludedCount, shadow.size() / 10);
        std::cout << "[ measured ] " << accel->name() << " batch vs single: " << same << "/" << rays.size()
                  << " closest hits, " << sameOcc << "/" << shadow.size() << " occlusion answers identical\n";
    }
}

// Rays leaving a convex mesh, with the hints that say so (Accelerator::
// intersectPrimBatch's `leaving`): mirror-like rays above the surface, some
// within a thousandth of a degree of grazing it, and shadow rays to points on
// the other shapes, from hits on a convex icosphere beside a cube of triangles,
// a lane-tested sphere and a floor plane. In a scene of few shapes, where
// Embree skips what a hinted packet cannot meet, and with more shapes, the
// answers are the naive loop's, and the same as without the hints (the same
// primitive; t within a few ulps, as between packets and single rays). A hint
// is taken at its word: a ray aimed at the icosphere that claims to leave it
// does not find it, which shows that the queries skip it.
TEST(AcceleratorAgreementTest, RaysLeavingAConvexMeshWithHintsAnswerAsWithout) {
    FlushDenormalsScope ftz;
    for (const bool manyShapes : {false, true}) {
        Scene scene;
        scene.meshes.push_back(makeIcosphere({0.f, 1.5f, 0.f}, 1.5f, 2));
        scene.meshes.push_back(makeTriangleCube({2.f, 0.f, -1.f}, {3.f, 2.5f, 1.f}));
        scene.spheres.push_back(Sphere{Vec3f{-2.5f, 1.f, 0.5f}, 1.f, 0});
        scene.planes.push_back(Plane{Vec3f{0.f, 0.f, 0.f}, Vec3f{0.f, 1.f, 0.f}, 0});
        if (manyShapes)
            for (int i = 0; i < 8; ++i)
                scene.spheres.push_back(Sphere{Vec3f{-6.f + 1.5f * float(i), 4.5f, -3.f}, 0.5f, 0});
        scene.finalize(quietLogger());
        const auto embree = makeAccelerator(AcceleratorKind::Embree, scene);
        const auto naive = makeAccelerator(AcceleratorKind::Naive, scene);
        ASSERT_EQ(embree->shapeBounds().available(), !manyShapes);
        Rng rng(41);
        std::vector<Ray> rays, shadow, aimed;
        std::vector<int32_t> hints;  // the mirror-like rays' hints, set as the Whitted integrator sets them
        for (int k = 0; k < 600; ++k) {
            // A hit on the icosphere, as a camera ray finds it.
            const Vec3f target = Vec3f{0.f, 1.5f, 0.f} + 1.4f * rng.direction();
            const Vec3f eye = target + rng.range(2.f, 8.f) * normalize(target - Vec3f{0.f, 1.5f, 0.f} + rng.direction());
            const std::optional<Hit> h = naive->intersect(Ray{eye, normalize(target - eye), 0.f, kInfinity});
            if (!h || h->ref.kind != ShapeKind::Mesh || h->ref.object != 0) continue;
            ASSERT_EQ(scene.convexMeshOf(h->ref), 0);
            // From above, straight down through the icosphere, clear of the cube.
            const Vec3f top{rng.range(-0.5f, 0.5f), 10.f, rng.range(-0.5f, 0.5f)};
            aimed.push_back(Ray{top, normalize(Vec3f{rng.range(-0.5f, 0.5f), 2.5f, rng.range(-0.5f, 0.5f)} - top)});
            Vec3f w = rng.direction();
            if (dot(w, h->ng) < 0.f) w = -w;
            if (k % 4 == 0) {  // grazing: within 1e-5 rad of the triangle's plane
                const Vec3f along = normalize(w - dot(w, h->ng) * h->ng);
                w = normalize(along + rng.range(1e-7f, 1e-5f) * h->ng);
            }
            rays.push_back(spawnRay(h->p, h->ng, w));
            hints.push_back(dot(w, h->ng) > 0.f ? 0 : -1);  // rounding can leave a grazing ray below
            const Vec3f onOther[] = {Vec3f{rng.range(2.f, 3.f), rng.range(0.f, 2.5f), rng.range(-1.f, 1.f)},
                                     scene.spheres[0].center + scene.spheres[0].radius * rng.direction(),
                                     Vec3f{rng.range(-5.f, 5.f), 0.f, rng.range(-5.f, 5.f)},
                                     Vec3f{rng.range(-6.f, 6.f), 6.f, rng.range(-6.f, 6.f)}};
            for (const Vec3f& q : onOther)
                if (dot(q - h->p, h->ng) > 0.f) shadow.push_back(spawnRayTo(h->p, h->ng, q));
        }
        ASSERT_GT(rays.size(), 300u);
        const std::vector<int32_t> leaving(std::max(shadow.size(), aimed.size()), 0);
        size_t others = 0;
        for (const bool coherent : {false, true}) {
            std::vector<std::optional<Hit>> hinted(rays.size()), plain(rays.size());
            embree->intersectBatch(rays, hinted, coherent, hints);
            embree->intersectBatch(rays, plain, coherent);
            for (size_t i = 0; i < rays.size(); ++i) {
                const std::optional<Hit> ref = naive->intersect(rays[i]);
                ASSERT_EQ(hinted[i].has_value(), ref.has_value()) << "ray " << i << " many " << manyShapes;
                ASSERT_EQ(plain[i].has_value(), ref.has_value()) << "ray " << i << " many " << manyShapes;
                if (!ref) continue;
                if (hints[i] == 0) {
                    EXPECT_FALSE(ref->ref.kind == ShapeKind::Mesh && ref->ref.object == 0) << "ray " << i;
                }
                ASSERT_EQ(hinted[i]->ref, ref->ref) << "ray " << i;
                ASSERT_EQ(plain[i]->ref, ref->ref) << "ray " << i;
                EXPECT_NEAR(hinted[i]->t, ref->t, 1e-5f * ref->t) << "ray " << i;
                EXPECT_EQ(hinted[i]->t, plain[i]->t) << "ray " << i;
                others += 1;
            }
        }
        EXPECT_GT(others, rays.size() / 5);  // the hints do not hide the other shapes
        size_t blocked = 0;
        for (size_t b = 0; b < shadow.size(); b += 16) {
            const RayLanes lanes = lanesOf(shadow, b);
            const int n = int(std::min<size_t>(16, shadow.size() - b));
            uint8_t hinted[16], plain[16];
            embree->occludedLanes(lanes, hinted, leaving.data());
            embree->occludedLanes(lanes, plain);
            for (int l = 0; l < n; ++l) {
                const bool ref = naive->occluded(shadow[b + size_t(l)]);
                ASSERT_EQ(hinted[l] != 0, ref) << "shadow ray " << b + size_t(l) << " many " << manyShapes;
                ASSERT_EQ(plain[l] != 0, ref) << "shadow ray " << b + size_t(l) << " many " << manyShapes;
                blocked += ref;
            }
        }
        EXPECT_GT(blocked, shadow.size() / 10);
        EXPECT_LT(blocked, shadow.size() * 9 / 10);
        if (manyShapes) continue;
        // A false hint: rays from outside, straight at the icosphere, that meet no other mesh.
        std::vector<std::optional<Hit>> claimed(aimed.size());
        embree->intersectBatch(aimed, claimed, true, std::span(leaving.data(), aimed.size()));
        for (size_t i = 0; i < aimed.size(); ++i) {
            const std::optional<Hit> truth = naive->intersect(aimed[i]);
            ASSERT_TRUE(truth && truth->ref.kind == ShapeKind::Mesh && truth->ref.object == 0) << "ray " << i;
            ASSERT_TRUE(claimed[i] && claimed[i]->ref.kind == ShapeKind::Plane) << "ray " << i << ": the hint was not used";
        }
    }
}

PENUMBRA_FOR_BOTH_ACCELERATORS(EachAcceleratorWatertight);
PENUMBRA_FOR_BOTH_ACCELERATORS(EachAcceleratorBatch);


// The camera-ray packets (Accelerator::intersectLanes, which Embree answers
// with its coherent traversal) give the answers of the single-ray query (the
// same primitive, t within a few ulps, most bit for bit): a
// 4 x 4 block of neighbouring pixels per packet, as the renderer sends them,
// from eyes on the axes (so that some rays run along an axis or parallel to
// an axis plane), on the planes of the scene's boxes and meshes, and aimed at
// the edges and corners of triangle cubes, where neighbouring primitives meet
// at one distance; lanes with tiny direction components are mixed in.
TEST_P(EachAcceleratorBatch, CameraPacketsAnswerAsSingleRays) {
    FlushDenormalsScope ftz;
    Scene scene = makeRandomScene(11);
    scene.meshes.push_back(makeTriangleCube({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}));
    scene.finalize(quietLogger());
    const auto acc = makeAccelerator(GetParam(), scene);
    Rng rng(17);
    struct View {
        Vec3f eye, lookAt;
    };
    const View views[] = {{{0.f, 0.f, 28.f}, {0.f, 0.f, 0.f}},  {{28.f, 0.f, 0.f}, {0.f, 0.f, 0.f}},
                          {{0.f, 25.f, 0.5f}, {0.f, 0.f, 0.5f}}, {{1.f, 1.f, 12.f}, {1.f, 1.f, 0.f}},
                          {{-1.f, 0.f, 6.f}, {-1.f, 0.f, 1.f}},  {{-20.f, 10.f, 20.f}, {0.f, 2.f, 0.f}},
                          {{3.f, -1.f, 9.f}, {1.f, 1.f, 1.f}}};
    size_t lanes = 0, hits = 0, bitExact = 0;
    for (const View& v : views) {
        const int w = 24, h = 16;
        const std::vector<Ray> rays = cameraRays(w, h, v.eye, v.lookAt, rng);
        for (int by = 0; by < h; by += 4)
            for (int bx = 0; bx < w; bx += 4) {
                RayLanes packet;
                Ray block[RayLanes::kWidth];
                for (int l = 0; l < RayLanes::kWidth; ++l) {
                    Ray r = rays[size_t(by + l / 4) * size_t(w) + size_t(bx + l % 4)];
                    // Some lanes straight at the unit cube's edges and corners, and some
                    // with a direction component at or near zero.
                    if (l == 5) r.d = normalize(Vec3f{1.f, 1.f, 0.f} - r.o);
                    if (l == 6) r.d = normalize(Vec3f{-1.f, 1.f, 1.f} - r.o);
                    if (l == 9) r.d = normalize(Vec3f{r.d.x, 1e-30f, r.d.z});
                    if (l == 10) r.d = normalize(Vec3f{1e-12f, r.d.y, r.d.z});
                    block[l] = r;
                    packet.set(l, r);
                    packet.active[l] = 1;
                }
                EmptyOptionals<Hit, RayLanes::kWidth> got;
                Ray back[RayLanes::kWidth];
                acc->intersectLanes(packet, std::span<std::optional<Hit>>(got.data(), RayLanes::kWidth), back);
                // The odd lanes' rays again in other lanes, the even ones replaced by rays
                // of the view's far corner and one lane idle (as the blocks at a tile's edge
                // have): each ray's answer is its own, bit for bit, whatever shares its
                // packet (films do not depend on the tile size).
                RayLanes moved;
                for (int l = 0; l < RayLanes::kWidth; ++l) {
                    moved.set((l + 5) % RayLanes::kWidth, block[l]);
                    moved.active[(l + 5) % RayLanes::kWidth] = l != 2;
                    if (l % 2 == 1) {
                        const int fx = w - 1 - (bx + l % 4), fy = h - 1 - (by + l / 4);
                        moved.set((l + 4) % RayLanes::kWidth, rays[size_t(fy) * size_t(w) + size_t(fx)]);
                    }
                }
                EmptyOptionals<Hit, RayLanes::kWidth> again;
                acc->intersectLanes(moved, std::span<std::optional<Hit>>(again.data(), RayLanes::kWidth), back);
                for (int l = 0; l < RayLanes::kWidth; ++l) {
                    if (l % 2 == 0) continue;  // replaced (lane 2, left idle, among them)
                    const std::optional<Hit>& a = again[size_t((l + 5) % RayLanes::kWidth)];
                    ASSERT_EQ(a.has_value(), got[l].has_value()) << acc->name() << " lane " << l;
                    if (!a) continue;
                    EXPECT_EQ(a->ref, got[l]->ref) << acc->name() << " lane " << l;
                    EXPECT_EQ(a->t, got[l]->t) << acc->name() << " lane " << l;
                }
                for (int l = 0; l < RayLanes::kWidth; ++l) {
                    const std::optional<Hit> want = acc->intersect(block[l]);
                    ++lanes;
                    ASSERT_EQ(got[l].has_value(), want.has_value())
                        << acc->name() << " eye " << v.eye.x << "," << v.eye.y << "," << v.eye.z << " lane " << l;
                    if (!want) continue;
                    ++hits;
                    EXPECT_EQ(got[l]->ref, want->ref) << acc->name() << " lane " << l;
                    // The coherent traversal's quad test rounds differently: a few ulps.
                    EXPECT_NEAR(got[l]->t, want->t, 4e-7f * want->t) << acc->name() << " lane " << l;
                    bitExact += got[l]->t == want->t;
                }
            }
    }
    // Most rays meet something: the comparison is about hits, not empty space.
    EXPECT_GT(hits, lanes / 2);
    EXPECT_GT(bitExact, hits * 9 / 10);
}

}  // namespace
}  // namespace penumbra
