// penumbra-mpi against the single-process penumbra, bit for bit; failing
// ranks; crops that oiiotool assembles into the full frame. The MPI tests
// skip when penumbra-mpi is not built (no MPI found), the oiiotool test when
// oiiotool is not installed.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <penumbra/penumbra.hpp>
#include <set>

#include "core/image_io.h"
#include "support/test_support.h"

using namespace penumbra;
namespace fs = std::filesystem;

namespace {

struct RunResult {
    int exitCode;
    std::string output;  // stdout + stderr
};

RunResult runCommand(const std::string& command) {
    FILE* p = ::popen((command + " 2>&1").c_str(), "r");
    if (!p) return {-1, "popen failed"};
    std::string out;
    std::array<char, 4096> buf{};
    size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
    const int status = ::pclose(p);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), out};
}

std::string penumbraCli() { return (test::binaryDir() / "penumbra").string(); }
std::string penumbraMpi() { return (test::binaryDir() / "penumbra-mpi").string(); }

#ifdef PENUMBRA_MPIEXEC
constexpr const char* kMpiexec = PENUMBRA_MPIEXEC;
#else
constexpr const char* kMpiexec = "";
#endif

// mpirun with what a container needs: shared memory and loopback only, no
// single-copy mechanism (ptrace is usually not allowed), root allowed when
// running as root; `timeout` so that a hang fails the test instead of holding it,
// with a KILL ten seconds later for an mpirun that does not end on TERM.
std::string mpirun(const std::string& contexts) {
    ::setenv("OMPI_MCA_btl_vader_single_copy_mechanism", "none", 1);
    // Under AddressSanitizer (the asan preset), OpenMPI's own allocations that
    // it never frees (its components, its op tables) would be reported as leaks
    // at exit; the ranks run without leak checking (later options win).
    if (const char* asan = std::getenv("ASAN_OPTIONS"); asan && std::string(asan).find("detect_leaks=0") == std::string::npos)
        ::setenv("ASAN_OPTIONS", (std::string(asan) + ":detect_leaks=0").c_str(), 1);
    std::string cmd = "timeout -k 10 120 ";
    cmd += kMpiexec;
    cmd += " --oversubscribe --mca btl self,vader";
    if (::geteuid() == 0) cmd += " --allow-run-as-root";
    return cmd + " " + contexts;
}

#define REQUIRE_MPI()                                                               \
    do {                                                                            \
        if (std::string(kMpiexec).empty() || !fs::exists(penumbraMpi()))           \
            GTEST_SKIP() << "penumbra-mpi is not built (MPI not found at configure)"; \
    } while (0)

// Floor, a shiny sphere, a mirror sphere and a rectangle light: soft shadows,
// reflections and AOVs in a few tiles.
fs::path smallScene(const fs::path& dir, const std::string& name = "small.json", float radius = 0.5f) {
    return test::writeFile(dir / name, R"({
  "camera": {"eye": [0, 1, 4], "look_at": [0, 0.5, 0], "up": [0, 1, 0], "fov": 40},
  "render": {"width": 56, "height": 40, "spp": 4, "light_samples": 2, "seed": 11},
  "materials": {
    "floor": {"kd": 0.7},
    "ball": {"kd": [0.8, 0.3, 0.2], "ks": 0.2, "n": 40},
    "mirror": {"kd": 0.1, "kr": 0.8},
    "lamp": {"kd": 0, "ke": 6}
  },
  "shapes": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"},
    {"type": "sphere", "center": [0, 0.5, 0], "radius": )" + std::to_string(radius) + R"(, "material": "ball"},
    {"type": "sphere", "center": [1.1, 0.4, -0.5], "radius": 0.4, "material": "mirror"},
    {"type": "rectangle", "p0": [-0.5, 2, -0.5], "a": [1, 0, 0], "b": [0, 0, 1], "material": "lamp"}
  ]
})");
}

std::string readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Same size, channels and pixel bits (not just equal values).
void expectSameBits(const fs::path& a, const fs::path& b) {
    const ImageData x = readImage(a), y = readImage(b);
    ASSERT_EQ(x.width, y.width);
    ASSERT_EQ(x.height, y.height);
    ASSERT_EQ(x.channelNames, y.channelNames);
    ASSERT_EQ(x.pixels.size(), y.pixels.size());
    size_t differing = 0;
    for (size_t i = 0; i < x.pixels.size(); ++i)
        if (std::memcmp(&x.pixels[i], &y.pixels[i], sizeof(float)) != 0) ++differing;
    EXPECT_EQ(differing, 0u) << a << " and " << b << " differ in " << differing << " of " << x.pixels.size() << " values";
}

size_t countOf(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

// Nothing in `dir` but `keep` (no image, no temporary file).
void expectOnly(const fs::path& dir, const std::set<std::string>& keep) {
    for (const auto& e : fs::directory_iterator(dir))
        EXPECT_TRUE(keep.count(e.path().filename().string())) << "left behind: " << e.path();
}

}  // namespace

TEST(MpiRender, ThreeRanksGiveTheSingleProcessImageBitForBit) {
    REQUIRE_MPI();
    const fs::path dir = test::tempDir();
    const fs::path scene = smallScene(dir);
    // PFM is raw floats after a fixed header: the files themselves must match.
    ASSERT_EQ(runCommand(penumbraCli() + " " + scene.string() + " -q -o " + (dir / "one.pfm").string()).exitCode, 0);
    const RunResult r = runCommand(mpirun("-np 3 " + penumbraMpi() + " " + scene.string() + " -o " + (dir / "mpi.pfm").string()));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(readBytes(dir / "one.pfm"), readBytes(dir / "mpi.pfm"));
    // Progress and summary come from rank 0 only.
    EXPECT_EQ(countOf(r.output, "penumbra-mpi: wrote"), 1u) << r.output;
    EXPECT_EQ(countOf(r.output, "100%"), 1u) << r.output;
    EXPECT_NE(r.output.find("on 3 rank(s)"), std::string::npos) << r.output;
}

TEST(MpiRender, PathIntegratorTravelsToTheWorkersAndMatchesBitForBit) {
    REQUIRE_MPI();
    const fs::path dir = test::tempDir();
    const fs::path scene = smallScene(dir);
    ASSERT_EQ(runCommand(penumbraCli() + " " + scene.string() + " -q --integrator path -o " + (dir / "one.pfm").string())
                  .exitCode,
              0);
    const RunResult r = runCommand(mpirun("-np 3 " + penumbraMpi() + " " + scene.string() +
                                          " -q --integrator path --stats-json " + (dir / "s.json").string() + " -o " +
                                          (dir / "mpi.pfm").string()));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(readBytes(dir / "one.pfm"), readBytes(dir / "mpi.pfm"));
    const std::string stats = readBytes(dir / "s.json");
    EXPECT_NE(stats.find("\"integrator\": \"path\""), std::string::npos) << stats;
    EXPECT_NE(stats.find("\"indirect\""), std::string::npos) << stats;
    EXPECT_NE(stats.find("\"path_length\""), std::string::npos) << stats;
}

TEST(MpiRender, CropWithAovsOverTwoAndThreeRanksMatchesTheSingleProcessExr) {
    REQUIRE_MPI();
    const fs::path dir = test::tempDir();
    const fs::path scene = smallScene(dir);
    const std::string opts = " -q --aovs --crop 5,3,50,37 --tile-size 8 --max-depth 3";
    ASSERT_EQ(runCommand(penumbraCli() + " " + scene.string() + opts + " -o " + (dir / "one.exr").string()).exitCode, 0);
    for (int ranks : {2, 3}) {
        const fs::path out = dir / ("mpi" + std::to_string(ranks) + ".exr");
        const RunResult r = runCommand(mpirun("-np " + std::to_string(ranks) + " " + penumbraMpi() + " " +
                                              scene.string() + opts + " -o " + out.string()));
        ASSERT_EQ(r.exitCode, 0) << r.output;
        expectSameBits(dir / "one.exr", out);
    }
}

TEST(MpiRender, RankThatCannotReadTheSceneEndsTheJobWithOneErrorAndNoImage) {
    REQUIRE_MPI();
    const fs::path dir = test::tempDir();
    const fs::path scene = smallScene(dir);
    const fs::path out = dir / "never.exr";
    // Rank 2 is given a scene its node does not have.
    const RunResult r = runCommand(mpirun("-np 2 " + penumbraMpi() + " " + scene.string() + " -o " + out.string() +
                                          " : -np 1 " + penumbraMpi() + " " + (dir / "elsewhere.json").string() +
                                          " -o " + out.string()));
    EXPECT_NE(r.exitCode, 0) << r.output;
    EXPECT_EQ(countOf(r.output, "error:"), 1u) << r.output;
    EXPECT_NE(r.output.find("penumbra-mpi: error: rank 2"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("elsewhere.json"), std::string::npos) << r.output;
    expectOnly(dir, {"small.json"});
}

TEST(MpiRender, RankWithAnotherSceneIsRefused) {
    REQUIRE_MPI();
    const fs::path dir = test::tempDir();
    const fs::path scene = smallScene(dir);
    // The same file name on another node, but another version of the scene.
    const fs::path other = test::writeFile(dir / "node2" / "small.json",
                                           R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1}]})");
    const fs::path out = dir / "never.png";
    const RunResult r = runCommand(mpirun("-np 2 " + penumbraMpi() + " " + scene.string() + " -o " + out.string() +
                                          " : -np 1 " + penumbraMpi() + " " + other.string() + " -o " + out.string()));
    EXPECT_NE(r.exitCode, 0) << r.output;
    EXPECT_EQ(countOf(r.output, "error:"), 1u) << r.output;
    EXPECT_NE(r.output.find("rank 2"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("every rank must read the same scene"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

TEST(MpiRender, KilledRankEndsTheJobWithoutAnImage) {
    REQUIRE_MPI();
    const fs::path dir = test::tempDir();
    const fs::path scene = smallScene(dir);
    const fs::path out = dir / "never.exr";
    // The test hook makes rank 2 SIGKILL itself on its first tile.
    ::setenv("PENUMBRA_MPI_TEST_KILL_RANK", "2", 1);
    const RunResult r = runCommand(mpirun("-np 3 " + penumbraMpi() + " " + scene.string() + " -o " + out.string()));
    ::unsetenv("PENUMBRA_MPI_TEST_KILL_RANK");
    EXPECT_NE(r.exitCode, 0) << r.output;
    EXPECT_NE(r.exitCode, 124) << "the job hung: " << r.output;
    EXPECT_NE(r.output.find("signal 9"), std::string::npos) << r.output;
    expectOnly(dir, {"small.json"});
}

TEST(MpiRender, UsageErrorIsReportedOnce) {
    REQUIRE_MPI();
    const fs::path dir = test::tempDir();
    const fs::path scene = smallScene(dir);
    const RunResult r = runCommand(mpirun("-np 3 " + penumbraMpi() + " " + scene.string() + " -o " +
                                          (dir / "x.exr").string() + " --light-selection some"));
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_EQ(countOf(r.output, "error:"), 1u) << r.output;
    EXPECT_NE(r.output.find("penumbra-mpi: error: --light-selection: expected auto, all, power or tree, got 'some' (see --help)"),
              std::string::npos)
        << r.output;
}

// Bad option values found only once the scene is loaded (a crop outside the
// scene's 56x40 image), or before it (an -o that is no image format), exit 2
// with penumbra's message, as penumbra does; a scene's own problem exits 1.
TEST(MpiRender, BadOptionValuesFoundAfterLoadingExitTwoLikePenumbra) {
    REQUIRE_MPI();
    const fs::path dir = test::tempDir();
    const fs::path scene = smallScene(dir);
    const std::string out = (dir / "never.exr").string();
    struct Case {
        std::string options;
        const char* message;
    };
    const Case cases[] = {
        {" -o " + out + " --crop 0,0,900,900", "crop window 0,0,900,900 must satisfy"},
        {" -o " + out + " --fov 0", "camera: fov must lie in (0, 180) degrees"},
        {" -o " + out + " --ambient -1,0,0", "--ambient: ambient light must be finite and >= 0"},
        {" -o " + (dir / "never.xyz").string(), "-o: "}};
    for (const Case& c : cases) {
        const RunResult single = runCommand(penumbraCli() + " " + scene.string() + " -q" + c.options);
        const RunResult r = runCommand(mpirun("-np 3 " + penumbraMpi() + " " + scene.string() + " -q" + c.options));
        EXPECT_EQ(single.exitCode, 2) << single.output;
        EXPECT_EQ(r.exitCode, 2) << c.options << ": " << r.output;
        EXPECT_EQ(countOf(r.output, "error:"), 1u) << r.output;
        const size_t at = r.output.find(std::string("penumbra-mpi: error: ") + c.message);
        EXPECT_NE(at, std::string::npos) << r.output;
        EXPECT_NE(r.output.find("(see --help)\n", at), std::string::npos) << r.output;
        // The same line as penumbra's, under the other name.
        const size_t s = single.output.find("penumbra: error: ");
        ASSERT_NE(s, std::string::npos) << single.output;
        const std::string line = single.output.substr(s + 17, single.output.find('\n', s) - s - 17);
        EXPECT_NE(r.output.find("penumbra-mpi: error: " + line + "\n"), std::string::npos) << line << "\n" << r.output;
    }
    const RunResult missing = runCommand(mpirun("-np 2 " + penumbraMpi() + " " + (dir / "none.json").string() + " -o " + out));
    EXPECT_EQ(missing.exitCode, 1) << missing.output;
    EXPECT_EQ(missing.output.find("(see --help)"), std::string::npos) << missing.output;
    expectOnly(dir, {"small.json"});
}

TEST(Crops, OiiotoolAssemblesCropsIntoTheFullFrameBitForBit) {
    const char* oiiotool = "/usr/bin/oiiotool";
    if (!fs::exists(oiiotool)) GTEST_SKIP() << "oiiotool is not installed (openimageio-tools)";
    const fs::path dir = test::tempDir();
    const fs::path scene = smallScene(dir);
    ASSERT_EQ(runCommand(penumbraCli() + " " + scene.string() + " -q -o " + (dir / "full.exr").string()).exitCode, 0);
    // Uneven crops covering the 56x40 frame; each file records its place.
    const std::array<std::array<int, 4>, 4> crops{{{0, 0, 23, 17}, {23, 0, 56, 17}, {0, 17, 40, 40}, {40, 17, 56, 40}}};
    std::string inputs;
    for (size_t i = 0; i < crops.size(); ++i) {
        const auto& c = crops[i];
        const fs::path out = dir / ("crop" + std::to_string(i) + ".exr");
        const std::string window = std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) +
                                   "," + std::to_string(c[3]);
        const RunResult r = runCommand(penumbraCli() + " " + scene.string() + " -q --crop " + window + " -o " + out.string());
        ASSERT_EQ(r.exitCode, 0) << r.output;
        const RunResult info = runCommand(std::string(oiiotool) + " --info -v " + out.string());
        if (c[0] || c[1]) {  // oiiotool names the origin only when it is not 0,0
            EXPECT_NE(info.output.find("pixel data origin: x=" + std::to_string(c[0]) + ", y=" + std::to_string(c[1])),
                      std::string::npos)
                << info.output;
        }
        EXPECT_NE(info.output.find("full/display size: 56 x 40"), std::string::npos) << info.output;
        inputs += " " + out.string() + (i ? " --add" : "");
    }
    // Outside its data window an image is black to oiiotool, so adding the
    // crops pastes each into place; no offsets typed.
    const RunResult merged = runCommand(std::string(oiiotool) + inputs + " -o " + (dir / "merged.exr").string());
    ASSERT_EQ(merged.exitCode, 0) << merged.output;
    expectSameBits(dir / "full.exr", dir / "merged.exr");
}

TEST(FramebufferTransfer, TilesSerializedAndPastedEqualOneRender) {
    pnb::Renderer renderer([](pnb::LogLevel, std::string_view) {});
    const fs::path dir = test::tempDir();
    const pnb::PreparedScene prepared = renderer.prepare(renderer.loadScene(smallScene(dir).string()));
    pnb::RenderSettings s = prepared.settings();
    s.aovs = true;
    const pnb::Camera camera = *prepared.camera();
    const pnb::Framebuffer whole = renderer.render(prepared, camera, s);
    pnb::Framebuffer assembled(s);
    for (const pnb::CropWindow& t : {pnb::CropWindow{0, 0, 56, 21}, pnb::CropWindow{0, 21, 30, 40},
                                     pnb::CropWindow{30, 21, 56, 40}}) {
        pnb::RenderSettings ts = s;
        ts.crop = t;
        const std::vector<std::uint8_t> bytes = renderer.render(prepared, camera, ts).serialize();
        assembled.paste(pnb::Framebuffer::deserialize(bytes.data(), bytes.size()));
    }
    EXPECT_EQ(assembled.sampleCount(), whole.sampleCount());
    for (auto get : {&pnb::Framebuffer::rgba, &pnb::Framebuffer::albedo, &pnb::Framebuffer::normals,
                     &pnb::Framebuffer::depth}) {
        const std::vector<float> a = (whole.*get)(), b = (assembled.*get)();
        ASSERT_EQ(a.size(), b.size());
        EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
    }
}

TEST(FramebufferTransfer, BadBytesAndMismatchedTilesAreRefused) {
    pnb::RenderSettings s;
    s.width = 16;
    s.height = 8;
    pnb::Framebuffer full(s);
    std::vector<std::uint8_t> bytes = full.serialize();
    EXPECT_THROW(pnb::Framebuffer::deserialize(bytes.data(), bytes.size() - 1), pnb::Error);
    bytes[0] ^= 0xff;
    EXPECT_THROW(pnb::Framebuffer::deserialize(bytes.data(), bytes.size()), pnb::Error);
    pnb::RenderSettings other = s;
    other.width = 32;
    other.crop = pnb::CropWindow{0, 0, 8, 8};
    EXPECT_THROW(full.paste(pnb::Framebuffer(other)), pnb::Error);  // another frame
    pnb::RenderSettings aovs = s;
    aovs.aovs = true;
    EXPECT_THROW(full.paste(pnb::Framebuffer(aovs)), pnb::Error);  // AOVs in one only
    pnb::RenderSettings crop = s;
    crop.crop = pnb::CropWindow{0, 0, 8, 8};
    pnb::Framebuffer part(crop);
    EXPECT_THROW(part.paste(pnb::Framebuffer(s)), pnb::Error);  // larger than the window
}
