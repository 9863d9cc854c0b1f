#include "bench_options.h"

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/error.h"

namespace penumbra::bench {

std::vector<size_t> parseSizes(const std::string& text) {
    std::vector<size_t> sizes;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        size_t used = 0;
        double v = 0.0;
        try {
            v = std::stod(item, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        // At least 6 triangles: the smallest closed sphere the generator makes.
        if (used == 0 || used != item.size() || !std::isfinite(v) || v < 6 || v > 5e7 || v != std::floor(v))
            throw Error(ErrorCode::InvalidArgument,
                        "--sizes: '" + item + "' is not a triangle count between 6 and 5e7");
        sizes.push_back(static_cast<size_t>(v));
    }
    if (sizes.empty()) throw Error(ErrorCode::InvalidArgument, "--sizes: expected a comma-separated list");
    return sizes;
}

BenchParseResult parseBenchCommandLine(int argc, char** argv) {
    CLI::App app{
        "penumbra-bench: Embree against the naive intersector and the raw Embree ceiling, on the same ray sets"};
    BenchOptions o;
    std::string sizes;
    std::string defaultScene = PENUMBRA_DEFAULT_SCENE;
    bool noMixed = false;
    size_t rays = 0, naiveMaxRays = 0;
    int reps = 0;
    app.add_option("--sizes", sizes, "Triangle counts of the procedural scenes (default 1e2,1e3,1e4,1e5,1e6)");
    app.add_option("--obj", o.objs, "An OBJ file to place in a room with a light (repeatable)")
        ->check(CLI::ExistingFile);
    app.add_option("--scene", o.scenes, "A JSON scene file to measure as it stands (repeatable)")
        ->check(CLI::ExistingFile);
    app.add_option("--default-scene", defaultScene, "The default scene (\"\" leaves it out)")->capture_default_str();
    app.add_flag("--no-mixed", noMixed, "Leave out the scene with analytic shapes");
    app.add_flag("--quick", o.quick, "Tiny sizes, ray counts and frame (the smoke test)");
    app.add_option("--threads", o.threads, "Threads of the multi-threaded runs (0 = all cores)")
        ->check(CLI::Range(0, 1024));
    app.add_option("--rays", rays, "Camera rays per scene (default 262144; --quick 4096)")
        ->check(CLI::Range(size_t(16), size_t(1) << 26));
    app.add_option("--naive-max-rays", naiveMaxRays, "Most rays per kind the naive intersector answers (default 2048)")
        ->check(CLI::Range(size_t(16), size_t(1) << 26));
    app.add_option("--repetitions", reps, "Timed runs after the warm-up; the best counts (default 3)")
        ->check(CLI::Range(1, 100));
    app.add_option("--json", o.json, "Write all figures as JSON to this file");
    app.add_option("--plot", o.plot, "Write a log-log plot (PNG, needs gnuplot) to this file");
    app.add_option("--seed", o.seed, "Seed of the ray sets and the frame")->capture_default_str();

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // CLI11 has its own codes per kind of error; ours are 0 (help) and 2.
        const int code = app.exit(e);
        return {std::nullopt, code == 0 ? 0 : 2};
    }

    o.defaultScene = defaultScene;
    o.mixed = !noMixed;
    if (sizes.empty()) {
        o.sizes = o.quick ? std::vector<size_t>{100, 1000} : std::vector<size_t>{100, 1000, 10000, 100000, 1000000};
    } else {
        try {
            o.sizes = parseSizes(sizes);
        } catch (const Error& e) {
            std::fprintf(stderr, "%s\nRun with --help for more information.\n", e.what());
            return {std::nullopt, 2};
        }
    }
    o.rays = rays ? rays : (o.quick ? 4096 : 262144);
    o.naiveMaxRays = naiveMaxRays ? naiveMaxRays : (o.quick ? 256 : 2048);
    o.naiveBudget = o.quick ? 2e6 : 5e7;
    o.repetitions = reps ? reps : (o.quick ? 1 : 3);
    o.frameWidth = o.quick ? 32 : 160;
    o.frameHeight = o.quick ? 24 : 120;
    o.frameSpp = o.quick ? 1 : 4;
    o.frameLightSamples = o.quick ? 1 : 2;
    o.frameMaxDepth = 4;
    for (int i = 0; i < argc; ++i) o.commandLine += (i ? " " : "") + std::string(argv[i]);
    return {o, 0};
}

}  // namespace penumbra::bench
