// Model files (core/io/model_file.h): glTF (gltf_loader.h) materials, camera
// and lights, a referenced .bin read through the path policy, its malformed
// files; through Assimp (assimp_loader.h) STL and PLY (vertex colours); the
// --model and smoothing options, unknown and malformed files, and the
// Stanford bunny (skipped without ../shared). gltf_loader_test.cpp has the
// glTF material channels, textures, tangents and limits.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/io/scene_loader.h"
#include "support/test_support.h"

namespace penumbra {
namespace {
namespace fs = std::filesystem;

struct Quiet {
    std::vector<std::string> warnings;
    Logger logger{[this](LogLevel level, std::string_view msg) {
                      if (level == LogLevel::Warning) warnings.emplace_back(msg);
                  },
                  LogLevel::Debug};
};

/// The material of the mesh whose name contains `name`.
const Material& materialOf(const Scene& s, const std::string& name) {
    for (const TriangleMesh& m : s.meshes)
        if (m.name.find(name) != std::string::npos) return s.materials.at(m.material);
    throw std::runtime_error("no mesh named " + name);
}

std::string errorOf(const fs::path& file, const LoadOptions& options = {}) {
    Quiet q;
    try {
        loadScene(file, options, q.logger);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(ModelFile, GltfMaterialsCameraAndLight) {
    const fs::path dir = test::tempDir();
    const fs::path file = test::writeFile(dir / "quads.gltf", test::twoQuadsGltf());
    Quiet q;
    LoadedScene s = loadScene(file, {}, q.logger);
    EXPECT_TRUE(q.warnings.empty()) << q.warnings.front();
    EXPECT_EQ(s.scene.triangleCount(), 4u);

    const Material& glow = materialOf(s.scene, "lamp");
    EXPECT_TRUE(glow.isEmissive());
    EXPECT_FLOAT_EQ(glow.ke.r, 1.f);
    EXPECT_FLOAT_EQ(glow.ke.g, 0.5f);
    EXPECT_FLOAT_EQ(glow.ke.b, 0.25f);
    EXPECT_FLOAT_EQ(glow.kd.r, 0.f);

    // Shaded by the metal-roughness BSDF: kd holds the base colour (the albedo AOV's), no glossy term.
    const Material& clay = materialOf(s.scene, "card");
    EXPECT_FALSE(clay.isEmissive());
    EXPECT_TRUE(clay.shadedAsMetalRoughness());
    EXPECT_FLOAT_EQ(clay.baseColor.g, 0.4f);
    EXPECT_FLOAT_EQ(clay.roughness, 1.f);
    EXPECT_NEAR(clay.kd.r, 0.8f, 1e-6f);
    EXPECT_FLOAT_EQ(clay.ks.r, 0.f);
    EXPECT_EQ(clay.model, PhongModel::Normalized);

    ASSERT_EQ(s.scene.pointLights.size(), 1u);
    EXPECT_NEAR(s.scene.pointLights[0].position.x, 1.25f, 1e-6f);
    EXPECT_NEAR(s.scene.pointLights[0].position.z, 2.f, 1e-6f);
    EXPECT_NEAR(s.scene.pointLights[0].intensity.g, 4.f, 1e-5f);

    ASSERT_TRUE(s.camera.has_value());
    EXPECT_NEAR(s.camera->eye.z, 5.f, 1e-6f);
    EXPECT_NEAR(s.camera->lookAt.z, 4.f, 1e-6f);
    EXPECT_NEAR(s.camera->vfovDegrees, 0.8f * 180.f / kPi, 1e-3f);
}

TEST(ModelFile, ModelAndSmoothingOptions) {
    const fs::path dir = test::tempDir();
    const fs::path file = test::writeFile(dir / "quads.gltf", test::twoQuadsGltf());
    LoadOptions classic;
    classic.meshModel = PhongModel::Classic;
    Quiet q;
    LoadedScene s = loadScene(file, classic, q.logger);
    EXPECT_EQ(materialOf(s.scene, "card").model, PhongModel::Classic);
    // Flat quads: smoothing gives them their face normal; 0 leaves them without normals.
    for (const TriangleMesh& m : s.scene.meshes) {
        ASSERT_EQ(m.normals.size(), m.positions.size());
        for (const Vec3f& n : m.normals) EXPECT_NEAR(n.z, 1.f, 1e-6f);
    }
    LoadOptions faceted;
    faceted.smoothAngleDegrees = 0.f;
    LoadedScene f = loadScene(file, faceted, q.logger);
    for (const TriangleMesh& m : f.scene.meshes) EXPECT_TRUE(m.normals.empty());
}

TEST(ModelFile, ReferencedBufferIsReadThroughThePathPolicy) {
    const fs::path dir = test::tempDir();
    test::writeFile(dir / "scene" / "quads.bin", test::twoQuadsBuffer());
    const fs::path file = test::writeFile(dir / "scene" / "quads.gltf", test::twoQuadsGltf("quads.bin"));
    std::vector<fs::path> reads;
    LoadOptions watch;
    watch.noticeRoots = {fs::path("/nonexistent-root")};
    watch.onReadOutside = [&](const fs::path& p) { reads.push_back(p); };
    Quiet q;
    EXPECT_EQ(loadScene(file, watch, q.logger).scene.triangleCount(), 4u);
    ASSERT_EQ(reads.size(), 2u) << "the model and its buffer, each once";
    EXPECT_EQ(reads[1].filename(), "quads.bin");

    // A buffer outside the allowed folders is refused, and the error names it.
    test::writeFile(dir / "outside.bin", test::twoQuadsBuffer());
    test::writeFile(dir / "scene" / "escape.gltf", test::twoQuadsGltf("../outside.bin"));
    LoadOptions confined;
    confined.allowedRoots = {dir / "scene"};
    const std::string e = errorOf(dir / "scene" / "escape.gltf", confined);
    EXPECT_NE(e.find("escape.gltf"), std::string::npos) << e;
    EXPECT_NE(e.find("outside.bin"), std::string::npos) << e;
    EXPECT_NE(e.find("outside the allowed directories"), std::string::npos) << e;
    // A missing buffer names the model and the buffer.
    test::writeFile(dir / "scene" / "lost.gltf", test::twoQuadsGltf("lost.bin"));
    const std::string lost = errorOf(dir / "scene" / "lost.gltf");
    EXPECT_NE(lost.find("lost.gltf"), std::string::npos) << lost;
    EXPECT_NE(lost.find("lost.bin"), std::string::npos) << lost;
}

TEST(ModelFile, GltfBaseColourTexturesFromFilesAndBufferViewsAreUsed) {
    const fs::path dir = test::tempDir();
    {
        auto out = OIIO::ImageOutput::create((dir / "wood.png").string());
        ASSERT_TRUE(out);
        OIIO::ImageSpec spec(1, 1, 3, OIIO::TypeDesc::UINT8);
        ASSERT_TRUE(out->open((dir / "wood.png").string(), spec));
        unsigned char px[3] = {200, 100, 50};
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px));
        out->close();
    }
    std::string gltf = test::twoQuadsGltf();
    const std::string clay = R"("pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.4, 0.2, 1])";
    ASSERT_NE(gltf.find(clay), std::string::npos);
    gltf.replace(gltf.find(clay), clay.size(), clay + R"(, "baseColorTexture": {"index": 0})");
    gltf.replace(gltf.find(R"("buffers")"), 0, R"("images": [{"uri": "wood.png"}], "textures": [{"source": 0}], )");
    test::writeFile(dir / "textured.gltf", gltf);
    Quiet q;
    LoadedScene s = loadScene(dir / "textured.gltf", {}, q.logger);
    EXPECT_TRUE(q.warnings.empty()) << q.warnings.front();
    ASSERT_EQ(s.scene.textures.size(), 1u);
    EXPECT_EQ(fs::path(s.scene.textures[0].name).filename(), "wood.png");
    EXPECT_EQ(materialOf(s.scene, "card").textureIndex, 0);
    EXPECT_EQ(materialOf(s.scene, "lamp").textureIndex, -1);

    // An image inside the file (a buffer view) is kept as bytes, named after the file, for the
    // texture cache to decode (here a buffer of indices: the cache will warn that it is no image).
    gltf.replace(gltf.find(R"({"uri": "wood.png"})"), std::string(R"({"uri": "wood.png"})").size(),
                 R"({"bufferView": 1, "mimeType": "image/png"})");
    test::writeFile(dir / "embedded.gltf", gltf);
    Quiet e;
    LoadedScene embedded = loadScene(dir / "embedded.gltf", {}, e.logger);
    EXPECT_TRUE(e.warnings.empty()) << e.warnings.front();
    const Material& card = materialOf(embedded.scene, "card");
    ASSERT_GE(card.textureIndex, 0);
    const TextureSource& image = embedded.scene.textures[size_t(card.textureIndex)];
    EXPECT_EQ(image.name, (dir / "embedded.gltf").string() + "#image0.png");
    ASSERT_NE(image.bytes, nullptr);
    EXPECT_EQ(image.bytes->size(), 12u);
    EXPECT_NEAR(card.kd.r, 0.8f, 1e-6f);  // the base colour (mapTransmissionOntoGlass)
}

// The fuzz target's seeds (tests/fuzz/corpus_model: a format byte, then the file) load as they should.
TEST(ModelFile, BinaryGltfColladaOffPlyAndStlSeedsLoad) {
    const fs::path dir = test::tempDir();
    struct Seed {
        const char* name;
        size_t triangles;
    };
    for (const Seed& seed : {Seed{"two_quads.glb", 4}, Seed{"triangle.dae", 1}, Seed{"quad.off", 2},
                             Seed{"binary.ply", 2}, Seed{"binary.stl", 2}}) {
        SCOPED_TRACE(seed.name);
        std::ifstream in(fs::path(PENUMBRA_SOURCE_DIR) / "tests" / "fuzz" / "corpus_model" / seed.name, std::ios::binary);
        std::stringstream bytes;
        bytes << in.rdbuf();
        ASSERT_GT(bytes.str().size(), 1u);
        const fs::path file = test::writeFile(dir / seed.name, bytes.str().substr(1));
        Quiet q;
        LoadedScene s = loadScene(file, {}, q.logger);
        EXPECT_EQ(s.scene.triangleCount(), seed.triangles);
        if (std::string(seed.name) == "two_quads.glb") {
            EXPECT_TRUE(materialOf(s.scene, "lamp").isEmissive());
        }
    }
}

TEST(ModelFile, StlAndPlyWithVertexColours) {
    const fs::path dir = test::tempDir();
    const fs::path stl = test::writeFile(dir / "quad.stl", R"(solid quad
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 1 0 0
  vertex 1 1 0
 endloop
endfacet
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 1 1 0
  vertex 0 1 0
 endloop
endfacet
endsolid quad
)");
    Quiet q;
    LoadedScene s = loadScene(stl, {}, q.logger);
    EXPECT_EQ(s.scene.triangleCount(), 2u);
    EXPECT_FALSE(s.camera.has_value());

    // Per-vertex red and blue: each triangle's kd is the material's times its corners' mean colour.
    const fs::path ply = test::writeFile(dir / "colours.ply", R"(ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
property uchar red
property uchar green
property uchar blue
element face 2
property list uchar int vertex_indices
end_header
0 0 0 255 0 0
1 0 0 255 0 0
1 1 0 255 0 0
0 1 0 0 0 255
3 0 1 2
3 0 2 3
)");
    LoadedScene p = loadScene(ply, {}, q.logger);
    ASSERT_EQ(p.scene.meshes.size(), 1u);
    const TriangleMesh& m = p.scene.meshes[0];
    ASSERT_EQ(m.faceMaterials.size(), 2u);
    const Material& red = p.scene.materials[m.faceMaterials[0]];
    const Material& mixed = p.scene.materials[m.faceMaterials[1]];
    const Material& base = p.scene.materials[m.material];
    EXPECT_GT(base.kd.r, 0.f);
    EXPECT_NEAR(red.kd.r, base.kd.r, 1e-6f);
    EXPECT_EQ(red.kd.g, 0.f);
    EXPECT_EQ(red.kd.b, 0.f);
    EXPECT_NEAR(mixed.kd.r, base.kd.r * 170.f / 255.f, 1e-5f);  // (255 + 255 + 0) / 3
    EXPECT_NEAR(mixed.kd.b, base.kd.b * 85.f / 255.f, 1e-5f);
}

TEST(ModelFile, UnknownMalformedAndEmptyFilesAreErrorsNamingTheFile) {
    const fs::path dir = test::tempDir();
    test::writeFile(dir / "scene.xyz", "whatever\n");
    std::string e = errorOf(dir / "scene.xyz");
    EXPECT_NE(e.find("scene.xyz: unknown scene format '.xyz'"), std::string::npos) << e;
    for (const char* ext : {".json", ".obj", ".ply", ".stl", ".gltf", ".glb", ".fbx", ".dae"})
        EXPECT_NE(e.find(ext), std::string::npos) << ext << " missing from: " << e;

    struct Case {
        const char* name;
        std::string text;
    };
    const Case cases[] = {{"broken.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n"},
                          {"broken.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [{\"primitives\": 7}]}"},
                          {"garbage.glb", std::string("glTF\x02\0\0\0\xff\xff\xff\x7f", 12)},
                          {"garbage.fbx", std::string(300, '\x17')},
                          {"empty.stl", ""},
                          {"notriangles.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                              "property float z\nend_header\n0 0 0\n"}};
    for (const Case& c : cases) {
        test::writeFile(dir / c.name, c.text);
        const std::string err = errorOf(dir / c.name);
        EXPECT_NE(err.find((dir / c.name).string()), std::string::npos) << c.name << ": " << err;
        EXPECT_EQ(err.find('\n'), std::string::npos) << err;
    }
}

// Assimp 5.2.5's OFF reader allocates what the header's counts claim, and its
// number parser wraps past 2^32 - 1: a 110-byte fuzz_model finding
// (corpus_model/oom_off_count_wraps.off) made it ask for 32 GiB. The loader
// refuses counts the file cannot hold first; valid headers (comments, blank
// lines, the counts glued to OFF) still load.
TEST(ModelFile, OffCountsTheFileCannotHoldAreRefusedBeforeAssimp) {
    const fs::path dir = test::tempDir();
    std::ifstream in(fs::path(PENUMBRA_SOURCE_DIR) / "tests" / "fuzz" / "corpus_model" / "oom_off_count_wraps.off",
                     std::ios::binary);
    std::stringstream seed;
    seed << in.rdbuf();
    ASSERT_GT(seed.str().size(), 1u);
    struct Case {
        const char* name;
        std::string text;
        const char* why;
    };
    const Case refused[] = {
        {"wraps.off", seed.str().substr(1), "the header's vertex or face count does not fit in 32 bits"},
        {"million.off", "OFF\n1000000 1 0\n0 0 0\n3 0 0 0\n",
         "the header declares 1000000 vertices and 1 faces, more than the file's 5 lines can hold"},
        {"faces.off", "OFF 3 4000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "declares 3 vertices and 4000000000 faces"},
    };
    for (const Case& c : refused) {
        test::writeFile(dir / c.name, c.text);
        const std::string err = errorOf(dir / c.name);
        EXPECT_NE(err.find((dir / c.name).string()), std::string::npos) << c.name << ": " << err;
        EXPECT_NE(err.find(c.why), std::string::npos) << c.name << ": " << err;
    }
    const std::string triangle = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    for (const std::string& header : {std::string("# made by hand\nOFF\n\n# counts\n3 1 0\n"), std::string("OFF3 1 0\n"),
                                      std::string("3 1 0\n")}) {
        SCOPED_TRACE(header);
        const fs::path file = test::writeFile(dir / "ok.off", header + triangle);
        Quiet q;
        LoadedScene s = loadScene(file, {}, q.logger);
        EXPECT_EQ(s.scene.triangleCount(), 1u);
    }
}

// A data: URI whose base64 holds a byte outside ASCII, and a URI of control
// characters (both fuzz_model findings that made Assimp leak or misread), are
// refused with one short line naming the file; the same bytes in a name are fine.
TEST(ModelFile, GltfDataUrisOutsideAsciiAndControlCharactersAreRefused) {
    const fs::path dir = test::tempDir();
    const std::string good = test::twoQuadsGltf();
    const size_t at = good.find(";base64,") + 20;
    ASSERT_NE(at, std::string::npos + 20);
    struct Case {
        const char* name;
        std::string text;
        const char* why;
    };
    const Case cases[] = {
        {"raw.gltf", good.substr(0, at) + "\xc3\xa9" + good.substr(at + 2), "Failed to decode 'uri'"},
        {"escaped.gltf", good.substr(0, at) + "\\u00e9" + good.substr(at + 2), "Failed to decode 'uri'"},
        {"u0010.gltf", test::twoQuadsGltf("\\u0010\\u0001\\u0000\\u0003\\u0005AAAA"), "a URI holds a control character"}};
    for (const Case& c : cases) {
        test::writeFile(dir / c.name, c.text);
        const std::string err = errorOf(dir / c.name);
        EXPECT_NE(err.find((dir / c.name).string() + ": cannot read as glTF: "), std::string::npos) << err;
        EXPECT_NE(err.find(c.why), std::string::npos) << c.name << ": " << err;
        EXPECT_LT(err.size(), (dir / c.name).string().size() + 350) << "tinygltf quotes the whole URI: " << err;
        EXPECT_EQ(err.find('\n'), std::string::npos) << err;
    }
    // The same bytes elsewhere (a name) are fine.
    std::string named = good;
    named.replace(named.find("\"glow\""), 6, "\"gl\xc3\xb6w\"");
    test::writeFile(dir / "named.gltf", named);
    EXPECT_EQ(errorOf(dir / "named.gltf"), "");
}

// Assimp 5.2.5's ASCII STL reader leaks a solid's mesh and node (2,464 bytes)
// when it throws inside the solid (a fuzz_model finding): text STL files are
// checked first, and the error names the line. Well-formed ones still load.
TEST(ModelFile, MalformedAsciiStlIsRefusedBeforeAssimpWellFormedLoads) {
    const fs::path dir = test::tempDir();
    const std::string facet = "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 1 1 0\n endloop\nendfacet\n";
    struct Case {
        const char* name;
        std::string text;
        const char* why;
    };
    const Case cases[] = {
        {"two_vertices.stl", "solid q\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n endloop\nendfacet\nendsolid q\n",
         "line 6: ' endloop' where 'vertex X Y Z' was expected"},
        {"bad_number.stl", "solid q\nfacet normal 0 0 1e\n", "line 2: "},
        {"garbled.stl", "solid q\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  v\x80\x80\x80\x80" "ertex 1 0 0\n", "line 5: "},
        {"split_vertex.stl", "solid q\nfacet normal 0 0 1\n outer loop\n  vertex 0 0\n0\n", "line 4: "},
        {"unended.stl", "solid q\n" + facet, "ends inside a solid"},
        {"keyword_name.stl", "solid q facet\n" + facet + "endsolid q\n", "keyword 'facet'"},
        {"utf16.stl", std::string("\xff\xfes\0o\0l\0i\0d\0", 12), "UTF-16"}};
    for (const Case& c : cases) {
        test::writeFile(dir / c.name, c.text);
        const std::string err = errorOf(dir / c.name);
        EXPECT_NE(err.find((dir / c.name).string() + ": cannot read as stl: "), std::string::npos) << err;
        EXPECT_NE(err.find(c.why), std::string::npos) << c.name << ": " << err;
        EXPECT_EQ(err.find('\n'), std::string::npos) << err;
    }

    // CRLF lines, tabs, a UTF-8 byte-order mark, two solids, numbers as C writes them.
    std::string crlf = "\xef\xbb\xbfsolid first part\r\n";
    for (char ch : facet) crlf += ch == '\n' ? std::string("\r\n") : std::string(1, ch == ' ' ? '\t' : ch);
    crlf += "endsolid first\r\n\r\nsolid second\nfacet normal -0 +0 1.0e+0\nouter loop\n"
            "vertex .5 0. 0\nvertex 1.5E0 -0 0\nvertex 1 1 0\nendloop\nendfacet\nendsolid\n";
    test::writeFile(dir / "good.stl", crlf);
    Quiet q;
    LoadedScene s = loadScene(dir / "good.stl", {}, q.logger);
    EXPECT_EQ(s.scene.triangleCount(), 2u);

    // A binary STL whose 80-byte header starts with "solid" is binary (its size says so).
    std::string binary = "solid but binary";
    binary.resize(80, ' ');
    binary += std::string("\x01\0\0\0", 4);
    const float tri[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 1, 0};
    binary.append(reinterpret_cast<const char*>(tri), sizeof tri);
    binary += std::string(2, '\0');
    test::writeFile(dir / "binary.stl", binary);
    EXPECT_EQ(loadScene(dir / "binary.stl", {}, q.logger).scene.triangleCount(), 1u);
}

// A NaN coordinate (a fuzz_model finding: a binary STL) drops the faces on it,
// and the mesh keeps finite positions only.
TEST(ModelFile, FacesOnNonFinitePositionsAreDroppedWithThem) {
    const fs::path dir = test::tempDir();
    std::string stl(80, ' ');
    stl += std::string("\x02\0\0\0", 4);
    const float nan = std::nanf("");
    const float facets[2][12] = {{0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 1, 0, 0, 0, 1, 1, 0, nan, 1, 0}};
    for (const auto& f : facets) {
        stl.append(reinterpret_cast<const char*>(f), sizeof f);
        stl += std::string(2, '\0');
    }
    test::writeFile(dir / "nan.stl", stl);
    Quiet q;
    LoadedScene s = loadScene(dir / "nan.stl", {}, q.logger);
    EXPECT_EQ(s.scene.triangleCount(), 1u);
    for (const TriangleMesh& m : s.scene.meshes) {
        for (const Vec3f& p : m.positions) EXPECT_TRUE(isFinite(p));
        EXPECT_TRUE(m.normals.empty() || m.normals.size() == m.positions.size());
        for (uint32_t i : m.indices) EXPECT_LT(i, m.positions.size());
    }
}

// Where two Assimp readers claim an extension (.gltf, .glb) and neither accepts
// the file, Assimp would try every other format's reader: a PLY header in a
// .gltf hung the PLY reader. Such a file is refused instead: not JSON, or JSON
// that is not glTF.
TEST(ModelFile, GltfThatNoGltfReaderAcceptsIsRefusedNotReadAsAnotherFormat) {
    const fs::path dir = test::tempDir();
    struct Case {
        const char* name;
        std::string text;
        const char* why;
    };
    const Case cases[] = {
        {"ply.gltf", "ply\nformat ascii 1.0\nelement vertex 1\n", "the JSON is not valid"},
        {"stl.glb", "solid q\nfacet normal 0 0 1\nendsolid q\n", "the JSON is not valid"},
        {"solid.gltf", "{\"solid q\": \"*3dsmax_asciiexport\"}\n", "\"asset\" object not found"}};
    for (const Case& c : cases) {
        test::writeFile(dir / c.name, c.text);
        const std::string err = errorOf(dir / c.name);
        EXPECT_NE(err.find((dir / c.name).string() + ": cannot read as "), std::string::npos) << err;
        EXPECT_NE(err.find(c.why), std::string::npos) << c.name << ": " << err;
    }
}

// Assimp 5.2.5 bounds an accessor by its buffer view's length but not by its
// byteOffset, and read past the buffer (a fuzz_model finding): accessors and
// buffer views must lie inside what they view.
TEST(ModelFile, GltfAccessorsAndViewsPastTheirBufferAreRefused) {
    const fs::path dir = test::tempDir();
    const std::string good = test::twoQuadsGltf();
    struct Case {
        const char* name;
        const char* from;
        const char* to;
        const char* why;
    };
    const Case cases[] = {
        {"accessor.gltf", "\"byteOffset\": 48, \"componentType\": 5126", "\"byteOffset\": 68, \"componentType\": 5126",
         "accessors[1] reads bytes up to 116 of bufferViews[0], which has 96"},
        {"view.gltf", "\"byteOffset\": 96, \"byteLength\": 12", "\"byteOffset\": 100, \"byteLength\": 12",
         "bufferViews[1] (byteOffset 100, byteLength 12) reaches past its buffer's 108 bytes"},
        {"type.gltf", "\"type\": \"SCALAR\"", "\"type\": \"VEC5\"", "Unsupported `type` for accessor object. Got \"VEC5\""},
        {"nobuffer.gltf", "{\"buffer\": 0, \"byteOffset\": 96", "{\"buffer\": 3, \"byteOffset\": 96",
         "bufferViews[1].buffer names no entry of 'buffers'"}};
    for (const Case& c : cases) {
        std::string text = good;
        const size_t at = text.find(c.from);
        ASSERT_NE(at, std::string::npos) << c.from;
        text.replace(at, std::string(c.from).size(), c.to);
        test::writeFile(dir / c.name, text);
        const std::string err = errorOf(dir / c.name);
        EXPECT_NE(err.find((dir / c.name).string() + ": cannot read as glTF: "), std::string::npos) << err;
        EXPECT_NE(err.find(c.why), std::string::npos) << c.name << ": " << err;
    }
}

TEST(SharedScenes, StanfordBunnyPlyHasAllItsTriangles) {
    const fs::path ply = test::sharedScenePath("bunny_stanford/bun_zipper.ply");
    if (ply.empty()) GTEST_SKIP() << "../shared/scenes not present";
    Quiet q;
    LoadedScene s = loadScene(ply, {}, q.logger);
    EXPECT_EQ(s.scene.triangleCount(), 69451u);
    ASSERT_EQ(s.scene.meshes.size(), 1u);
    EXPECT_EQ(s.scene.meshes[0].normals.size(), s.scene.meshes[0].positions.size()) << "smoothed";
}

}  // namespace
}  // namespace penumbra
