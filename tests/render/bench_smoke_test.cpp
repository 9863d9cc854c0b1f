// Smoke run of penumbra-bench --quick: correctness of the tool only (exit code,
// the agreement check, the JSON layout and the values it must hold); no
// timing is asserted beyond "measured and positive".
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "support/test_support.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct RunResult {
    int exitCode;
    std::string output;  // stdout + stderr
};

fs::path benchBinary() { return penumbra::test::binaryDir() / "penumbra-bench"; }

RunResult runBench(const std::string& args) {
    const std::string cmd = benchBinary().string() + " " + args + " 2>&1";
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) return {-1, "popen failed"};
    std::string out;
    std::array<char, 4096> buf{};
    size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
    const int status = ::pclose(p);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), out};
}

// A regular tetrahedron (4 triangles) for the --obj path.
fs::path tetrahedron(const fs::path& dir) {
    return penumbra::test::writeFile(dir / "tet.obj",
                                     "v 1 1 1\nv 1 -1 -1\nv -1 1 -1\nv -1 -1 1\n"
                                     "f 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n");
}

const json* sceneNamed(const json& j, const std::string& name) {
    for (const auto& s : j.at("scenes"))
        if (s.at("name") == name) return &s;
    return nullptr;
}

bool gnuplotAvailable() { return std::system("command -v gnuplot > /dev/null 2>&1") == 0; }

}  // namespace

class BenchSmoke : public ::testing::Test {
protected:
    // One quick run shared by the tests below (it takes about a second).
    static void SetUpTestSuite() {
        dir_ = new fs::path(fs::temp_directory_path() / ("penumbra-bench-smoke-" + std::to_string(::getpid())));
        fs::create_directories(*dir_);
        const fs::path obj = tetrahedron(*dir_);
        result_ = new RunResult(runBench("--quick --threads 2 --seed 7 --obj " + obj.string() + " --json " +
                                         (*dir_ / "bench.json").string() + " --plot " +
                                         (*dir_ / "bench.png").string()));
        std::ifstream in(*dir_ / "bench.json");
        json_ = new json(json::parse(in, nullptr, false));
    }
    static void TearDownTestSuite() {
        std::error_code ec;
        fs::remove_all(*dir_, ec);
        delete dir_;
        delete result_;
        delete json_;
    }
    void SetUp() override {
        ASSERT_TRUE(fs::exists(benchBinary())) << benchBinary() << " is missing: build the penumbra-bench target";
        ASSERT_EQ(result_->exitCode, 0) << result_->output;
        ASSERT_FALSE(json_->is_discarded()) << "bench.json is not valid JSON";
    }
    static fs::path* dir_;
    static RunResult* result_;
    static json* json_;
};
fs::path* BenchSmoke::dir_ = nullptr;
RunResult* BenchSmoke::result_ = nullptr;
json* BenchSmoke::json_ = nullptr;

TEST_F(BenchSmoke, AgreementPassesAndIsReported) {
    EXPECT_NE(result_->output.find("agreement: passed"), std::string::npos) << result_->output;
    const json& a = json_->at("agreement");
    EXPECT_TRUE(a.at("passed").get<bool>());
    EXPECT_DOUBLE_EQ(a.at("max_fraction").get<double>(), 1e-4);
    EXPECT_GT(a.at("naive_vs_embree").at("compared").get<size_t>(), 1000u);
    EXPECT_EQ(a.at("naive_vs_embree").at("mismatches").get<size_t>(), 0u);
    // Raw Embree answers every ray of the triangle-only scenes, packets included.
    EXPECT_GT(a.at("raw_vs_embree").at("compared").get<size_t>(), 10000u);
    EXPECT_EQ(a.at("raw_vs_embree").at("mismatches").get<size_t>(), 0u);
}

TEST_F(BenchSmoke, SettingsAndScenesAreTheRequestedOnes) {
    const json& j = *json_;
    EXPECT_EQ(j.at("tool"), "penumbra-bench");
    EXPECT_EQ(j.at("settings").at("threads").get<int>(), 2);
    EXPECT_EQ(j.at("settings").at("rays").get<size_t>(), 4096u);
    EXPECT_EQ(j.at("settings").at("naive_max_rays").get<size_t>(), 256u);
    EXPECT_EQ(j.at("settings").at("seed").get<uint64_t>(), 7u);
    EXPECT_TRUE(j.at("settings").at("quick").get<bool>());
    EXPECT_FALSE(j.at("machine").at("cpu").get<std::string>().empty());

    std::vector<std::string> names;
    for (const auto& s : j.at("scenes")) names.push_back(s.at("name"));
    EXPECT_EQ(names, (std::vector<std::string>{"sphere-1e2", "sphere-1e3", "mixed", "cornell", "tet"}));
    // The procedural sphere has exactly the requested count; the room adds 12.
    EXPECT_EQ(sceneNamed(j, "sphere-1e2")->at("triangles").get<size_t>(), 112u);
    EXPECT_EQ(sceneNamed(j, "sphere-1e3")->at("triangles").get<size_t>(), 1012u);
    EXPECT_EQ(sceneNamed(j, "tet")->at("triangles").get<size_t>(), 16u);
    EXPECT_EQ(sceneNamed(j, "tet")->at("family"), "obj");
    EXPECT_EQ(sceneNamed(j, "cornell")->at("family"), "default");
    const json& mixed = *sceneNamed(j, "mixed");
    EXPECT_FALSE(mixed.at("triangle_only").get<bool>());
    EXPECT_EQ(mixed.at("triangles").get<size_t>(), 1000u);
    EXPECT_GT(mixed.at("primitives").get<size_t>(), 1000u);
}

TEST_F(BenchSmoke, EveryAcceleratorAnsweredEveryRayKind) {
    for (const auto& s : json_->at("scenes")) {
        SCOPED_TRACE(s.at("name").get<std::string>());
        const json& sets = s.at("ray_sets");
        EXPECT_EQ(sets.at("camera").get<size_t>(), 4096u);
        EXPECT_EQ(sets.at("image_side").get<int>(), 64);
        EXPECT_GT(sets.at("shadow").get<size_t>(), 0u);
        EXPECT_EQ(sets.at("incoherent").get<size_t>(), sets.at("camera_hits").get<size_t>());
        EXPECT_EQ(sets.at("mirror").get<size_t>() + sets.at("random").get<size_t>(), sets.at("incoherent").get<size_t>());

        const json& acc = s.at("accelerators");
        for (const char* kind : {"camera", "shadow", "incoherent"}) {
            SCOPED_TRACE(kind);
            const json& e = acc.at("embree").at("rays").at(kind);
            EXPECT_EQ(e.at("rays"), sets.at(kind));
            EXPECT_GT(e.at("mrays_1t").get<double>(), 0.0);
            EXPECT_GT(e.at("mrays_nt").get<double>(), 0.0);
            // The naive loop answers an evenly spread subset and says so.
            const json& n = acc.at("naive").at("rays").at(kind);
            EXPECT_EQ(n.at("set_rays"), sets.at(kind));
            EXPECT_GE(n.at("rays").get<size_t>(), 16u);
            EXPECT_LE(n.at("rays").get<size_t>(), 256u);
            EXPECT_GT(n.at("mrays_1t").get<double>(), 0.0);
        }
        EXPECT_GT(acc.at("embree_intersect_prim").at("rays").at("camera").at("mrays_1t").get<double>(), 0.0);
        EXPECT_GT(acc.at("embree").at("memory_bytes").get<size_t>(), 0u);
        EXPECT_GT(acc.at("embree").at("build_seconds").get<double>(), 0.0);
        EXPECT_EQ(acc.at("naive").at("memory_bytes").get<size_t>(), 0u);

        const json& raw = acc.at("raw_embree");
        const json& ratios = s.at("ratios");
        if (s.at("triangle_only").get<bool>()) {
            EXPECT_GT(raw.at("rays").at("camera").at("mrays_1t").get<double>(), 0.0);
            EXPECT_GT(raw.at("packets").at("camera").at("16").at("mrays_1t").get<double>(), 0.0);
            EXPECT_GT(raw.at("packets").at("shadow").at("8").at("mrays_nt").get<double>(), 0.0);
            EXPECT_TRUE(ratios.at("camera_renderer_over_raw_1t").is_number());
            EXPECT_TRUE(ratios.at("memory_renderer_over_raw").is_number());
            EXPECT_TRUE(ratios.at("frame_over_query_nt").is_number());
            // The same without the robust flag: measured, compared, not checked.
            const json& fast = acc.at("raw_embree_not_robust");
            EXPECT_GT(fast.at("rays").at("incoherent").at("mrays_nt").get<double>(), 0.0);
            EXPECT_EQ(fast.at("agreement_with_embree").at("camera").at("compared"), sets.at("camera"));
        } else {
            EXPECT_FALSE(raw.contains("rays"));
            EXPECT_TRUE(acc.at("raw_embree_not_robust").is_null());
            EXPECT_NE(raw.at("note").get<std::string>().find("analytic"), std::string::npos);
            EXPECT_TRUE(ratios.at("camera_renderer_over_raw_1t").is_null());
        }
        EXPECT_TRUE(ratios.at("embree_over_naive_1t").at("camera").is_number());
    }
}

TEST_F(BenchSmoke, FramesCountTheRaysTheyTraced) {
    const json& s = *sceneNamed(*json_, "sphere-1e2");
    const json& e = s.at("accelerators").at("embree").at("frame");
    ASSERT_TRUE(e.at("measured").get<bool>());
    EXPECT_EQ(e.at("rays").at("camera").get<uint64_t>(), 32u * 24u);  // --quick: 32x24, 1 spp
    EXPECT_GT(e.at("rays").at("shadow").get<uint64_t>(), 0u);
    EXPECT_GT(e.at("seconds_1t").get<double>(), 0.0);
    // The naive frame is small enough here, and traces exactly the same rays.
    const json& n = s.at("accelerators").at("naive").at("frame");
    ASSERT_TRUE(n.at("measured").get<bool>());
    EXPECT_EQ(n.at("rays"), e.at("rays"));
}

TEST_F(BenchSmoke, PlotIsWrittenWhenGnuplotIsInstalled) {
    if (!gnuplotAvailable()) GTEST_SKIP() << "gnuplot is not installed";
    std::ifstream png(*dir_ / "bench.png", std::ios::binary);
    std::array<char, 8> sig{};
    png.read(sig.data(), sig.size());
    EXPECT_EQ(std::string(sig.data(), 8), std::string("\x89PNG\r\n\x1a\n", 8));
    // Nine series (3 accelerators x 3 ray kinds), each with both procedural sizes.
    std::ifstream tsv(*dir_ / "bench.tsv");
    std::stringstream ss;
    ss << tsv.rdbuf();
    const std::string data = ss.str();
    size_t titles = 0, pos = 0;
    while ((pos = data.find("\n\"", pos)) != std::string::npos) ++titles, ++pos;
    EXPECT_EQ(titles, 9u);
    EXPECT_NE(data.find("\"naive shadow\"\n112\t"), std::string::npos);
}

TEST(BenchUsage, BadOptionsAreUsageErrors) {
    ASSERT_TRUE(fs::exists(benchBinary())) << benchBinary() << " is missing: build the penumbra-bench target";
    const RunResult sizes = runBench("--sizes 3");
    EXPECT_EQ(sizes.exitCode, 2);
    EXPECT_NE(sizes.output.find("--sizes: '3'"), std::string::npos) << sizes.output;
    const RunResult obj = runBench("--obj /nonexistent/file.obj");
    EXPECT_EQ(obj.exitCode, 2);
    const RunResult rays = runBench("--rays 1");
    EXPECT_EQ(rays.exitCode, 2);
}
