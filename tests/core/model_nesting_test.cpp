// Model files that Assimp 5.2.5 would recurse into until the stack overflows,
// loop on, or copy without bound (COLLADA, FBX, DirectX .x, AC3D), refused
// before Assimp reads them with an error naming the file; files nested a
// modest depth still load. The hostile files are generated here.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/io/fbx_checks.h"
#include "core/io/nesting_checks.h"
#include "core/io/scene_loader.h"
#include "support/test_support.h"

namespace penumbra {
namespace {
namespace fs = std::filesystem;

std::string repeat(const std::string& s, size_t n) {
    std::string out;
    out.reserve(s.size() * n);
    for (size_t i = 0; i < n; ++i) out += s;
    return out;
}

/// The error of loading `text` as `name` (empty when it loads), with the triangles it loaded.
struct Outcome {
    std::string error;
    size_t triangles = 0;
};

Outcome load(const std::string& name, const std::string& text, const LoadOptions& options = {}) {
    const fs::path file = test::writeFile(test::tempDir() / name, text);
    try {
        return {"", loadScene(file, options, Logger([](LogLevel, std::string_view) {}, LogLevel::Error)).scene.triangleCount()};
    } catch (const Error& e) {
        return {e.what(), 0};
    }
}

void expectRefused(const std::string& name, const std::string& text, std::initializer_list<std::string_view> has) {
    const Outcome o = load(name, text);
    ASSERT_FALSE(o.error.empty()) << name << " loaded";
    EXPECT_NE(o.error.find(name), std::string::npos) << o.error;
    for (auto h : has) EXPECT_NE(o.error.find(h), std::string::npos) << "'" << h << "' not in: " << o.error;
}

// ---- COLLADA

const char* kColladaHead =
    R"(<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">)"
    R"(<asset><unit meter="1"/><up_axis>Y_UP</up_axis></asset>)";

/// One triangle: `count` is the float_array's count, `p` the indices, `semantic` the primitive's input.
std::string colladaGeometry(const std::string& count = "9", const std::string& p = "0 1 2",
                            const std::string& semantic = "VERTEX") {
    return R"(<library_geometries><geometry id="g"><mesh><source id="pos"><float_array id="pa" count=")" + count +
           R"(">0 0 0 1 0 0 0 1 0</float_array><technique_common><accessor source="#pa" count="3" stride="3">)"
           R"(<param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>)"
           R"(</accessor></technique_common></source><vertices id="v"><input semantic="POSITION" source="#pos"/>)"
           R"(</vertices><triangles count="1"><input semantic=")" + semantic +
           R"(" source="#v" offset="0"/><p>)" + p + "</p></triangles></mesh></geometry></library_geometries>";
}

std::string collada(const std::string& nodes, const std::string& geometry = colladaGeometry(),
                    const std::string& libraries = "") {
    return kColladaHead + geometry + libraries + R"(<library_visual_scenes><visual_scene id="s">)" + nodes +
           R"(</visual_scene></library_visual_scenes><scene><instance_visual_scene url="#s"/></scene></COLLADA>)";
}

std::string nestedNodes(size_t depth) {
    std::string open, close;
    for (size_t i = 0; i < depth; ++i) open += "<node id=\"n" + std::to_string(i) + "\">";
    return open + R"(<instance_geometry url="#g"/>)" + repeat("</node>", depth);
}

TEST(ModelNesting, ColladaNodesNestedTenThousandDeepAreRefused) {
    expectRefused("deep.dae", collada(nestedNodes(10000)), {"nest deeper than 256", "line 1"});
    EXPECT_EQ(load("fifty.dae", collada(nestedNodes(50))).triangles, 1u);
}

TEST(ModelNesting, ColladaNodeThatInstancesItselfIsRefused) {
    const std::string library = R"(<library_nodes><node id="a"><instance_node url="#a"/>)"
                                R"(<instance_geometry url="#g"/></node></library_nodes>)";
    expectRefused("self.dae", collada(R"(<node id="r"><instance_node url="#a"/></node>)", colladaGeometry(), library),
                  {"<node>", "instances itself"});
    // Through a child: b holds c, which instances b.
    const std::string loop = R"(<library_nodes><node id="b"><node id="c"><instance_node url="#b"/></node></node></library_nodes>)";
    expectRefused("loop.dae", collada(R"(<node id="r"><instance_node url="#b"/></node>)", colladaGeometry(), loop),
                  {"instances itself"});
}

TEST(ModelNesting, ColladaInstanceChainsThatExpandWithoutBoundAreRefused) {
    // 40 library nodes, each instancing the one before twice: 2^40 nodes once expanded.
    std::string library = R"(<library_nodes><node id="l0"><instance_geometry url="#g"/></node>)";
    for (int i = 1; i <= 40; ++i)
        library += "<node id=\"l" + std::to_string(i) + "\"><instance_node url=\"#l" + std::to_string(i - 1) +
                   "\"/><instance_node url=\"#l" + std::to_string(i - 1) + "\"/></node>";
    library += "</library_nodes>";
    expectRefused("doubling.dae", collada(R"(<node id="r"><instance_node url="#l40"/></node>)", colladaGeometry(), library + ""),
                  {"more than 1000000 nodes"});
    // A chain of 1,000 instances, each node holding only the next: deep, not wide.
    std::string chain = R"(<library_nodes><node id="c0"><instance_geometry url="#g"/></node>)";
    for (int i = 1; i <= 1000; ++i)
        chain += "<node id=\"c" + std::to_string(i) + "\"><instance_node url=\"#c" + std::to_string(i - 1) + "\"/></node>";
    expectRefused("chain.dae", collada(R"(<node id="r"><instance_node url="#c1000"/></node>)", colladaGeometry(),
                                       chain + "</library_nodes>"),
                  {"nest deeper than 256"});
}

TEST(ModelNesting, ColladaArraysAndIndicesAssimpWouldReadPastAreRefused) {
    // A count that is not a number: Assimp reads it as 0 values, then dereferences the empty array.
    expectRefused("count.dae", collada(R"(<node id="r"><instance_geometry url="#g"/></node>)", colladaGeometry("abc")),
                  {"<accessor>", "reads 9 values of an array that holds 0"});
    expectRefused("short.dae", collada(R"(<node id="r"><instance_geometry url="#g"/></node>)", colladaGeometry("6")),
                  {"reads 9 values of an array that holds 6"});
    expectRefused("many.dae", collada(R"(<node id="r"><instance_geometry url="#g"/></node>)", colladaGeometry("4000000000")),
                  {"<float_array>", "declares 4000000000 values but holds 9"});
    // An index Assimp cannot step over: it read "x" for ever, growing without bound.
    expectRefused("index.dae", collada(R"(<node id="r"><instance_geometry url="#g"/></node>)", colladaGeometry("9", "0 1 x 2")),
                  {"<p>", "integer"});
    // No VERTEX input: Assimp indexes with an unset offset.
    const std::string noVertex = colladaGeometry("9", "0 1 2", "NORMAL");
    expectRefused("novertex.dae", collada(R"(<node id="r"><instance_geometry url="#g"/></node>)", noVertex),
                  {"no VERTEX input"});
    EXPECT_EQ(load("fine.dae", collada(R"(<node id="r"><instance_geometry url="#g"/></node>)")).triangles, 1u);
}

TEST(ModelNesting, ColladaControllersThatDeformEachOtherInALoopAreRefused) {
    const std::string controllers = R"(<library_controllers><controller id="c1"><skin source="#c2"/></controller>)"
                                    R"(<controller id="c2"><skin source="#c1"/></controller></library_controllers>)";
    expectRefused("controllers.dae",
                  collada(R"(<node id="r"><instance_geometry url="#g"/></node>)", colladaGeometry(), controllers),
                  {"<controller>", "loops"});
}

TEST(ModelNesting, XmlElementsNestedDeeperThanTheLimitAreRefused) {
    expectRefused("deep_extra.dae",
                  collada(R"(<node id="r"><instance_geometry url="#g"/><extra>)" + repeat("<a>", 300) + repeat("</a>", 300) +
                          "</extra></node>"),
                  {"XML elements nest deeper than 256"});
    expectRefused("broken.dae", collada("<node id=\"r\">"), {"not well-formed XML"});
}

// ---- FBX

TEST(ModelNesting, AsciiFbxScopesNestedHundredThousandDeepAreRefused) {
    const std::string head = "; FBX 7.4.0 project file\nFBXHeaderExtension:  {\n FBXHeaderVersion: 1003\n}\n";
    expectRefused("deep.fbx", head + repeat("A: {\n", 100000) + repeat("}\n", 100000), {"FBX scopes nest deeper than 256"});
    // Braces in strings and comments are not scopes.
    EXPECT_FALSE(fbxProblem(head + repeat("A: \"{{{\" ; {{{\n", 1000)));
    EXPECT_FALSE(fbxProblem(head + repeat("A: {\n", 200) + repeat("}\n", 200)));
    EXPECT_TRUE(fbxProblem(head + repeat("A: {\n", 257)));
    // Where Assimp's parser would throw (leaking the scopes it has built), the file is refused first.
    expectRefused("values.fbx", head + "A: {\n B: 1 2\n}\n", {"line 6", "two values without a comma"});
    expectRefused("open.fbx", head + "A: {\n B: 1\n", {"ends inside 1 scope(s)"});
    expectRefused("keyless.fbx", head + "A: {\n 1, 2\n}\n", {"a value where a key was expected"});
}

/// A binary FBX (version 7400: 32-bit offsets) of records nested `depth`
/// deep: each a header with a one-byte name, then the next, then a sentinel.
std::string binaryFbx(size_t depth) {
    std::string b = std::string("Kaydara FBX Binary  ") + '\0' + "\x1a" + '\0';
    const uint32_t version = 7400;
    b.append(reinterpret_cast<const char*>(&version), 4);
    constexpr size_t kRecord = 13 + 1, kSentinel = 13;
    for (size_t i = 0; i < depth; ++i) {
        const uint32_t end = uint32_t(b.size() + kRecord + (depth - 1 - i) * (kRecord + kSentinel));
        const uint32_t zero = 0;
        b.append(reinterpret_cast<const char*>(&end), 4);
        b.append(reinterpret_cast<const char*>(&zero), 4);  // no properties
        b.append(reinterpret_cast<const char*>(&zero), 4);
        b += "\x01N";
    }
    return b + std::string((depth - 1) * kSentinel, '\0') + std::string(13, '\0');
}

TEST(ModelNesting, BinaryFbxRecordsNestedDeeperThanTheLimitAreRefused) {
    EXPECT_FALSE(fbxProblem(binaryFbx(100)));
    const auto deep = fbxProblem(binaryFbx(5000));
    ASSERT_TRUE(deep);
    EXPECT_NE(deep->find("FBX records nest deeper than 256"), std::string::npos) << *deep;
    expectRefused("deep_binary.fbx", binaryFbx(100000), {"FBX records nest deeper than 256"});
}

/// An ASCII FBX 7.4 file of Model objects 1..n and the connections (child, parent).
std::string fbxModels(size_t n, const std::vector<std::pair<size_t, size_t>>& connections) {
    std::string s = "; FBX 7.4.0 project file\nFBXHeaderExtension:  {\n FBXHeaderVersion: 1003\n FBXVersion: 7400\n}\n"
                    "GlobalSettings:  {\n Version: 1000\n}\nObjects:  {\n";
    for (size_t i = 1; i <= n; ++i)
        s += " Model: " + std::to_string(i) + ", \"Model::m" + std::to_string(i) + "\", \"Null\" {\n  Version: 232\n }\n";
    s += "}\nConnections:  {\n";
    for (const auto& [child, parent] : connections)
        s += " C: \"OO\"," + std::to_string(child) + "," + std::to_string(parent) + "\n";
    return s + "}\n";
}

// Assimp converts the model hierarchy recursively, following the Connections
// without looking for cycles: a model connected below itself, and a chain of
// 100,000 models, each overflowed the stack.
TEST(ModelNesting, FbxModelsConnectedInACycleOrTooDeepAreRefused) {
    expectRefused("self.fbx", fbxModels(1, {{1, 0}, {1, 1}}), {"FBX model 1 is connected below itself"});
    expectRefused("loop.fbx", fbxModels(3, {{1, 0}, {2, 1}, {3, 2}, {1, 3}}), {"connected below itself"});
    std::vector<std::pair<size_t, size_t>> chain{{1, 0}};
    for (size_t i = 2; i <= 100000; ++i) chain.emplace_back(i, i - 1);
    expectRefused("chain.fbx", fbxModels(100000, chain), {"FBX models (through their Connections) nest deeper than 256"});
    // 300 models side by side, and a chain of 200, are fine.
    std::vector<std::pair<size_t, size_t>> wide, deep{{1, 0}};
    for (size_t i = 1; i <= 300; ++i) wide.emplace_back(i, 0);
    for (size_t i = 2; i <= 200; ++i) deep.emplace_back(i, i - 1);
    EXPECT_FALSE(fbxProblem(fbxModels(300, wide)));
    EXPECT_FALSE(fbxProblem(fbxModels(200, deep)));
    // A triangle below two models still loads.
    std::string tri = fbxModels(2, {{1, 0}, {2, 1}, {10, 2}});
    tri.insert(tri.find("Objects:  {\n") + 12,
               " Geometry: 10, \"Geometry::tri\", \"Mesh\" {\n  Vertices: *9 {\n   a: 0,0,0,1,0,0,0,1,0\n  }\n"
               "  PolygonVertexIndex: *3 {\n   a: 0,1,-3\n  }\n  GeometryVersion: 124\n }\n");
    EXPECT_EQ(load("triangle.fbx", tri).triangles, 1u) << load("triangle.fbx", tri).error;
}

/// A binary FBX record (version 7400): its properties already encoded.
struct FbxRecord {
    std::string name, properties;
    uint32_t count = 0;
    std::vector<FbxRecord> nested;
};

std::string encode(const FbxRecord& r, size_t at) {
    std::string body = r.properties;
    size_t inner = at + 13 + r.name.size() + body.size();
    for (const FbxRecord& n : r.nested) {
        const std::string e = encode(n, inner);
        body += e;
        inner += e.size();
    }
    if (!r.nested.empty()) body += std::string(13, '\0');
    const uint32_t header[3] = {uint32_t(at + 13 + r.name.size() + body.size()), r.count, uint32_t(r.properties.size())};
    return std::string(reinterpret_cast<const char*>(header), 12) + char(r.name.size()) + r.name + body;
}

std::string int64Property(int64_t v) {
    std::string p(1, 'L');
    p.append(reinterpret_cast<const char*>(&v), 8);
    return p;
}
std::string stringProperty(const std::string& v) {
    const uint32_t n = uint32_t(v.size());
    std::string p(1, 'S');
    p.append(reinterpret_cast<const char*>(&n), 4);
    return p + v;
}

TEST(ModelNesting, BinaryFbxModelsConnectedInACycleAreRefused) {
    std::string b = std::string("Kaydara FBX Binary  ") + '\0' + "\x1a" + '\0';
    const uint32_t version = 7400;
    b.append(reinterpret_cast<const char*>(&version), 4);
    FbxRecord objects{"Objects", "", 0, {{"Model", int64Property(7) + stringProperty("m"), 2, {}}}};
    FbxRecord connections{"Connections", "", 0, {{"C", stringProperty("OO") + int64Property(7) + int64Property(0), 3, {}}}};
    const auto file = [&](const FbxRecord& c) {
        std::string f = b + encode(objects, b.size());
        return f + encode(c, f.size()) + std::string(13, '\0');
    };
    EXPECT_FALSE(fbxProblem(file(connections)));
    connections.nested.push_back({"C", stringProperty("OO") + int64Property(7) + int64Property(7), 3, {}});
    const auto problem = fbxProblem(file(connections));
    ASSERT_TRUE(problem);
    EXPECT_NE(problem->find("FBX model 7 is connected below itself"), std::string::npos) << *problem;
}

// ---- DirectX .x

const char* kXMesh = "Mesh m { 3; 0;0;0;, 1;0;0;, 0;1;0;; 1; 3;0,1,2;; }\n";

TEST(ModelNesting, DirectXFramesNestedHundredThousandDeepAreRefused) {
    const std::string head = "xof 0303txt 0032\n";
    expectRefused("deep.x", head + repeat("Frame f {\n", 100000) + kXMesh + repeat("}\n", 100000),
                  {"DirectX .x braces nest deeper than 256"});
    EXPECT_EQ(load("ten.x", head + repeat("Frame f {\n", 10) + kXMesh + repeat("}\n", 10)).triangles, 1u);
    // A '}' in a comment or in a string Assimp reads raw does not close a frame.
    EXPECT_TRUE(xFileNestingProblem(head + repeat("Frame f { # }\n", 300)));
    EXPECT_TRUE(xFileNestingProblem(head + repeat("Frame f { TextureFilename { \"}\"; \n", 300)));
    expectRefused("binary.x", "xof 0303bin 0032" + std::string(16, '\0'), {"binary and compressed"});
}

// ---- AC3D

const char* kAcHead = "AC3Db\nMATERIAL \"m\" rgb 1 1 1  amb 0.2 0.2 0.2  emis 0 0 0  spec 0 0 0  shi 0  trans 0\n";
const char* kAcTriangle = "OBJECT poly\nnumvert 3\n0 0 0\n1 0 0\n0 1 0\nnumsurf 1\nSURF 0x10\nmat 0\nrefs 3\n0 0 0\n1 0 0\n2 0 0\nkids 0\n";

TEST(ModelNesting, Ac3dKidsNestedHundredThousandDeepAreRefused) {
    expectRefused("deep.ac", kAcHead + std::string("OBJECT world\nkids 1\n") + repeat("OBJECT group\nkids 1\n", 100000) + kAcTriangle,
                  {"AC3D objects nest deeper than 256"});
    EXPECT_EQ(load("ten.ac", kAcHead + std::string("OBJECT world\nkids 1\n") + repeat("OBJECT group\nkids 1\n", 10) + kAcTriangle)
                  .triangles,
              1u);
    // Wide is fine: 300 groups side by side, each with one triangle.
    const std::string wide = kAcHead + std::string("OBJECT world\nkids 300\n") + repeat("OBJECT group\nkids 1\n" + std::string(kAcTriangle), 300);
    EXPECT_FALSE(ac3dNestingProblem(wide));
    // "kids" lines that Assimp reads as a surface's references do not count.
    const std::string refs = "OBJECT poly\nnumvert 3\n0 0 0\n1 0 0\n0 1 0\nnumsurf 1\nSURF 0x10\nmat 0\nrefs 3\nkids 1\nkids 1\nkids 1\nkids 0\n";
    EXPECT_FALSE(ac3dNestingProblem(kAcHead + repeat(refs, 300)));
}

TEST(ModelNesting, Ac3dCountsBeyondTheFileAreRefused) {
    expectRefused("surfaces.ac", kAcHead + std::string("OBJECT poly\nnumvert 0\nnumsurf 100000000\nkids 0\n"),
                  {"numsurf 100000000", "claims more lines"});
    expectRefused("empty_surfaces.ac", kAcHead + std::string("OBJECT poly\nnumsurf 3\nkids 0\nx\ny\nz\n"),
                  {"followed by fewer surfaces"});
}

}  // namespace
}  // namespace penumbra
