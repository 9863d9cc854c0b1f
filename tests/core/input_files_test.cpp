// Inputs opened once, by descriptor, after the path check (issue 13 items 3, 8,
// 10): what is not a regular file is refused with its reason, never blocked on
// or read without end; a symlink that flips between an inside and an outside
// file cannot lead outside; textures reach the texture side as open files.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <iostream>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "core/error.h"
#include "core/io/input_file.h"
#include "core/io/scene_loader.h"
#include "support/test_support.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using test::tempDir;
using test::writeFile;

struct Warnings {
    std::vector<std::string> lines;
    Logger logger{[this](LogLevel level, std::string_view msg) {
                      if (level >= LogLevel::Warning) lines.emplace_back(msg);
                  },
                  LogLevel::Debug};
    bool any(std::initializer_list<std::string_view> needles) const {
        for (const auto& l : lines) {
            bool all = true;
            for (auto n : needles) all = all && l.find(n) != std::string::npos;
            if (all) return true;
        }
        return false;
    }
};

/// The error `f` throws (or an Internal "no error").
template <class F>
Error errorOf(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e;
    }
    return Error(ErrorCode::Internal, "no error");
}

void expectHas(const std::string& msg, std::initializer_list<std::string_view> needles) {
    for (auto n : needles) EXPECT_NE(msg.find(n), std::string::npos) << "'" << n << "' not in: " << msg;
}

fs::path makeFifo(const fs::path& p) {
    EXPECT_EQ(::mkfifo(p.c_str(), 0600), 0) << p;
    return p;
}

constexpr const char* kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
constexpr const char* kSquare = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";

std::string meshScene(const std::string& file) {
    return R"({"shapes": [{"type": "mesh", "file": ")" + file + R"("}]})";
}

// ---------------------------------------------------------------- not regular files

TEST(InputFiles, FifoSceneIsRefusedWithoutBlocking) {
    fs::path dir = tempDir();
    const auto t0 = std::chrono::steady_clock::now();
    for (const char* name : {"scene.json", "scene.obj"}) {
        fs::path p = makeFifo(dir / name);
        Error e = errorOf([&] { loadScene(p, {}, Logger()); });
        EXPECT_NE(e.code(), ErrorCode::Internal) << name;
        expectHas(e.what(), {name, "is not a regular file", "FIFO"});
    }
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
}

TEST(InputFiles, DevZeroIsRefused) {
    fs::path dir = tempDir();
    fs::create_symlink("/dev/zero", dir / "zero.json");
    fs::create_symlink("/dev/zero", dir / "zero.obj");
    expectHas(errorOf([&] { loadScene(dir / "zero.json", {}, Logger()); }).what(),
              {"zero.json", "is not a regular file", "character device"});
    expectHas(errorOf([&] { loadScene(dir / "zero.obj", {}, Logger()); }).what(),
              {"zero.obj", "is not a regular file", "character device"});
}

TEST(InputFiles, SceneSymlinkLoopSaysSo) {
    fs::path dir = tempDir();
    fs::create_symlink(dir / "b.json", dir / "a.json");
    fs::create_symlink(dir / "a.json", dir / "b.json");
    Error e = errorOf([&] { loadScene(dir / "a.json", {}, Logger()); });
    EXPECT_EQ(e.code(), ErrorCode::IoError);
    expectHas(e.what(), {"a.json", "symlink loop"});
}

TEST(InputFiles, MeshThatIsNotARegularFileGetsItsReason) {
    fs::path dir = tempDir();
    makeFifo(dir / "fifo.obj");
    fs::create_directories(dir / "folder.obj");
    fs::create_symlink(dir / "loop2.obj", dir / "loop1.obj");
    fs::create_symlink(dir / "loop1.obj", dir / "loop2.obj");
    fs::create_symlink("/dev/zero", dir / "zero.obj");
    struct Case {
        const char* file;
        const char* reason;
    };
    for (const Case& c : {Case{"fifo.obj", "it is a FIFO"}, Case{"folder.obj", "it is a directory"},
                          Case{"loop1.obj", "symlink loop"}, Case{"zero.obj", "it is a character device"}}) {
        fs::path scene = writeFile(dir / "scene.json", meshScene(c.file));
        Error e = errorOf([&] { loadScene(scene, {}, Logger()); });
        expectHas(e.what(), {"scene.json", "/shapes/0/file", c.file, c.reason});
        EXPECT_EQ(std::string(e.what()).find("not found"), std::string::npos) << e.what();
    }
}

TEST(InputFiles, MtlAndTexturesThatAreNotRegularFilesGetTheirReason) {
    fs::path dir = tempDir();
    makeFifo(dir / "fifo.mtl");
    makeFifo(dir / "fifo.png");
    fs::create_directories(dir / "folder.png");
    writeFile(dir / "tex.mtl", "newmtl a\nKd 1 1 1\nmap_Kd fifo.png\nnewmtl b\nKd 1 1 1\nmap_Kd folder.png\n");
    fs::path obj = writeFile(dir / "a.obj", std::string("mtllib fifo.mtl\nmtllib tex.mtl\n") +
                                                "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl a\nf 1/1 2/1 3/1\n"
                                                "usemtl b\nf 1/1 3/1 2/1\n");
    Warnings log;
    LoadedScene s = loadScene(obj, {}, log.logger);
    EXPECT_EQ(s.scene.textures.size(), 0u);
    EXPECT_TRUE(log.any({"fifo.mtl", "is not a regular file", "FIFO"}));
    EXPECT_TRUE(log.any({"fifo.png", "is not a regular file", "FIFO"}));
    EXPECT_TRUE(log.any({"folder.png", "is not a regular file", "directory"}));
    EXPECT_FALSE(log.any({"not found"}));

    // JSON: the same reason, a warning (an error in strict mode).
    fs::path json = writeFile(dir / "t.json", R"({"materials": {"t": {"texture": "fifo.png"}},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "t"}]})");
    Warnings jlog;
    EXPECT_NO_THROW(loadScene(json, {}, jlog.logger));
    EXPECT_TRUE(jlog.any({"/materials/t/texture", "fifo.png", "is not a regular file"}));
    LoadOptions strict;
    strict.strict = true;
    expectHas(errorOf([&] { loadScene(json, strict, Logger()); }).what(), {"fifo.png", "is not a regular file"});
}

// ---------------------------------------------------------------- one open, by descriptor

TEST(InputFiles, SymlinkFlippingBetweenInsideAndOutsideNeverReadsOutside) {
    fs::path dir = tempDir();
    fs::path inside = dir / "inside";
    writeFile(inside / "real.obj", kTriangle);   // 1 triangle
    writeFile(dir / "outside" / "secret.obj", kSquare);  // 2 triangles: must never be read
    fs::path scene = writeFile(inside / "scene.json", meshScene("mesh.obj"));
    fs::path link = inside / "mesh.obj";
    fs::create_symlink(inside / "real.obj", link);
    LoadOptions options;
    options.allowedRoots = {inside};

    std::atomic<bool> stop{false};
    std::thread flipper([&] {
        // rename() over the link swaps it atomically, as an attacker would.
        fs::path tmp = inside / "mesh.tmp";
        for (bool out = true; !stop; out = !out) {
            std::error_code ec;
            fs::remove(tmp, ec);
            fs::create_symlink(out ? dir / "outside" / "secret.obj" : inside / "real.obj", tmp, ec);
            fs::rename(tmp, link, ec);
        }
    });
    int loaded = 0, refused = 0, leaked = 0;
    for (int i = 0; i < 1500; ++i) {
        try {
            LoadedScene s = loadScene(scene, options, Logger());
            ++loaded;
            if (s.scene.triangleCount() != 1) ++leaked;
        } catch (const Error& e) {
            ++refused;
            std::string msg = e.what();
            EXPECT_TRUE(msg.find("outside the allowed directories") != std::string::npos ||
                        msg.find("not found") != std::string::npos)
                << msg;
        }
    }
    stop = true;
    flipper.join();
    std::cout << "[ measured ] symlink flip: " << loaded << " loaded inside, " << refused << " refused, " << leaked
              << " read outside\n";
    EXPECT_EQ(leaked, 0) << loaded << " loaded, " << refused << " refused";
    EXPECT_GT(loaded, 0);
}

TEST(InputFiles, TexturesAreHandedOnOpenAndReadFromTheirDescriptor) {
    fs::path dir = tempDir();
    writeFile(dir / "tex.png", "first bytes");
    fs::path json = writeFile(dir / "t.json", R"({"materials": {"t": {"texture": "tex.png"}, "u": {"texture": "tex.png"}},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "t"}]})");
    LoadedScene s = loadScene(json, {}, Logger());
    ASSERT_EQ(s.scene.textures.size(), 1u);  // one file, shared by both materials
    const auto opened = [](const TextureSource& t) { return static_cast<const InputFile*>(t.file.get()); };
    ASSERT_NE(opened(s.scene.textures[0]), nullptr);
    EXPECT_EQ(s.scene.textures[0].fd, opened(s.scene.textures[0])->fd());
    // Another file renamed over the path after loading: the descriptor still reads the file checked.
    writeFile(dir / "other.png", "swapped in");
    fs::rename(dir / "other.png", dir / "tex.png");
    EXPECT_EQ(opened(s.scene.textures[0])->readAll(), "first bytes");
    EXPECT_EQ(opened(s.scene.textures[0])->path(), dir / "tex.png");

    // OBJ/MTL textures alike.
    writeFile(dir / "m.mtl", "newmtl a\nmap_Kd tex.png\n");
    fs::path obj = writeFile(dir / "m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl a\nf 1/1 2/1 3/1\n");
    LoadedScene o = loadScene(obj, {}, Logger());
    ASSERT_EQ(o.scene.textures.size(), 1u);
    ASSERT_NE(opened(o.scene.textures[0]), nullptr);
    EXPECT_EQ(opened(o.scene.textures[0])->readAll(), "swapped in");
}

TEST(InputFiles, OpenInputFileChecksTheFileItOpened) {
    fs::path dir = tempDir();
    writeFile(dir / "in" / "a.obj", kTriangle);
    writeFile(dir / "out" / "b.obj", kTriangle);
    fs::create_symlink(dir / "out" / "b.obj", dir / "in" / "link.obj");
    LoadOptions o;
    o.allowedRoots = {dir / "in"};
    EXPECT_EQ(openInputFile(dir / "in" / "a.obj", o)->readAll(), kTriangle);
    Error e = errorOf([&] { openInputFile(dir / "in" / "link.obj", o); });
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    expectHas(e.what(), {"link.obj", "outside the allowed directories"});
}

}  // namespace
}  // namespace penumbra
