// Bad input, end to end through the penumbra command: every broken file,
// option or extreme number either fails cleanly (exit code 1..127, never a
// signal; exactly one "penumbra: error:" line naming the file and the
// problem; no image and no temporary file left behind) or renders an image
// whose pixels are all finite.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "core/image_io.h"
#include "support/test_support.h"

using namespace penumbra;
namespace fs = std::filesystem;

#if defined(__SANITIZE_ADDRESS__)
#define PENUMBRA_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PENUMBRA_TEST_ASAN 1
#endif
#endif

namespace {

struct RunResult {
    int exitCode;
    std::string output;  // stdout + stderr
    double seconds;
};

std::string shellQuote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

/// Runs `prefix penumbra args` in a shell; a death by signal reads as 128 + signal.
RunResult runPenumbra(const std::string& args, const std::string& prefix = "") {
    std::string cmd = prefix + shellQuote((test::binaryDir() / "penumbra").string()) + " " + args + " 2>&1";
    auto t0 = std::chrono::steady_clock::now();
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) return {-1, "popen failed", 0.0};
    std::string out;
    std::array<char, 4096> buf{};
    size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
    int status = ::pclose(p);
    int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return {code, out, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()};
}

std::vector<std::string> linesStartingWith(const std::string& text, const std::string& prefix) {
    std::vector<std::string> out;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(prefix, 0) == 0) out.push_back(line);
    return out;
}

bool sanitizerReport(const std::string& out) {
    return out.find("Sanitizer") != std::string::npos || out.find("runtime error:") != std::string::npos;
}

std::vector<std::string> filesIn(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(dir)) names.push_back(e.path().filename().string());
    return names;
}

std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += x + " ";
    return s;
}

/// Deterministic binary garbage (with NUL bytes, high bytes and newlines).
std::string garbage(size_t n, uint32_t seed) {
    std::string s(n, '\0');
    for (char& c : s) {
        seed = seed * 1664525u + 1013904223u;
        c = static_cast<char>(seed >> 24);
    }
    return s;
}

// A 2x2 quad facing +z (the automatic camera looks at it along -z).
constexpr const char* kQuad = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n";

class BadInput : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = test::tempDir();
        out_ = dir_ / "out";
        fs::create_directories(out_);
    }

    fs::path write(const std::string& name, const std::string& text) const { return test::writeFile(dir_ / name, text); }

    /// Runs penumbra with the output folder emptied first, so that what the
    /// checks find there is what this run left.
    RunResult run(const std::string& args, const std::string& prefix = "") const {
        for (const auto& e : fs::directory_iterator(out_)) fs::remove_all(e.path());
        return runPenumbra(args, prefix);
    }
    std::string in(const std::string& name) const { return shellQuote((dir_ / name).string()); }
    fs::path outPath(const std::string& name = "img.exr") const { return out_ / name; }
    std::string out(const std::string& name = "img.exr") const { return " -o " + shellQuote(outPath(name).string()); }

    /// The run failed cleanly: exit code in [1, 127], no sanitizer report,
    /// exactly one error line, holding every needle, and nothing written.
    void expectCleanFailure(const RunResult& r, std::initializer_list<std::string> needles, int exitCode = 1) const {
        EXPECT_EQ(r.exitCode, exitCode) << r.output;
        EXPECT_FALSE(sanitizerReport(r.output)) << r.output;
        auto errors = linesStartingWith(r.output, "penumbra: error: ");
        ASSERT_EQ(errors.size(), 1u) << r.output;
        for (const auto& n : needles) EXPECT_NE(errors[0].find(n), std::string::npos) << "missing '" << n << "' in: " << errors[0];
        EXPECT_LT(errors[0].size(), 600u) << "an error message should fit a line: " << errors[0].substr(0, 600);
        EXPECT_TRUE(filesIn(out_).empty()) << "left behind: " << joined(filesIn(out_));
    }

    /// The run succeeded without sanitizer reports; returns its warnings.
    std::vector<std::string> expectSuccess(const RunResult& r) const {
        EXPECT_EQ(r.exitCode, 0) << r.output;
        EXPECT_FALSE(sanitizerReport(r.output)) << r.output;
        EXPECT_TRUE(linesStartingWith(r.output, "penumbra: error: ").empty()) << r.output;
        return linesStartingWith(r.output, "penumbra: warning: ");
    }

    /// Exactly one warning holds every needle.
    static void expectWarning(const std::vector<std::string>& warnings, std::initializer_list<std::string> needles) {
        size_t matches = 0;
        for (const auto& w : warnings) {
            bool all = true;
            for (const auto& n : needles) all = all && w.find(n) != std::string::npos;
            matches += all;
        }
        EXPECT_EQ(matches, 1u) << "warnings:\n" << joined(warnings);
    }

    /// Every channel of every pixel of the written image is finite; returns the image.
    ImageData expectFiniteImage(const std::string& name = "img.exr") const {
        ImageData img = readImage(outPath(name));
        size_t bad = 0;
        for (float v : img.pixels) bad += !std::isfinite(v);
        EXPECT_EQ(bad, 0u) << name << " has non-finite values";
        return img;
    }

    nlohmann::json stats(const std::string& name = "stats.json") const {
        std::ifstream f(dir_ / name);
        return nlohmann::json::parse(f);
    }

    fs::path dir_, out_;
};

// ------------------------------------------------------------------ files

TEST_F(BadInput, MissingSceneFile) {
    expectCleanFailure(run(in("nope.obj") + out()), {"nope.obj", "no such file"});
    expectCleanFailure(run(in("nope.json") + out()), {"nope.json", "no such file"});
}

TEST_F(BadInput, UnreadableSceneFile) {
    if (::geteuid() == 0) GTEST_SKIP() << "root reads files without read permission";
    fs::path obj = write("locked.obj", std::string(kQuad) + "f 1 2 3 4\n");
    fs::permissions(obj, fs::perms::none);
    expectCleanFailure(run(in("locked.obj") + out()), {"locked.obj", "cannot open"});
    fs::permissions(obj, fs::perms::owner_all);
}

TEST_F(BadInput, DirectoryAsSceneFile) {
    fs::create_directories(dir_ / "dir.obj");
    fs::create_directories(dir_ / "dir.json");
    expectCleanFailure(run(in("dir.obj") + out()), {"dir.obj", "is a directory"});
    expectCleanFailure(run(in("dir.json") + out()), {"dir.json", "is a directory"});
}

TEST_F(BadInput, UnknownSceneExtension) {
    write("scene.xyz", "ply\nformat ascii 1.0\n");
    expectCleanFailure(run(in("scene.xyz") + out()), {"scene.xyz", "unknown scene format '.xyz'", ".ply", ".gltf"});
    // A known extension with broken contents names the file too.
    write("scene.ply", "ply\nformat ascii 1.0\n");
    expectCleanFailure(run(in("scene.ply") + out()), {"scene.ply", "cannot read as ply"});
}

TEST_F(BadInput, EmptyFiles) {
    write("empty.obj", "");
    write("empty.json", "");
    expectCleanFailure(run(in("empty.obj") + out()), {"empty.obj", "no faces to render"});
    expectCleanFailure(run(in("empty.json") + out()), {"empty.json:1:1", "JSON syntax error", "end of input"});
}

TEST_F(BadInput, BinaryGarbage) {
    std::string bytes = garbage(4096, 1);
    ASSERT_NE(bytes.find('\0'), std::string::npos);
    write("garbage.obj", bytes);
    write("garbage.json", bytes);
    expectCleanFailure(run(in("garbage.obj") + out()), {"garbage.obj:", "binary data"});
    expectCleanFailure(run(in("garbage.json") + out()), {"garbage.json:1:", "JSON syntax error"});

    // A binary material library is skipped with a warning; the default material renders.
    write("garbage.mtl", bytes);
    write("uses_garbage.obj", "mtllib garbage.mtl\n" + std::string(kQuad) + "usemtl red\nf 1 2 3 4\n");
    auto warnings = expectSuccess(run(in("uses_garbage.obj") + " -q --width 8 --height 8 --spp 1" + out()));
    expectWarning(warnings, {"garbage.mtl", "binary data"});
    expectFiniteImage();
}

TEST_F(BadInput, ExtremelyLongLines) {
    const std::string tenMB(10u << 20, 'x');
    // A 10 MB comment and a 10 MB object name before a visible emitter.
    write("lit.mtl", "newmtl lamp\nKd 0 0 0\nKe 2 2 2\n");
    write("comment.obj", "# " + tenMB + "\nmtllib lit.mtl\no " + tenMB + "\n" + kQuad + "usemtl lamp\nf 1 2 3 4\n");
    expectSuccess(run(in("comment.obj") + " -q --width 8 --height 8 --spp 1" + out()));
    ImageData img = expectFiniteImage();
    EXPECT_EQ(img.at(4, 4, 0), 2.f);

    // A vertex with a 10-million-digit coordinate (infinite as a float): its face is dropped.
    write("number.obj", std::string(kQuad) + "v 1" + std::string(10u << 20, '1') + " 0 0\nf 1 2 5\n");
    expectCleanFailure(run(in("number.obj") + " --strict" + out()), {"number.obj", "non-finite", "line 6"});

    // JSON: a 10 MB key, a 10 MB number and an unterminated 10 MB string give short messages.
    write("key.json", "{\"" + tenMB + "\": 1}");
    expectCleanFailure(run(in("key.json") + out()), {"key.json", "unknown key"});
    write("number.json", "{\"ambient\": 1" + std::string(10u << 20, '0') + "}");
    expectCleanFailure(run(in("number.json") + out()), {"number.json:1:13", "out of range"});
    write("string.json", "{\"materials\": {\"" + tenMB);
    expectCleanFailure(run(in("string.json") + out()), {"string.json:1:", "JSON syntax error"});
}

TEST_F(BadInput, HugePolygonRenders) {
    // One face with 5000 corners (a disc seen head-on), far more than
    // tinyobjloader's 255: it loads, triangulates and renders.
    const int n = 5000;
    std::string obj = "mtllib lamp.mtl\n";
    for (int i = 0; i < n; ++i) {
        double a = 2.0 * std::numbers::pi * i / n;
        char line[64];
        std::snprintf(line, sizeof line, "v %.9g %.9g 0\n", std::cos(a), std::sin(a));
        obj += line;
    }
    obj += "usemtl lamp\nf";
    for (int i = 1; i <= n; ++i) (obj += ' ') += std::to_string(i);
    write("disc.obj", obj + "\n");
    write("lamp.mtl", "newmtl lamp\nKd 0 0 0\nKe 2 2 2\n");
    expectSuccess(run(in("disc.obj") + " -q --strict --width 16 --height 16 --spp 1 --stats-json " +
                              in("stats.json") + out()));
    ImageData img = expectFiniteImage();
    EXPECT_EQ(img.at(8, 8, 0), 2.f);   // the centre sees the emitter
    EXPECT_EQ(img.at(0, 0, 0), 0.f);   // the corners lie outside the disc
    EXPECT_EQ(img.at(15, 15, 0), 0.f);
    EXPECT_EQ(stats()["triangles"].get<size_t>(), size_t(n - 2));
}

// ------------------------------------------------------------------ OBJ

TEST_F(BadInput, ObjIndicesOutOfRange) {
    for (const char* face : {"f 1 2 9", "f 1 2 -9", "f 1 2 0", "f 1 2 3x 2147483648"}) {
        SCOPED_TRACE(face);
        write("bad.obj", std::string(kQuad) + face + "\n");
        expectCleanFailure(run(in("bad.obj") + " --strict" + out()), {"bad.obj", "invalid vertex indices", "line 5"});
    }
    // Without --strict the face is dropped with a warning, and then nothing is left.
    RunResult r = run(in("bad.obj") + out());
    expectCleanFailure(r, {"bad.obj", "no faces to render", "invalid"});
    EXPECT_EQ(linesStartingWith(r.output, "penumbra: warning: ").size(), 1u) << r.output;
}

TEST_F(BadInput, ObjBadTextureAndNormalIndicesFallBack) {
    write("lamp.mtl", "newmtl lamp\nKd 0 0 0\nKe 1 1 1\n");
    const std::string head = "mtllib lamp.mtl\n" + std::string(kQuad) + "vt 0 0\nvn 0 0 1\nusemtl lamp\n";
    write("vt.obj", head + "f 1/5 2/1 3/1\nf 1/1 3/-7 4/1\n");  // lines 9 and 10
    write("vn.obj", head + "f 1 2 3\nf 1//1 3//0 4//1\n");      // line 10
    auto w = expectSuccess(run(in("vt.obj") + " -q --width 8 --height 8 --spp 1" + out()));
    expectWarning(w, {"vt.obj", "2 face(s) with invalid texture coordinate indices", "line 9"});
    expectFiniteImage();
    w = expectSuccess(run(in("vn.obj") + " -q --width 8 --height 8 --spp 1" + out()));
    expectWarning(w, {"vn.obj", "1 face(s) with invalid normal indices", "line 10"});
    expectFiniteImage();
}

TEST_F(BadInput, ObjNonFiniteCoordinates) {
    for (const char* v : {"v nan 0 0", "v 0 -inf 0", "v 0 0 1e39", "v 1.#IND 0 0"}) {
        SCOPED_TRACE(v);
        write("nan.obj", std::string(kQuad) + v + "\nf 1 2 5\n");
        expectCleanFailure(run(in("nan.obj") + " --strict" + out()), {"nan.obj", "non-finite", "line 6"});
    }
    expectCleanFailure(run(in("nan.obj") + out()), {"nan.obj", "no faces to render"});
    // Next to a good face the bad one is dropped with a warning, and the image is finite.
    write("lamp.mtl", "newmtl lamp\nKd 0 0 0\nKe 1 1 1\n");
    write("mixed.obj", "mtllib lamp.mtl\nusemtl lamp\n" + std::string(kQuad) + "v nan 0 0\nf 1 2 7\nf 1 2 3 4\n");
    auto w = expectSuccess(run(in("mixed.obj") + " -q --width 8 --height 8 --spp 1" + out()));
    expectWarning(w, {"mixed.obj", "dropped 1 face(s)", "line 8"});
    expectFiniteImage();
}

// PLY and binary STL faces on a NaN or infinite vertex are dropped with a
// warning naming the file, as OBJ's are; --strict makes that an error; and a
// file of such faces only says so, not that it has no triangles.
TEST_F(BadInput, PlyAndStlNonFiniteVerticesWarnAndFailUnderStrict) {
    auto ply = [](int faces, const std::string& body) {
        return "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
               "element face " + std::to_string(faces) + "\nproperty list uchar int vertex_indices\nend_header\n"
               "-1 -1 0\n1 -1 0\nnan 1 0\n-1 1 0\n" + body;
    };
    write("one.ply", ply(1, "3 0 1 2\n"));
    expectCleanFailure(run(in("one.ply") + out()), {"one.ply", "all 1 face(s) were dropped", "non-finite"});
    write("two.ply", ply(2, "3 0 1 2\n3 0 1 3\n"));
    auto w = expectSuccess(run(in("two.ply") + " -q --width 8 --height 8 --spp 1" + out()));
    expectWarning(w, {"two.ply", "dropped 1 face(s)", "non-finite"});
    expectFiniteImage();
    expectCleanFailure(run(in("two.ply") + " --strict" + out()), {"two.ply", "1 face(s)", "non-finite"});

    std::string stl(80, ' ');
    stl += std::string("\x02\0\0\0", 4);
    const float inf = INFINITY;
    const float facets[2][12] = {{0, 0, 1, -1, -1, 0, 1, -1, 0, -1, 1, 0}, {0, 0, 1, -1, -1, 0, 1, -1, 0, inf, 1, 0}};
    for (const auto& f : facets) {
        stl.append(reinterpret_cast<const char*>(f), sizeof f);
        stl += std::string(2, '\0');
    }
    write("inf.stl", stl);
    w = expectSuccess(run(in("inf.stl") + " -q --width 8 --height 8 --spp 1" + out()));
    expectWarning(w, {"inf.stl", "dropped 1 face(s)", "non-finite"});
    expectCleanFailure(run(in("inf.stl") + " --strict" + out()), {"inf.stl", "1 face(s)", "non-finite"});
}

// Nesting that would overflow Assimp's stack (here a COLLADA node tree) fails
// cleanly, naming the file.
TEST_F(BadInput, DeeplyNestedModelFilesFailCleanly) {
    std::string nodes;
    for (int i = 0; i < 10000; ++i) nodes += "<node>";
    for (int i = 0; i < 10000; ++i) nodes += "</node>";
    write("deep.dae", R"(<?xml version="1.0"?><COLLADA version="1.4.1"><library_visual_scenes><visual_scene id="s">)" +
                          nodes + R"(</visual_scene></library_visual_scenes></COLLADA>)");
    expectCleanFailure(run(in("deep.dae") + out()), {"deep.dae", "nest deeper than 256"});
}

// A JSON file whose nested prototypes would copy 2^41 triangles fails quickly,
// naming the file and the count, instead of running out of memory.
TEST_F(BadInput, ExpansionBombFailsCleanlyAndQuickly) {
    std::string prototypes = R"({"name": "p0", "shapes": [{"type": "mesh", "vertices": [[0,0,0],[1,0,0],[0,1,0]], "indices": [0,1,2]}]})";
    for (int i = 1; i <= 40; ++i) {
        const std::string below = "\"p" + std::to_string(i - 1) + "\"";
        prototypes += ", {\"name\": \"p" + std::to_string(i) + "\", \"shapes\": [{\"type\": \"instance\", \"prototype\": " +
                      below + "}, {\"type\": \"instance\", \"prototype\": " + below + "}]}";
    }
    write("bomb.json", "{\"prototypes\": [" + prototypes + "], \"shapes\": [{\"type\": \"instance\", \"prototype\": \"p40\"}]}");
    const RunResult r = run(in("bomb.json") + out());
    expectCleanFailure(r, {"bomb.json", "2199023255550 triangles"});
    EXPECT_LT(r.seconds, 10.0);
}

TEST_F(BadInput, ObjMalformedNumbers) {
    // A coordinate that is not a number drops its faces (strict: an error naming the face's line).
    write("num.obj", "v 1.0.0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    expectCleanFailure(run(in("num.obj") + " --strict" + out()), {"num.obj", "line 4"});
    // In a material library a malformed number reads as 0, with a warning naming the line.
    write("num.mtl", "newmtl lamp\nKd 0 0 0\nKe 1 x 1\n");
    write("mtlnum.obj", "mtllib num.mtl\n" + std::string(kQuad) + "usemtl lamp\nf 1 2 3 4\n");
    auto w = expectSuccess(run(in("mtlnum.obj") + " -q --width 8 --height 8 --spp 1" + out()));
    expectWarning(w, {"num.mtl", "malformed", "line 3: 'x' in Ke"});
    ImageData img = expectFiniteImage();
    EXPECT_EQ(img.at(4, 4, 0), 1.f);
    EXPECT_EQ(img.at(4, 4, 1), 0.f);  // the malformed green read as 0
    EXPECT_EQ(img.at(4, 4, 2), 1.f);
}

TEST_F(BadInput, ObjDegenerateFaces) {
    write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 1 4\nf 4 4 4\n");
    expectCleanFailure(run(in("flat.obj") + out()), {"flat.obj", "no faces to render", "degenerate"});

    // A zero-area emitter next to a lit-by-nothing floor: no light comes from it
    // (a black --env keeps the default light of unlit scenes away; it is the one light).
    write("lamp.mtl", "newmtl lamp\nKd 0 0 0\nKe 1000 1000 1000\nnewmtl floor\nKd 0.8 0.8 0.8\n");
    write("dark.obj", "mtllib lamp.mtl\n" + std::string(kQuad) +
                          "v 0 0 1\nv 0.5 0 1\nv 1 0 1\n"
                          "usemtl floor\nf 1 2 3 4\nusemtl lamp\nf 5 6 7\nf 5 5 6\n");
    expectSuccess(run(in("dark.obj") + " -q --env 0,0,0 --width 8 --height 8 --spp 2 --stats-json " + in("stats.json") +
                      out()));
    ImageData img = expectFiniteImage();
    for (float v : img.pixels) ASSERT_EQ(v, 0.f);
    EXPECT_EQ(stats()["lights"].get<int>(), 1);
    EXPECT_EQ(stats()["triangles"].get<int>(), 2);
}

TEST_F(BadInput, ObjMissingMalformedOrUnknownMaterials) {
    // Missing library: the default material is used.
    write("nomtl.obj", "mtllib nothere.mtl\n" + std::string(kQuad) + "usemtl red\nf 1 2 3 4\n");
    auto w = expectSuccess(run(in("nomtl.obj") + " -q --width 8 --height 8 --spp 1" + out()));
    expectWarning(w, {"nothere.mtl", "not found"});
    expectFiniteImage();
    // A library that is a directory is skipped, and the warning says what it is (issue 13 item 10).
    fs::create_directories(dir_ / "dir.mtl");
    write("dirmtl.obj", "mtllib dir.mtl\n" + std::string(kQuad) + "f 1 2 3 4\n");
    w = expectSuccess(run(in("dirmtl.obj") + " -q --width 8 --height 8 --spp 1" + out()));
    expectWarning(w, {"dir.mtl", "is a directory"});
    // Malformed statements, an unknown key, an unknown illum and an unknown material name.
    write("odd.mtl", "newmtl red\nKd 1 0 0\nKs -1 nan 1e99\nNs abc\nillum 77\nfoo bar\n");
    write("odd.obj", "mtllib odd.mtl\n" + std::string(kQuad) + "usemtl red\nf 1 2 3\nusemtl blue\nf 1 3 4\n");
    w = expectSuccess(run(in("odd.obj") + " -q --width 8 --height 8 --spp 1" + out()));
    expectWarning(w, {"odd.mtl", "malformed or non-finite number", "line 3"});
    expectWarning(w, {"odd.mtl", "negative or non-finite values replaced by 0"});
    expectWarning(w, {"odd.mtl", "unknown MTL key 'foo'"});
    expectWarning(w, {"unknown illum model", "77"});
    expectWarning(w, {"odd.obj", "blue", "not found"});
    expectFiniteImage();
}

TEST_F(BadInput, AbsurdColoursGiveFinitePixels) {
    // Emitters at the edge of the float range, seen directly, through a mirror
    // and as lights on a glossy floor, with both light selections: every pixel
    // (and AOV) stays finite; overflowing samples are dropped, not written.
    write("hot.mtl",
          "newmtl hot\nKd 0 0 0\nKe 1e38 1e38 1e38\n"
          "newmtl floor\nKd 0.8 0.8 0.8\nKs 0.5 0.5 0.5\nNs 1e30\n"
          "newmtl mirror\nKd 0 0 0\nKs 1 1 1\nillum 3\n"
          "newmtl negative\nKd -1 -2 -3\nKa -1 0 0\n");
    write("hot.obj",
          "mtllib hot.mtl\n"
          "v -100 0 -100\nv 100 0 -100\nv 100 0 100\nv -100 0 100\n"
          "v -100 5 -100\nv 100 5 -100\nv 100 5 100\nv -100 5 100\n"
          "v -1 0 -1.5\nv 1 0 -1.5\nv 1 2 -1.5\nv -1 2 -1.5\n"
          "v -0.2 1 0\nv 0.2 1 0\nv 0 1.2 0\n"
          "usemtl floor\nf 1 4 3 2\nusemtl hot\nf 5 6 7 8\nf 5 6 7 8\nusemtl mirror\nf 9 10 11 12\n"
          "usemtl negative\nf 13 14 15\n");
    for (const char* selection : {"all", "power"}) {
        SCOPED_TRACE(selection);
        auto w = expectSuccess(run(in("hot.obj") + " -q --aovs --width 24 --height 24 --spp 4 --eye 0,2.5,3 " +
                                           "--look-at 0,1,0 --ambient 1e38,1e38,1e38 --light-selection " + selection +
                                           " --stats-json " + in("stats.json") + out()));
        expectWarning(w, {"hot.mtl", "negative", "replaced by 0"});
        ImageData img = expectFiniteImage();
        EXPECT_EQ(img.channels, 10);
        float peak = 0.f;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) peak = std::max(peak, img.at(x, y, 0));
        EXPECT_GT(peak, 1e37f) << "the emitter is seen";
    }
    // The same through a JSON scene, in every output format.
    write("hot.json", R"({
      "camera": {"eye": [0, 1, 4], "look_at": [0, 0.5, 0]},
      "materials": {"hot": {"kd": 0, "ke": 3.4e38}, "floor": {"kd": 0.8, "ks": 0.2, "n": 1e30},
                    "mirror": {"kd": 0, "kr": 1}},
      "ambient": 3e38,
      "shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"},
                 {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": "mirror"},
                 {"type": "rectangle", "p0": [-1, 2, -1], "a": [2, 0, 0], "b": [0, 0, 2], "material": "hot"}],
      "lights": [{"type": "point", "position": [0, 3, 0], "intensity": 3e38}]
    })");
    for (const char* name : {"j.exr", "j.pfm", "j.png"}) {
        SCOPED_TRACE(name);
        expectSuccess(run(in("hot.json") + " -q --width 16 --height 12 --spp 2" + out(name)));
        expectFiniteImage(name);
    }
}

TEST_F(BadInput, MissingOrCorruptTexturesRenderWithoutThem) {
    write("tex.mtl",
          "newmtl missing\nKd 0.5 0.5 0.5\nmap_Kd missing.png\n"
          "newmtl corrupt\nKd 0.5 0.5 0.5\nmap_Kd corrupt.png\n"
          "newmtl empty\nKd 0.5 0.5 0.5\nmap_Kd empty.png\n");
    write("corrupt.png", garbage(500, 7));
    write("empty.png", "");
    write("tex.obj", "mtllib tex.mtl\n" + std::string(kQuad) +
                         "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                         "usemtl missing\nf 1/1 2/2 3/3\nusemtl corrupt\nf 1/1 3/3 4/4\nusemtl empty\nf 1 2 4\n");
    auto w = expectSuccess(run(in("tex.obj") + " -q --width 8 --height 8 --spp 1 --ambient 1,1,1" + out()));
    expectWarning(w, {"missing.png", "not found"});
    expectWarning(w, {"corrupt.png", "cannot read texture"});
    expectWarning(w, {"empty.png", "cannot read texture"});
    expectFiniteImage();
    // JSON: a missing texture is a warning, an error in strict mode.
    write("tex.json", R"({"materials": {"t": {"texture": "missing.png"}},
                          "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "t"}]})");
    w = expectSuccess(run(in("tex.json") + " -q --width 8 --height 8 --spp 1" + out()));
    expectWarning(w, {"tex.json", "/materials/t/texture", "not found"});
    expectCleanFailure(run(in("tex.json") + " --strict" + out()), {"tex.json", "/materials/t/texture", "not found"});
}

TEST_F(BadInput, TextureWithAnAbsurdSizeInItsHeader) {
    // A PPM header that claims 100000 x 100000 pixels over a few bytes of data.
    write("huge.ppm", "P6\n100000 100000\n255\nabc");
    write("tex.mtl", "newmtl t\nKd 0.5 0.5 0.5\nmap_Kd huge.ppm\n");
    write("tex.obj", "mtllib tex.mtl\n" + std::string(kQuad) + "vt 0 0\nvt 1 0\nvt 1 1\nusemtl t\nf 1/1 2/2 3/3\n");
    RunResult r = run(in("tex.obj") + " -q --width 8 --height 8 --spp 1" + out());
    // Either the texture is skipped with a warning, or the scene is refused with a message naming it.
    if (r.exitCode == 0) {
        expectWarning(expectSuccess(r), {"huge.ppm"});
        expectFiniteImage();
    } else {
        expectCleanFailure(r, {"tex.obj", "out of memory"});
    }
}

// ------------------------------------------------------------------ JSON

TEST_F(BadInput, JsonSyntaxErrorsGiveLineAndColumn) {
    struct Case {
        const char* text;
        const char* where;
    } cases[] = {
        {"{\n  \"camera\": {\"eye\": [0, 1, 4],\n  \"fov\": 40\n}\n", "bad.json:5:1"},  // unclosed object
        {"{\n  \"ambient\": 0.1,\n}\n", "bad.json:3:1"},                               // trailing comma
        {"{\n  \"ambient\": [0.1 0.2 0.3]\n}\n", "bad.json:2:21"},                    // missing commas (the column ends the token)
        {"{\n  \"ambient\": 01\n}\n", "bad.json:2:15"},                               // leading zero
        {"{\"a\": \"\n\"}", "bad.json:1:8"},                                           // raw newline in a string
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.text);
        write("bad.json", c.text);
        expectCleanFailure(run(in("bad.json") + out()), {c.where, "JSON syntax error"});
    }
}

TEST_F(BadInput, JsonWrongTypes) {
    struct Case {
        const char* text;
        const char* pointer;
        const char* problem;
    } cases[] = {
        {R"({"camera": {"fov": "wide"}})", "/camera/fov", "expected a number, got a string"},
        {R"({"shapes": {"type": "sphere"}})", "/shapes", "expected an array"},
        {R"({"shapes": [{"type": "sphere", "center": [0, 0], "radius": 1}]})", "/shapes/0/center", "3 numbers"},
        {R"({"render": {"spp": 2.5}})", "/render/spp", "expected an integer"},
        {R"({"materials": {"m": {"two_sided": 1}}})", "/materials/m/two_sided", "true or false"},
        {R"([1, 2, 3])", "top level", "must be a JSON object"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.text);
        write("types.json", c.text);
        expectCleanFailure(run(in("types.json") + out()), {"types.json", c.pointer, c.problem});
    }
}

TEST_F(BadInput, JsonUnknownKeys) {
    struct Case {
        const char* text;
        const char* pointer;
    } cases[] = {
        {R"({"colour": 1})", "/colour"},
        {R"({"camera": {"eye": [0, 1, 4], "zoom": 2}})", "/camera/zoom"},
        {R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "radius2": 1}]})", "/shapes/0/radius2"},
        {"{\"line\\nbreak\": 1}", "/line?break"},  // a control character stays out of the one-line message
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.text);
        write("keys.json", c.text);
        expectCleanFailure(run(in("keys.json") + out()), {"keys.json", c.pointer, "unknown key"});
    }
    write("dup.json", R"({"ambient": 1, "ambient": 2})");
    expectCleanFailure(run(in("dup.json") + out()), {"dup.json", "/ambient", "duplicate key"});
}

TEST_F(BadInput, JsonOutOfRangeValues) {
    struct Case {
        const char* text;
        const char* where;
        const char* problem;
    } cases[] = {
        {R"({"render": {"width": -4}})", "/render/width", "must be in [1, 65536]"},
        {R"({"render": {"spp": 1e10}})", "/render/spp", "must be in [1, 1048576]"},
        {R"({"render": {"threads": -2}})", "/render/threads", "must be in [0, 4096]"},
        {R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": -1}]})", "/shapes/0/radius", "must be > 0"},
        {R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1e39}]})", "/shapes/0/radius", "finite"},
        {R"({"materials": {"a": {"kd": [1, -1, 0]}}})", "/materials/a/kd/1", "must be >= 0"},
        {R"({"camera": {"fov": 180}})", "/camera/fov", "(0, 180)"},
        {R"({"camera": {"eye": [0, 0, 0], "look_at": [0, 0, 0]}})", "/camera", "same point"},
        {R"({"shapes": [{"type": "mesh", "vertices": [0,0,0, 1,0,0, 0,1,0], "indices": [0, 1, 5]}]})",
         "/shapes/0/indices/2", "out of range"},
        {R"({"shapes": [{"type": "box", "min": [0, 0, 0], "max": [1, 0, 1]}]})", "/shapes/0/max", "greater"},
        {R"({"ambient": 1e999})", "range.json:1:13", "out of range"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.text);
        write("range.json", c.text);
        expectCleanFailure(run(in("range.json") + out()), {"range.json", c.where, c.problem});
    }
}

// ------------------------------------------------------------------ options

class BadOption : public BadInput {
protected:
    void SetUp() override {
        BadInput::SetUp();
        write("lamp.mtl", "newmtl lamp\nKd 0 0 0\nKe 1 1 1\n");
        write("scene.obj", "mtllib lamp.mtl\nusemtl lamp\n" + std::string(kQuad) + "f 1 2 3 4\n");
    }
    /// A bad option value is a usage error: exit code 2 unless said otherwise.
    void expectRefused(const std::string& options, std::initializer_list<std::string> needles, int exitCode = 2) {
        SCOPED_TRACE(options);
        expectCleanFailure(run(in("scene.obj") + " " + options + out()), needles, exitCode);
    }
};

TEST_F(BadOption, ZeroOrNegativeSizes) {
    expectRefused("--width 0", {"width must be in [1, 65536], got 0"});
    expectRefused("--height -3", {"height must be in [1, 65536], got -3"});
    expectRefused("--width 70000", {"width must be in [1, 65536], got 70000"});
    expectRefused("--tile-size 0", {"tile size"});
    expectRefused("--width 99999999999", {"--width"}, 2);  // not even an int
    expectRefused("--width abc", {"--width"}, 2);
}

TEST_F(BadOption, FramebufferTooBigForMemoryIsRefusedBeforeAllocating) {
    // With the address space capped at 4 GiB, an attempt to allocate the
    // 200 GiB framebuffer would fail differently; the check comes first.
#ifdef PENUMBRA_TEST_ASAN
    const std::string cap;  // AddressSanitizer reserves terabytes of address space up front
#else
    const std::string cap = "ulimit -v 4194304; ";
#endif
    RunResult r = run(in("scene.obj") + " --width 65536 --height 65536 --aovs" + out(), cap);
    expectCleanFailure(r, {"65536x65536", "MiB", "more than half of this machine's memory"});
    EXPECT_LT(r.seconds, 20.0);
    // A crop of a huge frame needs only the crop's memory.
    expectSuccess(run(in("scene.obj") + " -q --width 65536 --height 65536 --crop 32768,32768,32776,32776 " +
                                  "--spp 1 --eye 0,0,3 --look-at 0,0,0 --fov 1" + out(),
                              cap));
    ImageData img = expectFiniteImage();
    EXPECT_EQ(img.width, 8);
    EXPECT_EQ(img.at(4, 4, 0), 1.f);
}

TEST_F(BadOption, SamplesDepthAndThreads) {
    expectRefused("--spp 0", {"spp must be in [1, 1048576], got 0"});
    expectRefused("--spp -1", {"spp must be in"});
    expectRefused("--light-samples 0", {"light samples must be in"});
    expectRefused("--max-depth -1", {"max depth must be in"});
    expectRefused("--threads -1", {"threads must be >= 0"});
    expectRefused("--seed -1", {"--seed", "must be >= 0"}, 2);
}

TEST_F(BadOption, Camera) {
    expectRefused("--eye 0,1,3 --look-at 0,1,3", {"eye and look-at are the same point"});
    expectRefused("--eye 0,1,3 --look-at 0,1,0 --up 0,0,1", {"up vector is parallel to the view direction"});
    expectRefused("--up 0,0,0", {"up vector is zero"});
    for (const char* fov : {"0", "-10", "180", "nan"}) expectRefused(std::string("--fov ") + fov, {"fov must lie in (0, 180)"});
    expectRefused("--aperture -1", {"aperture"});
    expectRefused("--eye nan,0,0", {"--eye", "not a finite number"});
    expectRefused("--eye 1e39,0,0", {"must be finite"});
    expectRefused("--eye 1,2", {"--eye", "expected x,y,z"});
}

TEST_F(BadOption, AcceleratorAndFormats) {
    expectRefused("--accel kdtree", {"--accel", "unknown accelerator 'kdtree'"});
    expectRefused("--build-quality ultra", {"--build-quality"});
    expectRefused("--light-selection random", {"--light-selection"});
    expectRefused("--integrator bdpt", {"--integrator", "expected whitted or path, got 'bdpt'"});
    SCOPED_TRACE("output formats");
    expectCleanFailure(run(in("scene.obj") + " -o " + shellQuote((out_ / "x.bmp").string())),
                       {"x.bmp", "unknown image format '.bmp'"}, 2);
    expectCleanFailure(run(in("scene.obj") + " -o " + shellQuote((out_ / "noextension").string())),
                       {"noextension", "unknown image format"}, 2);
    expectCleanFailure(run(in("scene.obj")), {"--output", "required"}, 2);
}

TEST_F(BadOption, UnwritableOutput) {
    // Below a regular file: no folder there, whoever runs the test.
    expectCleanFailure(run(in("scene.obj") + " -o /etc/passwd/x.png"), {"/etc/passwd/x.png", "cannot write image"});
    // A directory where the image should go.
    fs::create_directories(dir_ / "taken.exr");
    RunResult r = run(in("scene.obj") + " -o " + shellQuote((dir_ / "taken.exr").string()));
    expectCleanFailure(r, {"taken.exr", "is a directory"});
    EXPECT_TRUE(fs::is_empty(dir_ / "taken.exr"));
    if (::geteuid() != 0) {
        fs::permissions(out_, fs::perms::owner_read | fs::perms::owner_exec);
        expectRefused("", {"img.exr", "not writable"}, 1);
        fs::permissions(out_, fs::perms::owner_all);
    }
}

// ------------------------------------------------------------------ numerics and memory

TEST_F(BadInput, FacingMirrorsWithAHugeDepthFinish) {
    // Two parallel perfect mirrors and a camera looking straight between them:
    // every ray bounces max-depth times. The integrator is a loop, so 100000
    // bounces need no stack (1 MiB is plenty) and finish quickly.
    write("mirrors.json", R"({
      "camera": {"eye": [0, 0, 0.5], "look_at": [0, 0, -1], "up": [0, 1, 0], "fov": 0.001},
      "materials": {"mirror": {"kd": 0.1, "kr": 1}},
      "shapes": [{"type": "rectangle", "p0": [-10, -10, -1], "a": [20, 0, 0], "b": [0, 20, 0], "material": "mirror"},
                 {"type": "rectangle", "p0": [-10, -10, 1], "a": [0, 20, 0], "b": [20, 0, 0], "material": "mirror"}],
      "lights": [{"type": "point", "position": [0.5, 0.5, 0], "intensity": 1}]
    })");
    RunResult r = run(in("mirrors.json") + " -q --width 4 --height 4 --spp 1 --max-depth 100000 --stats-json " +
                                  in("stats.json") + out(),
                              "ulimit -s 1024; ");
    expectSuccess(r);
    EXPECT_LT(r.seconds, 120.0);
    EXPECT_EQ(stats()["rays"]["reflection"].get<uint64_t>(), 16u * 100000u);
    EXPECT_EQ(stats()["nonfinite_samples_dropped"].get<uint64_t>(), 0u);
    ImageData img = expectFiniteImage();
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) EXPECT_GT(img.at(x, y, 0), 1.f) << "each bounce adds the lamp's light";
}

TEST_F(BadInput, OutOfMemoryIsACleanError) {
#ifdef PENUMBRA_TEST_ASAN
    GTEST_SKIP() << "AddressSanitizer cannot run under an address-space limit";
#else
    // 2 GiB of address space cannot hold a 12000 x 12000 film (3.2 GiB): the
    // allocation fails with std::bad_alloc, which becomes a one-line error.
    write("lamp.mtl", "newmtl lamp\nKd 0 0 0\nKe 1 1 1\n");
    write("scene.obj", "mtllib lamp.mtl\nusemtl lamp\n" + std::string(kQuad) + "f 1 2 3 4\n");
    expectCleanFailure(run(in("scene.obj") + " -q --width 12000 --height 12000 --spp 1" + out(), "ulimit -v 2097152; "),
                       {"out of memory while rendering a 12000x12000 image"});
#endif
}

TEST_F(BadInput, AcceleratorErrorsNameTheSceneFile) {
    // Embree reports out of memory for this device configuration (read from
    // PENUMBRA_EMBREE_CONFIG when the BVH is built): the error names the scene.
    write("lamp.mtl", "newmtl lamp\nKd 0 0 0\nKe 1 1 1\n");
    write("scene.obj", "mtllib lamp.mtl\nusemtl lamp\n" + std::string(kQuad) + "f 1 2 3 4\n");
    expectCleanFailure(run(in("scene.obj") + " -q --width 8 --height 8 --spp 1" + out(),
                           "PENUMBRA_EMBREE_CONFIG=tessellation_cache_size=-1 "),
                       {(dir_ / "scene.obj").string() + ": Embree error during rtcNewDevice: out of memory"});
}

// ------------------------------------------------------------------ outputs over inputs (issue 13, item 5)

std::string slurpFile(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

TEST_F(BadOption, OutputsThatWouldOverwriteAnInputAreRefusedBeforeAnyWork) {
    // A textured quad: tex.obj reads tex.mtl, which reads tex.png (a real image, rendered here).
    ASSERT_EQ(runPenumbra(in("scene.obj") + " -q --width 4 --height 4 --spp 1 -o " + in("tex.png")).exitCode, 0);
    write("tex.mtl", "newmtl t\nKd 1 1 1\nmap_Kd tex.png\n");
    write("tex.obj", "mtllib tex.mtl\nusemtl t\n" + std::string(kQuad) + "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n");
    write("lamp.json", R"({"materials": {"lamp": {"kd": 0, "ke": 1}},
                           "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "lamp"}]})");
    fs::create_hard_link(dir_ / "scene.obj", dir_ / "linked.json");
    fs::create_symlink(dir_ / "tex.png", dir_ / "alias.png");
    const std::string before[] = {slurpFile(dir_ / "scene.obj"), slurpFile(dir_ / "tex.png"),
                                  slurpFile(dir_ / "tex.mtl"), slurpFile(dir_ / "lamp.json")};
    const std::string quick = " -q --width 8 --height 8 --spp 1";

    // --stats-json over the scene file, also through a hard link (same inode, another name).
    expectCleanFailure(run(in("lamp.json") + quick + " --stats-json " + in("lamp.json") + out()),
                       {"--stats-json", "lamp.json", "the scene file", "refusing to overwrite an input"});
    expectCleanFailure(run(in("scene.obj") + quick + " --stats-json " + in("linked.json") + out()),
                       {"--stats-json", "linked.json", "the scene file", "refusing to overwrite an input"});
    // --stats-json over the -o image.
    expectCleanFailure(run(in("scene.obj") + quick + " --stats-json " + shellQuote(outPath().string()) + out()),
                       {"--stats-json", "img.exr", "-o"});
    // -o over the scene's texture (directly and through a symlink), --stats-json over its MTL file.
    expectCleanFailure(run(in("tex.obj") + quick + " -o " + in("tex.png")),
                       {"-o", "tex.png", "a file the scene reads", "refusing to overwrite an input"});
    expectCleanFailure(run(in("tex.obj") + quick + " -o " + in("alias.png")),
                       {"-o", "alias.png", "a file the scene reads"});
    expectCleanFailure(run(in("tex.obj") + quick + " --stats-json " + in("tex.mtl") + out()),
                       {"--stats-json", "tex.mtl", "a file the scene reads"});
    EXPECT_EQ(slurpFile(dir_ / "scene.obj"), before[0]);
    EXPECT_EQ(slurpFile(dir_ / "tex.png"), before[1]);
    EXPECT_EQ(slurpFile(dir_ / "tex.mtl"), before[2]);
    EXPECT_EQ(slurpFile(dir_ / "lamp.json"), before[3]);
    // Different files with the same name in other folders are fine.
    fs::create_directories(dir_ / "other");
    expectSuccess(run(in("tex.obj") + quick + " -o " + in("other/tex.png")));
}

TEST_F(BadOption, AFailedStatisticsWriteIsAnErrorAndLeavesNoImage) {
    if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
    RunResult r = run(in("scene.obj") + " -q --width 8 --height 8 --spp 1 --stats-json /dev/full" + out());
    // One error line naming the file, exit code 1, and no image: the run reports failure, so it leaves no output.
    expectCleanFailure(r, {"/dev/full: cannot write statistics"});
}

TEST_F(BadOption, AFailedImageWriteLeavesNoStatistics) {
    // A 64x64 PFM (48 KiB) over an 8 KiB file-size limit (dash counts 512-byte
    // blocks); the statistics (about 1 KiB) fit, and are staged before the image.
    RunResult r = run(in("scene.obj") + " -q --width 64 --height 64 --spp 1 --stats-json " +
                          shellQuote(outPath("stats.json").string()) + out("img.pfm"),
                      "ulimit -f 16; ");
    expectCleanFailure(r, {"img.pfm", "file size limit"});
}

// ------------------------------------------------------------------ command-line values (issue 13, item 9)

TEST_F(BadOption, AmbientAndBackgroundAreHeldToTheSceneFilesLimits) {
    // The JSON loader refuses a radiance that is not finite as a 32-bit float; so does the command line.
    write("hot.json", R"({"ambient": [1e39, 0, 0], "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1}]})");
    expectCleanFailure(run(in("hot.json") + out()), {"hot.json", "/ambient/0", "finite"});
    expectRefused("--ambient 1e39,0,0", {"--ambient", "finite"});
    expectRefused("--background 0,1e39,0", {"--background", "finite"});
    expectRefused("--ambient -1,0,0", {"--ambient", ">= 0"});
    // The largest finite values pass, on the command line as in a file.
    expectSuccess(run(in("scene.obj") + " -q --width 4 --height 4 --spp 1 --ambient 3e38,0,0" + out()));
}

TEST_F(BadOption, SeedAboveTheLargestIsAUsageError) {
    expectRefused("--seed 18446744073709551616", {"--seed", "18446744073709551615"}, 2);
    expectRefused("--seed 99999999999999999999999", {"--seed", "above the largest seed"}, 2);
    expectSuccess(run(in("scene.obj") + " -q --width 4 --height 4 --spp 1 --seed 18446744073709551615" + out()));
}

}  // namespace
