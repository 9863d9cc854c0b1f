// OBJ/MTL loading: triangulation, de-indexing, placement, the MTL mapping of
// docs/mtl-mapping.md, every validation rule and its warning, restricted
// paths, loadScene dispatch, frameBounds, the default Cornell scene, and the
// third-party scenes in ../shared (skipped when absent).
#include <gtest/gtest.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/scene.h"
#include "core/io/scene_loader.h"
#include "core/transform.h"
#include "support/test_support.h"

namespace penumbra {
namespace {
namespace fs = std::filesystem;
using test::tempDir;
using test::writeFile;

// Collects what the loader logs.
struct LogCapture {
    std::vector<std::pair<LogLevel, std::string>> lines;
    Logger logger{[this](LogLevel level, std::string_view msg) { lines.emplace_back(level, std::string(msg)); },
                  LogLevel::Debug};

    LogCapture() = default;
    LogCapture(const LogCapture&) = delete;

    /// Warnings containing every one of `needles`.
    size_t warnings(std::initializer_list<std::string_view> needles = {}) const {
        size_t n = 0;
        for (const auto& [level, msg] : lines) {
            if (level != LogLevel::Warning) continue;
            bool all = true;
            for (auto s : needles) all = all && msg.find(s) != std::string::npos;
            n += all ? 1 : 0;
        }
        return n;
    }
    std::string all() const {
        std::string s;
        for (const auto& l : lines) s += l.second + "\n";
        return s;
    }
};

struct Loaded {
    Scene scene;
    ObjStats stats;
};

Loaded load(const fs::path& obj, LogCapture& log, const LoadOptions& options = {},
            const Transform& worldFromObject = Transform()) {
    Loaded l;
    l.stats = appendObj(l.scene, obj, worldFromObject, options, log.logger);
    return l;
}

float triangleArea(const TriangleMesh& m, size_t t) {
    Vec3f a, b, c;
    m.vertices(t, a, b, c);
    return 0.5f * length(cross(b - a, c - a));
}

Vec3f triangleNormal(const TriangleMesh& m, size_t t) {
    Vec3f a, b, c;
    m.vertices(t, a, b, c);
    return normalize(cross(b - a, c - a));
}

size_t countTriangles(const Scene& s) {
    size_t n = 0;
    for (const auto& m : s.meshes) n += m.triangleCount();
    return n;
}

float totalArea(const Scene& s) {
    float a = 0.f;
    for (const auto& m : s.meshes)
        for (size_t t = 0; t < m.triangleCount(); ++t) a += triangleArea(m, t);
    return a;
}

struct EmitterSummary {
    size_t triangles = 0;
    float area = 0.f;
    float maxNormalY = -2.f;  // the largest y of the emitters' geometric normals
};

EmitterSummary emitters(const Scene& s) {
    EmitterSummary e;
    for (const auto& m : s.meshes)
        for (size_t t = 0; t < m.triangleCount(); ++t)
            if (s.materials[m.materialOf(t)].isEmissive()) {
                ++e.triangles;
                e.area += triangleArea(m, t);
                e.maxNormalY = std::max(e.maxNormalY, triangleNormal(m, t).y);
            }
    return e;
}

const Material* findMaterial(const Scene& s, const std::string& name) {
    for (const auto& m : s.materials)
        if (m.name == name) return &m;
    return nullptr;
}

void expectRgb(const Rgb& c, float r, float g, float b, float eps = 1e-6f) {
    EXPECT_NEAR(c.r, r, eps);
    EXPECT_NEAR(c.g, g, eps);
    EXPECT_NEAR(c.b, b, eps);
}

const char* kUnitQuad =
    "v 0 0 0\n"
    "v 1 0 0\n"
    "v 1 1 0\n"
    "v 0 1 0\n";

// A tiny RGB PNG, so texture paths point at real files.
void writePng(const fs::path& path) {
    fs::create_directories(path.parent_path());
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(1, 1, 3, OIIO::TypeDesc::UINT8);
    ASSERT_TRUE(out->open(path.string(), spec));
    unsigned char px[3] = {200, 100, 50};
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px));
    out->close();
}

// ---------------------------------------------------------------- geometry

TEST(ObjLoader, QuadsAndNgonsAreTriangulated) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "poly.obj", std::string(kUnitQuad) +
                                                "f 1 2 3 4\n"
                                                "v 3 0 0\nv 4 0 0\nv 4.5 1 0\nv 3.5 2 0\nv 2.5 1 0\n"
                                                "f 5 6 7 8 9\n");
    LogCapture log;
    Loaded l = load(obj, log);
    EXPECT_EQ(l.stats.triangles, 2u + 3u);
    EXPECT_EQ(countTriangles(l.scene), 5u);
    EXPECT_EQ(l.stats.droppedFaces, 0u);
    // Area is preserved: 1 for the square, 2.5 for the pentagon.
    EXPECT_NEAR(totalArea(l.scene), 1.f + 2.5f, 1e-5f);
    for (const auto& m : l.scene.meshes)
        for (size_t t = 0; t < m.triangleCount(); ++t) EXPECT_NEAR(triangleNormal(m, t).z, 1.f, 1e-6f);
    EXPECT_EQ(log.warnings(), 0u) << log.all();
}

TEST(ObjLoader, ConcavePolygonsKeepTheirShape) {
    // An L-shaped hexagon (area 3) and a concave quad (a dart, area 0.5):
    // a fan from vertex 0 would cover area outside both.
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "concave.obj",
                         "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\n"
                         "f 2 3 4 5 6 1\n"
                         "v 10 0 0\nv 11 0.5 0\nv 12 0 0\nv 11 1 0\n"
                         "f 8 9 10 7\n");
    LogCapture log;
    Loaded l = load(obj, log);
    ASSERT_EQ(l.scene.meshes.size(), 1u);
    EXPECT_EQ(l.stats.triangles, 4u + 2u);
    EXPECT_NEAR(totalArea(l.scene), 3.f + 0.5f, 1e-5f);
    const auto& m = l.scene.meshes[0];
    for (size_t t = 0; t < m.triangleCount(); ++t) EXPECT_NEAR(triangleNormal(m, t).z, 1.f, 1e-6f) << t;
}

TEST(ObjLoader, VerticesAreSharedPerIndexTriple) {
    fs::path dir = tempDir();
    // Two triangles share an edge and its (v, vn) pairs; a third reuses v 1 with another normal.
    auto obj = writeFile(dir / "share.obj", std::string(kUnitQuad) +
                                                 "vn 0 0 1\nvn 0 0 -1\n"
                                                 "f 1//1 2//1 3//1\n"
                                                 "f 1//1 3//1 4//1\n"
                                                 "v 0 0 1\n"
                                                 "f 1//2 4//2 5//2\n");
    LogCapture log;
    Loaded l = load(obj, log);
    ASSERT_EQ(l.scene.meshes.size(), 1u);
    const auto& m = l.scene.meshes[0];
    EXPECT_EQ(m.triangleCount(), 3u);
    EXPECT_EQ(m.positions.size(), 4u + 3u);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    EXPECT_EQ(m.indices[0], m.indices[3]);  // vertex 1 with normal 1, shared
    EXPECT_EQ(m.indices[2], m.indices[4]);  // vertex 3 with normal 1, shared
    EXPECT_NE(m.indices[0], m.indices[6]);  // vertex 1 with normal 2: its own vertex
    EXPECT_EQ(m.normals[m.indices[6]].z, -1.f);
}

TEST(ObjLoader, MissingNormalsAreSmoothedAndMissingUvsLeftEmpty) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "plain.obj", std::string(kUnitQuad) + "f 1 2 3 4\n");
    LogCapture log;
    Loaded l = load(obj, log);
    ASSERT_EQ(l.scene.meshes.size(), 1u);
    // A flat quad's smooth normals are its face normal (core/mesh_normals.h).
    ASSERT_EQ(l.scene.meshes[0].normals.size(), 4u);
    for (const Vec3f& n : l.scene.meshes[0].normals) EXPECT_NEAR(dot(n, Vec3f{0, 0, 1}), 1.f, 1e-6f);
    EXPECT_TRUE(l.scene.meshes[0].uvs.empty());
    EXPECT_EQ(l.scene.meshes[0].positions.size(), 4u);
    // An angle of 0 keeps it faceted: no normals.
    LoadOptions faceted;
    faceted.smoothAngleDegrees = 0.f;
    Loaded f = load(obj, log, faceted);
    EXPECT_TRUE(f.scene.meshes[0].normals.empty());
}

TEST(ObjLoader, NormalsAndUvsAreKept) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "attrs.obj", std::string(kUnitQuad) +
                                                 "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 2\n"
                                                 "f 1/1/1 2/2/1 3/3/1 4/4/1\n");
    LogCapture log;
    Loaded l = load(obj, log);
    const auto& m = l.scene.meshes.at(0);
    ASSERT_EQ(m.uvs.size(), 4u);
    ASSERT_EQ(m.normals.size(), 4u);
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_FLOAT_EQ(m.uvs[i].x, m.positions[i].x);  // this quad's uv equals its xy
        EXPECT_FLOAT_EQ(m.uvs[i].y, m.positions[i].y);
        EXPECT_FLOAT_EQ(m.normals[i].z, 1.f);  // normalised
    }
}

TEST(ObjLoader, NegativeIndicesAreRelative) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "rel.obj", std::string(kUnitQuad) + "f -4 -3 -2 -1\n" + "v 5 5 5\nf -5 -4 -1\n");
    LogCapture log;
    Loaded l = load(obj, log);
    ASSERT_EQ(l.scene.meshes.size(), 1u);
    const auto& m = l.scene.meshes[0];
    EXPECT_EQ(m.triangleCount(), 3u);
    Vec3f a, b, c;
    m.vertices(2, a, b, c);
    EXPECT_EQ(a, Vec3f(0, 0, 0));
    EXPECT_EQ(b, Vec3f(1, 0, 0));
    EXPECT_EQ(c, Vec3f(5, 5, 5));
    EXPECT_EQ(l.stats.droppedFaces, 0u);
}

TEST(ObjLoader, ObjectsAndGroupsBecomeNamedMeshes) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "groups.obj", std::string(kUnitQuad) +
                                                  "o first\nf 1 2 3\n"
                                                  "g second part\nf 1 3 4\n"
                                                  "o third\nf 1 2 4\n");
    LogCapture log;
    Loaded l = load(obj, log);
    ASSERT_EQ(l.scene.meshes.size(), 3u);
    EXPECT_EQ(l.scene.meshes[0].name, "first");
    EXPECT_EQ(l.scene.meshes[1].name, "second part");
    EXPECT_EQ(l.scene.meshes[2].name, "third");
    // Faces outside any object are named after the file.
    auto anon = writeFile(dir / "anon.obj", std::string(kUnitQuad) + "f 1 2 3\n");
    Loaded a = load(anon, log);
    ASSERT_EQ(a.scene.meshes.size(), 1u);
    EXPECT_EQ(a.scene.meshes[0].name, "anon");
}

TEST(ObjLoader, PlacementTransformsPositionsAndNormals) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "placed.obj", std::string(kUnitQuad) + "vn 0 0 1\nf 1//1 2//1 3//1 4//1\n");
    LogCapture log;
    Transform t = Transform::translate({10, 0, 0}) * Transform::scale({2, 2, 2}) * Transform::rotate(90, {1, 0, 0});
    Loaded l = load(obj, log, {}, t);
    const auto& m = l.scene.meshes.at(0);
    // (1,1,0) -> rotate about x -> (1,0,1) -> scale -> (2,0,2) -> translate -> (12,0,2)
    Vec3f p2 = m.positions[m.indices[2]];
    EXPECT_NEAR(p2.x, 12.f, 1e-5f);
    EXPECT_NEAR(p2.y, 0.f, 1e-5f);
    EXPECT_NEAR(p2.z, 2.f, 1e-5f);
    Vec3f n = m.normals[m.indices[0]];
    EXPECT_NEAR(n.x, 0.f, 1e-6f);
    EXPECT_NEAR(n.y, -1.f, 1e-6f);
    EXPECT_NEAR(n.z, 0.f, 1e-6f);
    EXPECT_NEAR(triangleNormal(m, 0).y, -1.f, 1e-6f);  // winding agrees with the normal
    EXPECT_NEAR(totalArea(l.scene), 4.f, 1e-4f);
}

TEST(ObjLoader, MirroringPlacementKeepsTheFrontSide) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "mirror.obj", std::string(kUnitQuad) + "vn 0 0 1\nf 1//1 2//1 3//1\n");
    LogCapture log;
    Loaded l = load(obj, log, {}, Transform::scale({1, 1, -1}));
    const auto& m = l.scene.meshes.at(0);
    EXPECT_NEAR(m.normals[0].z, -1.f, 1e-6f);
    EXPECT_NEAR(triangleNormal(m, 0).z, -1.f, 1e-6f);
}

TEST(ObjLoader, DegenerateFacesAreSkipped) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "degenerate.obj", std::string(kUnitQuad) +
                                                      "v 2 0 0\n"
                                                      "f 1 2 5\n"   // collinear
                                                      "f 1 1 2\n"   // repeated vertex
                                                      "f 1 2 3\n");  // fine
    LogCapture log;
    Loaded l = load(obj, log);
    EXPECT_EQ(l.stats.triangles, 1u);
    EXPECT_EQ(l.stats.droppedFaces, 2u);
    EXPECT_EQ(log.warnings(), 0u) << log.all();  // an info, not a warning (strict mode accepts it)
}

TEST(ObjLoader, FacesWithFewerThanThreeVerticesAreDropped) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "short.obj", std::string(kUnitQuad) + "f 1\nf 1 2\nf 1 2 3\n");
    LogCapture log;
    Loaded l = load(obj, log);
    EXPECT_EQ(l.stats.triangles, 1u);
    EXPECT_EQ(l.stats.droppedFaces, 2u);
    EXPECT_EQ(log.warnings({"short.obj", "dropped 2 face(s)", "line 5"}), 1u) << log.all();
}

TEST(ObjLoader, TrailingCommentsOnFaceLinesAreIgnored) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "comment.obj", std::string(kUnitQuad) + "f 1 2 3 4 # a quad\n");
    LogCapture log;
    Loaded l = load(obj, log);
    EXPECT_EQ(l.stats.triangles, 2u);
    EXPECT_EQ(l.stats.droppedFaces, 0u);
}

// ---------------------------------------------------------------- validation

TEST(ObjLoader, OutOfRangeIndicesAreDroppedWithOneCountedWarning) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "bad.obj", std::string(kUnitQuad) +
                                               "f 1 2 3\n"     // line 5: fine
                                               "f 1 2 99\n"    // line 6: positive out of range
                                               "f -10 1 2\n"   // negative before the first vertex
                                               "f 0 1 2\n"     // zero (OBJ is 1-based)
                                               "f 1 2 3 9\n"   // a quad with one bad corner
                                               "f 2 3 4\n");   // fine
    LogCapture log;
    Loaded l = load(obj, log);
    EXPECT_EQ(l.stats.triangles, 2u);
    EXPECT_EQ(l.stats.droppedFaces, 4u);
    EXPECT_EQ(log.warnings({"bad.obj", "dropped 4 face(s)", "invalid vertex indices", "line 6"}), 1u) << log.all();
    EXPECT_EQ(log.warnings(), 1u) << log.all();

    LoadOptions strict;
    strict.strict = true;
    try {
        load(obj, log, strict);
        FAIL() << "strict mode accepted bad indices";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::ParseError);
        EXPECT_NE(std::string(e.what()).find("bad.obj"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("line 6"), std::string::npos) << e.what();
    }
}

TEST(ObjLoader, NonFiniteCoordinatesAreDropped) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "nan.obj", std::string(kUnitQuad) +
                                               "v nan 0 0\n"      // 5
                                               "v 0 inf 0\n"      // 6
                                               "v 0 0 1e39\n"     // 7: overflows float
                                               "v 1.#IND 0 0\n"   // 8: MSVC's NaN
                                               "v -1.#INF 0 0\n"  // 9: MSVC's infinity
                                               "f 1 2 5\nf 1 2 6\nf 1 2 7\nf 1 2 8\nf 9 1 2\n"
                                               "f 1 2 3\n");
    LogCapture log;
    Loaded l = load(obj, log);
    EXPECT_EQ(l.stats.triangles, 1u);
    EXPECT_EQ(l.stats.droppedFaces, 5u);
    EXPECT_EQ(log.warnings({"nan.obj", "dropped 5 face(s)", "non-finite"}), 1u) << log.all();
    for (const auto& m : l.scene.meshes)
        for (const auto& p : m.positions) EXPECT_TRUE(isFinite(p));
}

TEST(ObjLoader, BadNormalAndUvIndicesFallBack) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "attrs.obj", std::string(kUnitQuad) +
                                                 "vt 0 0\nvn 0 0 1\n"
                                                 "f 1/1/1 2/1/1 3/1/1\n"     // fine
                                                 "f 1/1/7 3/1/7 4/1/7\n"     // bad normal index
                                                 "f 1/5/1 2/5/1 4/5/1\n"     // bad uv index
                                                 "f 2/-3/-4 3/1/1 4/1/1\n");  // both bad (relative before the first)
    LogCapture log;
    Loaded l = load(obj, log);
    EXPECT_EQ(l.stats.triangles, 4u);
    EXPECT_EQ(l.stats.droppedFaces, 0u);
    EXPECT_EQ(log.warnings({"attrs.obj", "2 face(s) with invalid normal indices", "geometric normal"}), 1u)
        << log.all();
    EXPECT_EQ(log.warnings({"attrs.obj", "2 face(s) with invalid texture coordinate indices"}), 1u) << log.all();
    const auto& m = l.scene.meshes.at(0);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    ASSERT_EQ(m.uvs.size(), m.positions.size());
    // Triangle 1 (bad normals): zero normals, so Scene::completeHit uses the geometric normal.
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.normals[m.indices[3 + k]], Vec3f());
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.normals[m.indices[k]], Vec3f(0, 0, 1));

    // The completed hit on the bad-normal triangle uses its geometric normal.
    Scene scene = l.scene;
    LogCapture flog;
    scene.finalize(flog.logger);
    Hit h = scene.completeHit(Ray{{0.2f, 0.7f, 1.f}, {0, 0, -1}}, PrimRef{ShapeKind::Mesh, 0, 1}, 1.f, 0.3f, 0.3f);
    EXPECT_NEAR(h.ns.z, 1.f, 1e-6f);
}

TEST(ObjLoader, CrlfBomTabsAndBackslashTexturePaths) {
    fs::path dir = tempDir();
    writePng(dir / "tex" / "wood.png");
    writeFile(dir / "crlf.mtl",
              "\xEF\xBB\xBF"
              "newmtl\twood\r\n"
              "Kd\t0.5 0.25\t0.125\r\n"
              "map_Kd tex\\wood.png\r\n");
    auto obj = writeFile(dir / "crlf.obj",
                         "\xEF\xBB\xBF"
                         "mtllib crlf.mtl\r\n"
                         "v\t0 0 0\r\nv 1\t0 0\r\nv 1 1 0\r\nv 0 1 0\r\n"
                         "vt 0 0\r\n"
                         "o\tboard\r\n"
                         "usemtl wood\r\n"
                         "f\t1/1 2/1\t3/1 4/1\r\n");
    LogCapture log;
    Loaded l = load(obj, log);
    EXPECT_EQ(log.warnings(), 0u) << log.all();
    EXPECT_EQ(l.stats.triangles, 2u);
    ASSERT_EQ(l.scene.meshes.size(), 1u);
    EXPECT_EQ(l.scene.meshes[0].name, "board");
    const Material* wood = findMaterial(l.scene, "wood");
    ASSERT_NE(wood, nullptr);
    expectRgb(wood->kd, 0.5f, 0.25f, 0.125f);
    EXPECT_EQ(l.scene.meshes[0].material, static_cast<uint32_t>(wood - l.scene.materials.data()));
    ASSERT_EQ(l.scene.textures.size(), 1u);
    EXPECT_EQ(wood->textureIndex, 0);
    EXPECT_TRUE(fs::equivalent(l.scene.textures[0].name, dir / "tex" / "wood.png"));
}

TEST(ObjLoader, LoneCarriageReturnLineEndings) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "mac.obj", "v 0 0 0\rv 1 0 0\rv 1 1 0\rf 1 2 3\r");
    LogCapture log;
    EXPECT_EQ(load(obj, log).stats.triangles, 1u);
}

// ---------------------------------------------------------------- materials

TEST(ObjMaterials, PhongValuesAreMapped) {
    fs::path dir = tempDir();
    writeFile(dir / "m.mtl",
              "newmtl plastic\nKa 0.1 0.2 0.3\nKd 0.4 0.5 0.6\nKs 0.2 0.2 0.2\nNs 32\nillum 2\n"
              "newmtl lamp\nKd 0.5 0.5 0.5\nKe 4 3 2\n");
    auto obj = writeFile(dir / "m.obj", "mtllib m.mtl\n" + std::string(kUnitQuad) +
                                             "usemtl plastic\nf 1 2 3\nusemtl lamp\nf 1 3 4\n");
    LogCapture log;
    Scene scene;
    scene.materials.resize(2);  // the OBJ's materials go after the scene's own
    ObjStats stats = appendObj(scene, obj, Transform(), {}, log.logger);
    EXPECT_EQ(stats.materials, 2u);
    ASSERT_EQ(scene.materials.size(), 4u);
    const Material& p = scene.materials[2];
    EXPECT_EQ(p.name, "plastic");
    expectRgb(p.ka, 0.1f, 0.2f, 0.3f);
    expectRgb(p.kd, 0.4f, 0.5f, 0.6f);
    expectRgb(p.ks, 0.2f, 0.2f, 0.2f);
    EXPECT_FLOAT_EQ(p.exponent, 32.f);
    expectRgb(p.kr, 0, 0, 0);
    expectRgb(p.ke, 0, 0, 0);
    EXPECT_EQ(p.model, PhongModel::Normalized);
    EXPECT_EQ(p.textureIndex, -1);
    const Material& lamp = scene.materials[3];
    expectRgb(lamp.ke, 4, 3, 2);
    EXPECT_TRUE(lamp.isEmissive());
    // One mesh with per-face materials.
    ASSERT_EQ(scene.meshes.size(), 1u);
    ASSERT_EQ(scene.meshes[0].faceMaterials.size(), 2u);
    EXPECT_EQ(scene.meshes[0].faceMaterials[0], 2u);
    EXPECT_EQ(scene.meshes[0].faceMaterials[1], 3u);
    EXPECT_EQ(stats.emissiveTriangles, 1u);
    EXPECT_EQ(log.warnings(), 0u) << log.all();
}

TEST(ObjMaterials, MirrorIllumModels) {
    fs::path dir = tempDir();
    writeFile(dir / "mir.mtl",
              "newmtl m3\nKd 0.1 0.1 0.1\nKs 0.9 0.8 0.7\nNs 100\nillum 3\n"
              "newmtl m5\nKs 0.95 0.95 0.95\nillum 5\n"
              "newmtl m7\nKs 0.3 0.3 0.3\nNi 1.5\nillum 7\n"
              "newmtl m4\nKs 0.5 0.5 0.5\nillum 4\n"
              "newmtl m1\nKd 0.5 0.5 0.5\nKs 0.1 0.1 0.1\nillum 1\n");
    auto obj = writeFile(dir / "mir.obj", "mtllib mir.mtl\n" + std::string(kUnitQuad) + "usemtl m3\nf 1 2 3\n");
    LogCapture log;
    Loaded l = load(obj, log);
    const Material* m3 = findMaterial(l.scene, "m3");
    ASSERT_NE(m3, nullptr);
    expectRgb(m3->kr, 0.9f, 0.8f, 0.7f);
    expectRgb(m3->ks, 0, 0, 0);
    expectRgb(m3->kd, 0.1f, 0.1f, 0.1f);
    EXPECT_TRUE(m3->isMirror());
    const Material* m5 = findMaterial(l.scene, "m5");
    expectRgb(m5->kr, 0.95f, 0.95f, 0.95f);
    expectRgb(m5->ks, 0, 0, 0);
    const Material* m7 = findMaterial(l.scene, "m7");
    expectRgb(m7->kr, 0.3f, 0.3f, 0.3f);
    const Material* m1 = findMaterial(l.scene, "m1");
    expectRgb(m1->kr, 0, 0, 0);
    expectRgb(m1->ks, 0.1f, 0.1f, 0.1f);  // illum 0-2: lit Phong with the given Ks
    // Glass illum models without Tf cannot transmit: one warning for the file, naming 4 and 7 but not 5.
    EXPECT_EQ(log.warnings({"mir.obj", "glass without a transmission colour", "m7", "m4"}), 1u) << log.all();
    EXPECT_EQ(log.warnings({"m5"}), 0u) << log.all();
    EXPECT_EQ(log.warnings(), 1u) << log.all();
}

TEST(ObjMaterials, GlassIllumModelsWithTfBecomeDielectrics) {
    fs::path dir = tempDir();
    writeFile(dir / "glass.mtl",
              "newmtl g7\nKd 0.01 0.01 0.01\nKs 0.3 0.3 0.3\nTf 0.9 0.8 0.7\nNi 1.33\nNs 200\nillum 7\n"
              "newmtl g4\nTf 1 1 1\nNi 2.5\nillum 4\n"
              "newmtl g6\nKt 0.5 0.5 0.5\nillum 6\n"
              "newmtl g9\nKs 0.5 0.5 0.5\nTf 1 1 1\nNi 1.5\nillum 9\n");
    auto obj = writeFile(dir / "glass.obj", "mtllib glass.mtl\n" + std::string(kUnitQuad) + "usemtl g7\nf 1 2 3\n");
    LogCapture log;
    Loaded l = load(obj, log);
    const Material* g7 = findMaterial(l.scene, "g7");
    ASSERT_NE(g7, nullptr);
    EXPECT_TRUE(g7->isDielectric());
    expectRgb(g7->kt, 0.9f, 0.8f, 0.7f);
    EXPECT_FLOAT_EQ(g7->ior, 1.33f);
    expectRgb(g7->kr, 0, 0, 0);  // Fresnel decides the reflection
    expectRgb(g7->ks, 0, 0, 0);
    expectRgb(g7->kd, 0.01f, 0.01f, 0.01f);
    EXPECT_FLOAT_EQ(findMaterial(l.scene, "g4")->ior, 2.5f);
    EXPECT_TRUE(findMaterial(l.scene, "g4")->isDielectric());
    EXPECT_TRUE(findMaterial(l.scene, "g6")->isDielectric());  // Kt is Tf's other name
    EXPECT_FLOAT_EQ(findMaterial(l.scene, "g6")->ior, 1.f);    // no Ni: tinyobjloader's 1
    // illum 9 (glass without ray-traced refraction) stays a mirror, with the warning.
    EXPECT_FALSE(findMaterial(l.scene, "g9")->isDielectric());
    EXPECT_TRUE(findMaterial(l.scene, "g9")->isMirror());
    EXPECT_EQ(log.warnings({"glass.obj", "transparency/refraction", "g9"}), 1u) << log.all();
    EXPECT_EQ(log.warnings(), 1u) << log.all();
}

TEST(ObjMaterials, MissingMtlFileGivesDefaultMaterial) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "nomtl.obj", "mtllib nowhere.mtl\n" + std::string(kUnitQuad) + "usemtl red\nf 1 2 3\n");
    LogCapture log;
    Loaded l = load(obj, log);
    EXPECT_EQ(l.stats.triangles, 1u);
    EXPECT_GE(log.warnings({"nomtl.obj", "nowhere.mtl"}), 1u) << log.all();
    ASSERT_EQ(l.scene.materials.size(), 1u);
    EXPECT_EQ(l.scene.materials[0].name, "default");
    expectRgb(l.scene.materials[0].kd, 0.8f, 0.8f, 0.8f);
    EXPECT_EQ(l.scene.meshes.at(0).material, 0u);
}

TEST(ObjMaterials, UnknownMaterialNameGivesDefaultMaterial) {
    fs::path dir = tempDir();
    writeFile(dir / "one.mtl", "newmtl known\nKd 0.2 0.2 0.2\n");
    auto obj = writeFile(dir / "unknown.obj", "mtllib one.mtl\n" + std::string(kUnitQuad) +
                                                   "usemtl missing\nf 1 2 3\nusemtl known\nf 1 3 4\n");
    LogCapture log;
    Loaded l = load(obj, log);
    EXPECT_EQ(log.warnings({"unknown.obj", "missing"}), 1u) << log.all();
    const auto& m = l.scene.meshes.at(0);
    ASSERT_EQ(m.faceMaterials.size(), 2u);
    EXPECT_EQ(l.scene.materials[m.faceMaterials[0]].name, "default");
    expectRgb(l.scene.materials[m.faceMaterials[0]].kd, 0.8f, 0.8f, 0.8f);
    EXPECT_EQ(l.scene.materials[m.faceMaterials[1]].name, "known");
}

TEST(ObjMaterials, FacesWithoutUsemtlGetTheDefault) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "nomat.obj", std::string(kUnitQuad) + "f 1 2 3\n");
    LogCapture log;
    Loaded l = load(obj, log);
    ASSERT_EQ(l.scene.materials.size(), 1u);
    EXPECT_EQ(l.stats.materials, 1u);
    expectRgb(l.scene.materials[0].kd, 0.8f, 0.8f, 0.8f);
    EXPECT_EQ(log.warnings(), 0u) << log.all();
}

TEST(ObjMaterials, LargeKaWarnsAndDoesNotEmit) {
    fs::path dir = tempDir();
    writeFile(dir / "ka.mtl", "newmtl light\nKa 20 20 20\nKd 1 1 1\n");
    auto obj = writeFile(dir / "ka.obj", "mtllib ka.mtl\n" + std::string(kUnitQuad) + "usemtl light\nf 1 2 3\n");
    LogCapture log;
    Loaded l = load(obj, log);
    EXPECT_EQ(log.warnings({"ka.mtl", "light", "Ka 20 20 20", "Ke"}), 1u) << log.all();
    EXPECT_EQ(l.stats.emissiveTriangles, 0u);
    expectRgb(findMaterial(l.scene, "light")->ke, 0, 0, 0);
    expectRgb(findMaterial(l.scene, "light")->ka, 20, 20, 20);
}

TEST(ObjMaterials, UnknownKeysWarnOncePerKeyPerFile) {
    fs::path dir = tempDir();
    writeFile(dir / "keys.mtl",
              "newmtl a\nKd 1 1 1\nfrobnicate 3\nsparkle 1\n"
              "newmtl b\nKd 1 1 1\nfrobnicate 4\n");
    auto obj = writeFile(dir / "keys.obj", "mtllib keys.mtl\n" + std::string(kUnitQuad) + "usemtl a\nf 1 2 3\n");
    LogCapture log;
    load(obj, log);
    EXPECT_EQ(log.warnings({"keys.mtl", "frobnicate"}), 1u) << log.all();
    EXPECT_EQ(log.warnings({"keys.mtl", "sparkle"}), 1u) << log.all();
    EXPECT_EQ(log.warnings(), 2u) << log.all();
}

TEST(ObjMaterials, MaterialNamesAreTrimmed) {
    // McGuire's CornellBox-Mirror.mtl says "newmtl tallBox " (trailing space).
    fs::path dir = tempDir();
    writeFile(dir / "trim.mtl", "newmtl tallBox \nKs 0.5 0.5 0.5\nillum 3\n");
    auto obj = writeFile(dir / "trim.obj", "mtllib trim.mtl\n" + std::string(kUnitQuad) + "usemtl tallBox\nf 1 2 3\n");
    LogCapture log;
    Loaded l = load(obj, log);
    EXPECT_EQ(log.warnings(), 0u) << log.all();
    EXPECT_TRUE(l.scene.materials[l.scene.meshes.at(0).material].isMirror());
}

TEST(ObjMaterials, TexturesResolveAndAreShared) {
    fs::path dir = tempDir();
    writePng(dir / "maps" / "Brick.png");
    writeFile(dir / "tex.mtl",
              "newmtl a\nKd 1 1 1\nmap_Kd maps/Brick.png\n"
              "newmtl b\nKd 1 1 1\nmap_Kd -s 2 2 1 MAPS/brick.PNG\n"  // options; other capitalisation
              "newmtl c\nKd 0.3 0.2 0.1\nmap_Kd maps/absent.png\n");
    auto obj = writeFile(dir / "tex.obj", "mtllib tex.mtl\n" + std::string(kUnitQuad) + "usemtl a\nf 1 2 3\n");
    LogCapture log;
    Loaded l = load(obj, log);
    ASSERT_EQ(l.scene.textures.size(), 1u);
    EXPECT_TRUE(fs::equivalent(l.scene.textures[0].name, dir / "maps" / "Brick.png"));
    EXPECT_EQ(findMaterial(l.scene, "a")->textureIndex, 0);
    EXPECT_EQ(findMaterial(l.scene, "b")->textureIndex, 0);
    const Material* c = findMaterial(l.scene, "c");
    EXPECT_EQ(c->textureIndex, -1);
    expectRgb(c->kd, 0.3f, 0.2f, 0.1f);
    EXPECT_EQ(log.warnings({"tex.mtl", "absent.png", "not found"}), 1u) << log.all();
    EXPECT_EQ(log.warnings(), 1u) << log.all();
}

// ---------------------------------------------------------------- errors and paths

TEST(ObjLoader, MissingFileAndDirectoryErrorsNameTheFile) {
    fs::path dir = tempDir();
    LogCapture log;
    try {
        load(dir / "absent.obj", log);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::FileNotFound);
        EXPECT_NE(std::string(e.what()).find("absent.obj"), std::string::npos) << e.what();
    }
    fs::create_directories(dir / "folder.obj");
    try {
        load(dir / "folder.obj", log);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::IoError);
        EXPECT_NE(std::string(e.what()).find("folder.obj"), std::string::npos) << e.what();
    }
}

TEST(ObjLoader, UnreadableFileIsAnIoError) {
    if (::geteuid() == 0) GTEST_SKIP() << "root reads everything";
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "locked.obj", std::string(kUnitQuad) + "f 1 2 3\n");
    fs::permissions(obj, fs::perms::none);
    LogCapture log;
    try {
        load(obj, log);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::IoError);
        EXPECT_NE(std::string(e.what()).find("locked.obj"), std::string::npos) << e.what();
    }
    fs::permissions(obj, fs::perms::owner_all);
}

TEST(ObjLoader, NoFacesIsAnInvalidSceneOnlyForLoadObjScene) {
    fs::path dir = tempDir();
    auto obj = writeFile(dir / "empty.obj", std::string(kUnitQuad) + "l 1 2\np 3\n");
    LogCapture log;
    Loaded l = load(obj, log);
    EXPECT_EQ(l.stats.triangles, 0u);
    EXPECT_TRUE(l.scene.meshes.empty());
    try {
        loadObjScene(obj, {}, log.logger);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidScene);
        EXPECT_EQ(std::string(e.what()), obj.string() + ": no faces to render");
    }
}

TEST(ObjLoader, RestrictedModeRefusesPathsOutsideTheRoots) {
    fs::path root = tempDir();
    fs::path inside = root / "scenes";
    writeFile(root / "secret.mtl", "newmtl s\nKd 1 0 0\n");
    writePng(root / "secret.png");
    writeFile(inside / "ok.mtl", "newmtl ok\nKd 0.5 0.5 0.5\n");
    LoadOptions restricted;
    restricted.allowedRoots = {inside};
    LogCapture log;

    auto good = writeFile(inside / "ok.obj", "mtllib ok.mtl\n" + std::string(kUnitQuad) + "usemtl ok\nf 1 2 3\n");
    EXPECT_EQ(load(good, log, restricted).stats.triangles, 1u);

    auto expectRefused = [&](const fs::path& obj, const std::string& needle) {
        try {
            load(obj, log, restricted);
            ADD_FAILURE() << obj << " was loaded";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("outside the allowed directories"), std::string::npos) << e.what();
        }
    };
    expectRefused(writeFile(inside / "passwd.obj", "mtllib ../../../../../../../etc/passwd\n" + std::string(kUnitQuad) +
                                                       "f 1 2 3\n"),
                  "passwd");
    expectRefused(writeFile(inside / "up.obj", "mtllib ../secret.mtl\n" + std::string(kUnitQuad) + "f 1 2 3\n"),
                  "secret.mtl");
    writeFile(inside / "tex.mtl", "newmtl t\nmap_Kd ../secret.png\n");
    expectRefused(writeFile(inside / "tex.obj", "mtllib tex.mtl\n" + std::string(kUnitQuad) + "f 1 2 3\n"),
                  "secret.png");
    expectRefused(writeFile(root / "outside.obj", std::string(kUnitQuad) + "f 1 2 3\n"), "outside.obj");

    // Unrestricted, the same files load.
    EXPECT_EQ(load(inside / "up.obj", log).stats.triangles, 1u);
}

TEST(SceneLoader, CheckPathAllowedComparesWholeComponents) {
    fs::path root = tempDir();
    LoadOptions o;
    o.allowedRoots = {root / "data"};
    EXPECT_NO_THROW(checkPathAllowed(root / "data" / "a" / "b.obj", o));
    EXPECT_NO_THROW(checkPathAllowed(root / "data" / "x" / ".." / "b.obj", o));
    EXPECT_THROW(checkPathAllowed(root / "data2" / "b.obj", o), Error);
    EXPECT_THROW(checkPathAllowed(root / "data" / ".." / "b.obj", o), Error);
    // A symlink inside that points outside is outside.
    fs::create_directories(root / "data");
    fs::create_directories(root / "elsewhere");
    fs::create_directory_symlink(root / "elsewhere", root / "data" / "link");
    EXPECT_THROW(checkPathAllowed(root / "data" / "link" / "b.obj", o), Error);
    EXPECT_NO_THROW(checkPathAllowed(root / "anything", LoadOptions{}));
}

TEST(SceneLoader, DispatchesOnTheExtension) {
    fs::path dir = tempDir();
    LogCapture log;
    auto obj = writeFile(dir / "UPPER.OBJ", std::string(kUnitQuad) + "f 1 2 3\n");
    LoadedScene s = loadScene(obj, {}, log.logger);
    EXPECT_EQ(countTriangles(s.scene), 1u);
    EXPECT_FALSE(s.camera.has_value());
    EXPECT_EQ(s.sourcePath, obj);
    try {
        loadScene(dir / "model.xyz", {}, log.logger);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
        EXPECT_EQ(std::string(e.what()).rfind((dir / "model.xyz").string() +
                                                  ": unknown scene format '.xyz' (supported: .json, .obj, ",
                                              0),
                  0u)
            << e.what();
    }
    auto json = writeFile(dir / "s.JSON", "{}");
    EXPECT_NO_THROW(loadScene(json, {}, log.logger));
}

TEST(FrameBounds, SeesTheWholeBoxFromPlusZ) {
    Bounds3f b;
    b.extend({-1, 0, -2});
    b.extend({3, 2, 1});
    for (float aspect : {0.5f, 1.f, 2.f}) {
        CameraDesc c = frameBounds(b, 40.f, aspect);
        EXPECT_EQ(c.lookAt, b.center());
        EXPECT_EQ(c.up, Vec3f(0, 1, 0));
        EXPECT_FLOAT_EQ(c.vfovDegrees, 40.f);
        EXPECT_FLOAT_EQ(c.eye.x, b.center().x);
        EXPECT_FLOAT_EQ(c.eye.y, b.center().y);
        EXPECT_GT(c.eye.z, b.hi.z);
        // Every corner projects inside the image.
        float tanV = std::tan(20.f * kPi / 180.f), tanH = tanV * aspect;
        for (int i = 0; i < 8; ++i) {
            Vec3f p{i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z};
            Vec3f d = p - c.eye;
            EXPECT_LT(std::fabs(d.x) / -d.z, tanH) << aspect << " corner " << i;
            EXPECT_LT(std::fabs(d.y) / -d.z, tanV) << aspect << " corner " << i;
        }
        validateCamera(c);
    }
    CameraDesc def = frameBounds(Bounds3f{}, 30.f, 1.f);
    EXPECT_EQ(Vec3f(def.eye), CameraDesc{}.eye);
    EXPECT_FLOAT_EQ(def.vfovDegrees, 30.f);
}

// ---------------------------------------------------------------- the default scene

TEST(DefaultScene, CornellBoxGeometryLightAndMirror) {
    fs::path obj = test::assetPath("cornell/cornell.obj");
    LogCapture log;
    LoadedScene s = loadObjScene(obj, {}, log.logger);
    EXPECT_EQ(log.warnings(), 0u) << log.all();
    EXPECT_EQ(countTriangles(s.scene), 2u * (5 + 5 + 5 + 1));

    EmitterSummary e = emitters(s.scene);
    EXPECT_EQ(e.triangles, 2u);
    EXPECT_NEAR(e.area, 130.f * 105.f, 1e-2f);
    EXPECT_NEAR(e.maxNormalY, -1.f, 1e-6f);  // both light triangles face down

    Bounds3f b = s.scene.bounds();
    EXPECT_EQ(b.lo, Vec3f(0, 0, 0));
    EXPECT_NEAR(b.hi.x, 556.f, 1e-3f);
    EXPECT_NEAR(b.hi.y, 548.8f, 1e-3f);
    EXPECT_NEAR(b.hi.z, 559.2f, 1e-3f);

    const Vec3f roomCentre{278.f, 274.4f, 279.6f};
    for (const auto& m : s.scene.meshes) {
        Vec3f centre{};
        for (const auto& p : m.positions) centre += p;
        centre = centre / static_cast<float>(m.positions.size());
        for (size_t t = 0; t < m.triangleCount(); ++t) {
            Vec3f a, bb, c;
            m.vertices(t, a, bb, c);
            Vec3f mid = (a + bb + c) / 3.f;
            Vec3f n = triangleNormal(m, t);
            if (m.name == "short_box" || m.name == "tall_box")
                EXPECT_GT(dot(n, mid - centre), 0.f) << m.name << " faces outwards";
            else
                EXPECT_GT(dot(n, roomCentre - mid), 0.f) << m.name << " faces into the room";
        }
    }
    const Material* mirror = nullptr;
    for (const auto& m : s.scene.meshes)
        if (m.name == "tall_box") mirror = &s.scene.materials[m.material];
    ASSERT_NE(mirror, nullptr);
    expectRgb(mirror->kr, 0.9f, 0.9f, 0.9f);
    expectRgb(mirror->ks, 0, 0, 0);
    const Material* red = nullptr;
    for (const auto& m : s.scene.meshes)
        if (m.name == "left_wall") red = &s.scene.materials[m.material];
    ASSERT_NE(red, nullptr);
    EXPECT_GT(red->kd.r, 5 * red->kd.g);
}

// ---------------------------------------------------------------- third-party scenes

TEST(SharedScenes, McGuireCornellOriginalHasOneDownwardLight) {
    fs::path obj = test::sharedScenePath("cornell_mcguire/CornellBox-Original.obj");
    if (obj.empty()) GTEST_SKIP() << "../shared/scenes not present";
    LogCapture log;
    LoadedScene s = loadObjScene(obj, {}, log.logger);
    EXPECT_EQ(log.warnings(), 0u) << log.all();
    EXPECT_EQ(countTriangles(s.scene), 36u);
    EmitterSummary e = emitters(s.scene);
    EXPECT_EQ(e.triangles, 2u);
    EXPECT_NEAR(e.area, 0.1786f, 5e-4f);
    EXPECT_LT(e.maxNormalY, 0.f);
}

TEST(SharedScenes, McGuireCornellMirrorHasAMirror) {
    fs::path obj = test::sharedScenePath("cornell_mcguire/CornellBox-Mirror.obj");
    if (obj.empty()) GTEST_SKIP() << "../shared/scenes not present";
    LogCapture log;
    LoadedScene s = loadObjScene(obj, {}, log.logger);
    EXPECT_EQ(log.warnings(), 0u) << log.all();
    size_t mirrorTris = 0;
    for (const auto& m : s.scene.meshes)
        for (size_t t = 0; t < m.triangleCount(); ++t)
            if (s.scene.materials[m.materialOf(t)].isMirror()) ++mirrorTris;
    EXPECT_EQ(mirrorTris, 12u);  // the tall box: 6 quads
    const Material* tall = findMaterial(s.scene, "tallBox");
    ASSERT_NE(tall, nullptr);
    expectRgb(tall->kr, 0.95f, 0.95f, 0.95f);
    expectRgb(tall->ks, 0, 0, 0);
    EXPECT_EQ(emitters(s.scene).triangles, 2u);
}

TEST(SharedScenes, McGuireSphereHasGlass) {
    fs::path obj = test::sharedScenePath("cornell_mcguire/CornellBox-Sphere.obj");
    if (obj.empty()) GTEST_SKIP() << "../shared/scenes not present";
    LogCapture log;
    LoadedScene s = loadObjScene(obj, {}, log.logger);
    EXPECT_EQ(log.warnings({"transparency/refraction"}), 0u) << log.all();
    EXPECT_TRUE(findMaterial(s.scene, "leftSphere")->isMirror());
    const Material* glass = findMaterial(s.scene, "rightSphere");
    EXPECT_TRUE(glass->isDielectric());
    EXPECT_FLOAT_EQ(glass->ior, 2.5f);
    expectRgb(glass->kt, 0.1f, 0.1f, 0.1f);
}

TEST(SharedScenes, McGuireGlossyHasNoEmitterAndWarnsAboutLight) {
    fs::path obj = test::sharedScenePath("cornell_mcguire/CornellBox-Glossy.obj");
    if (obj.empty()) GTEST_SKIP() << "../shared/scenes not present";
    LogCapture log;
    LoadedScene s = loadObjScene(obj, {}, log.logger);
    EXPECT_EQ(emitters(s.scene).triangles, 0u);
    EXPECT_EQ(log.warnings({"CornellBox-Glossy.obj", "light"}), 1u) << log.all();
}

TEST(SharedScenes, TinyObjCornellWarnsAboutKa) {
    fs::path obj = test::sharedScenePath("tinyobjloader_models/cornell_box.obj");
    if (obj.empty()) GTEST_SKIP() << "../shared/scenes not present";
    LogCapture log;
    LoadedScene s = loadObjScene(obj, {}, log.logger);
    EXPECT_EQ(countTriangles(s.scene), 36u);
    EXPECT_EQ(log.warnings({"cornell_box.mtl", "Ka 20 20 20", "Ke"}), 1u) << log.all();
    EXPECT_EQ(emitters(s.scene).triangles, 0u);
}

TEST(SharedScenes, TinyObjNanDropsItsNonFiniteFace) {
    fs::path obj = test::sharedScenePath("tinyobjloader_models/test-nan.obj");
    if (obj.empty()) GTEST_SKIP() << "../shared/scenes not present";
    LogCapture log;
    Scene scene;
    ObjStats st = appendObj(scene, obj, Transform(), {}, log.logger);
    EXPECT_EQ(st.droppedFaces, 1u);  // f 1 2 3 4 uses nan, inf, 1.#IND and 1.#INF
    EXPECT_EQ(st.triangles, 34u);    // the other 17 quads
    EXPECT_EQ(log.warnings({"test-nan.obj", "dropped 1 face(s)"}), 1u) << log.all();
    for (const auto& m : scene.meshes)
        for (const auto& p : m.positions) EXPECT_TRUE(isFinite(p));
}

TEST(SharedScenes, TinyObjMalformedFilesLoadOrFailCleanly) {
    if (test::sharedScenePath("tinyobjloader_models").empty()) GTEST_SKIP() << "../shared/scenes not present";
    struct Case {
        const char* file;
        size_t triangles, dropped;
    };
    const Case cases[] = {
        {"issue-140-zero-face-idx.obj", 1, 1},         // f 0/0/0 ...: dropped; the other face stays
        {"invalid-relative-vertex-index.obj", 0, 1},  // f -4 -3 -2 before any v
        {"invalid-face-definition.obj", 0, 2},        // f 1, f 1 2
        {"line-prim.obj", 0, 0},
        {"points-prim.obj", 0, 0},
        {"issue-356-leading-spaces-newmtl.obj", 0, 0},
        {"skin-weight.obj", 12, 0},
        {"cube-vertex-w-component.obj", 12, 0},
    };
    for (const auto& c : cases) {
        LogCapture log;
        Scene scene;
        fs::path obj = test::sharedScenePath(std::string("tinyobjloader_models/") + c.file);
        ObjStats st = appendObj(scene, obj, Transform(), {}, log.logger);
        EXPECT_EQ(st.triangles, c.triangles) << c.file << "\n" << log.all();
        EXPECT_EQ(st.droppedFaces, c.dropped) << c.file << "\n" << log.all();
    }
}

TEST(SharedScenes, TinyObjConcaveNgonsKeepTheirArea) {
    for (const char* f : {"issue-319-002.obj", "issue-319-003.obj"}) {
        fs::path obj = test::sharedScenePath(std::string("tinyobjloader_models/") + f);
        if (obj.empty()) GTEST_SKIP() << "../shared/scenes not present";
        LogCapture log;
        Scene scene;
        ObjStats st = appendObj(scene, obj, Transform(), {}, log.logger);
        EXPECT_GT(st.triangles, 0u);
        // Triangles of an ear-clipped simple polygon never overlap, so their summed
        // area equals the polygon's (Newell) area; a fan over a concave polygon exceeds it.
        double polyArea = 0.0;
        {
            // Each face's area from the file, with Newell's formula in doubles relative
            // to its first corner (the coordinates are large).
            std::ifstream in(obj);
            std::vector<std::array<double, 3>> v;
            std::string line;
            while (std::getline(in, line)) {
                std::istringstream ls(line);
                std::string kw;
                ls >> kw;
                if (kw == "v") {
                    std::array<double, 3> p{};
                    ls >> p[0] >> p[1] >> p[2];
                    v.push_back(p);
                } else if (kw == "f") {
                    std::vector<std::array<double, 3>> poly;
                    std::string tok;
                    while (ls >> tok) poly.push_back(v.at(std::stoul(tok) - 1));
                    double n[3] = {0, 0, 0};
                    for (size_t i = 1; i + 1 < poly.size(); ++i) {
                        double a[3], b[3];
                        for (int k = 0; k < 3; ++k) {
                            a[k] = poly[i][k] - poly[0][k];
                            b[k] = poly[i + 1][k] - poly[0][k];
                        }
                        n[0] += a[1] * b[2] - a[2] * b[1];
                        n[1] += a[2] * b[0] - a[0] * b[2];
                        n[2] += a[0] * b[1] - a[1] * b[0];
                    }
                    polyArea += 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                }
            }
        }
        EXPECT_NEAR(totalArea(scene), polyArea, 1e-3 * polyArea) << f;
    }
}

TEST(SharedScenes, SponzaTexturesResolveCaseInsensitively) {
    fs::path obj = test::sharedScenePath("sponza_dabrovic/sponza.obj");
    if (obj.empty()) GTEST_SKIP() << "../shared/scenes not present";
    LogCapture log;
    Scene scene;
    ObjStats st = appendObj(scene, obj, Transform(), {}, log.logger);
    EXPECT_EQ(st.triangles + st.droppedFaces, 66450u);
    // 12 distinct map_Kd names; 9 differ from the files' capitalisation, all resolve
    // (as do the bump maps, 11 more textures).
    std::set<int> diffuse;
    for (const auto& m : scene.materials)
        if (m.textureIndex >= 0) diffuse.insert(m.textureIndex);
    EXPECT_EQ(diffuse.size(), 12u);
    EXPECT_EQ(scene.textures.size(), 23u);
    for (const auto& t : scene.textures) EXPECT_TRUE(fs::is_regular_file(t.name)) << t.name;
    EXPECT_EQ(log.warnings({"not found"}), 0u) << log.all();
    size_t textured = 0;
    for (const auto& m : scene.materials) textured += m.textureIndex >= 0 ? 1 : 0;
    EXPECT_GE(textured, 12u);
    EXPECT_EQ(st.emissiveTriangles, 0u);
}

TEST(PathNotice, UnrestrictedLoadingReportsFilesOutsideTheNoticeRoots) {
    fs::path dir = test::tempDir();
    test::writeFile(dir / "shared" / "lib.mtl", "newmtl red\nKd 1 0 0\n");
    fs::path obj = test::writeFile(dir / "scene" / "a.obj", "mtllib ../shared/lib.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
    LogCapture log;
    LoadOptions options;
    std::vector<fs::path> reported;
    options.noticeRoots = {dir / "scene"};
    options.onReadOutside = [&](const fs::path& f) { reported.push_back(f); };
    LoadedScene s = loadObjScene(obj, options, log.logger);
    EXPECT_EQ(countTriangles(s.scene), 1u);  // still read: the CLI allows everything
    ASSERT_EQ(reported.size(), 1u);         // the MTL, once; not the OBJ inside the folder
    EXPECT_EQ(reported[0].filename(), "lib.mtl");
}

}  // namespace
}  // namespace penumbra
