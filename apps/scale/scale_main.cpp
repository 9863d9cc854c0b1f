// penumbra-scale: does Penumbra hold a big scene? Generates a heightfield of
// N triangles in memory (no file, so loading costs do not blur the numbers),
// prepares it with Embree, renders a small frame with an area light, and
// reports the time of each step, the peak memory (getrusage) and the bytes
// per triangle: Penumbra's own arrays (positions + indices, shared with
// Embree, not copied) and Embree's BVH (Accelerator::memoryBytes()).
//   penumbra-scale [--triangles N] [--width W --height H --spp S] [--quality low|medium|high]
//                  [-o image.exr] [--json report.json]
#include <sys/resource.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <new>
#include <nlohmann/json.hpp>
#include <optional>

#include "core/error.h"
#include "core/image_io.h"
#include <penumbra/names.hpp>
#include "shading/renderer.h"

namespace penumbra::scale {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// Peak resident memory of the process so far, in bytes.
uint64_t peakRssBytes() {
    rusage ru{};
    ::getrusage(RUSAGE_SELF, &ru);
    return uint64_t(ru.ru_maxrss) * 1024u;  // KiB on Linux
}

double mib(uint64_t bytes) { return double(bytes) / double(1u << 20); }

/// A rolling heightfield over [-1, 1]^2 in the xz plane with exactly
/// `triangles` triangles (rows of quads; the last quad may be half), vertices
/// shared between neighbouring triangles as in a real mesh.
TriangleMesh heightfield(uint64_t triangles) {
    const uint64_t cols = std::max<uint64_t>(1, uint64_t(std::ceil(std::sqrt(double(triangles) / 2.0))));
    const uint64_t rows = (triangles + 2 * cols - 1) / (2 * cols);
    const uint64_t vertices = (cols + 1) * (rows + 1);
    if (vertices > UINT32_MAX) throw Error(ErrorCode::InvalidArgument, "too many triangles for 32-bit indices");
    TriangleMesh m;
    m.name = "heightfield";
    m.positions.reserve(vertices);
    for (uint64_t r = 0; r <= rows; ++r) {
        for (uint64_t c = 0; c <= cols; ++c) {
            float x = -1.f + 2.f * float(c) / float(cols);
            float z = -1.f + 2.f * float(r) / float(rows);
            float y = 0.08f * std::sin(9.f * x) * std::cos(7.f * z) + 0.02f * std::sin(61.f * x + 43.f * z);
            m.positions.push_back({x, y, z});
        }
    }
    m.indices.reserve(3 * triangles);
    uint64_t emitted = 0;
    for (uint64_t r = 0; r < rows && emitted < triangles; ++r) {
        for (uint64_t c = 0; c < cols && emitted < triangles; ++c) {
            uint32_t a = uint32_t(r * (cols + 1) + c), b = a + 1, d = uint32_t(a + cols + 1), e = d + 1;
            // Counter-clockwise seen from above (+y).
            m.indices.insert(m.indices.end(), {a, d, b});
            if (++emitted == triangles) break;
            m.indices.insert(m.indices.end(), {b, d, e});
            ++emitted;
        }
    }
    return m;
}

struct ScaleOptions {
    uint64_t triangles = 10'000'000;
    RenderSettings settings;
    std::string quality = "high", output, jsonPath;
};

/// The options, or the exit code when parsing ended the program (help, a usage error).
std::optional<ScaleOptions> parseOptions(int argc, char** argv, int& exitCode) {
    ScaleOptions o;
    RenderSettings& s = o.settings;
    s.width = 320;
    s.height = 240;
    s.spp = 4;
    s.lightSamples = 1;
    s.maxDepth = 1;
    s.aovs = false;
    CLI::App app{"penumbra-scale: build and render an N-triangle scene generated in memory; report memory and time"};
    app.add_option("--triangles", o.triangles, "Triangle count")->capture_default_str()->check(CLI::Range(1ull, 1ull << 31));
    app.add_option("--width", s.width, "Image width")->capture_default_str();
    app.add_option("--height", s.height, "Image height")->capture_default_str();
    app.add_option("--spp", s.spp, "Samples per pixel")->capture_default_str();
    app.add_option("--threads", s.threads, "Render threads (0 = all cores)")->capture_default_str();
    app.add_option("--quality", o.quality, "Embree BVH quality: low, medium or high")
        ->capture_default_str()
        ->check(CLI::Validator(
            [](std::string& v) {
                return pnb::enumFromName<BuildQuality>(v) ? "" : "expected " + pnb::enumNameList<BuildQuality>() + ", got '" + v + "'";
            },
            "QUALITY"));
    app.add_option("-o,--output", o.output, "Also write the image (.exr, .png, ...)");
    app.add_option("--json", o.jsonPath, "Write the report as JSON");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        exitCode = app.exit(e);
        return std::nullopt;
    }
    validateSettings(s);
    return o;
}

/// The heightfield under a rectangle lamp that faces it.
Scene heightfieldScene(uint64_t triangles) {
    Scene scene;
    Material ground;
    ground.name = "ground";
    ground.kd = Rgb(0.6f, 0.55f, 0.5f);
    Material lamp;
    lamp.name = "lamp";
    lamp.kd = Rgb(0.f);
    lamp.ke = Rgb(12.f);
    scene.materials = {ground, lamp};
    scene.meshes.push_back(heightfield(triangles));
    scene.meshes[0].material = 0;
    // a x b points down: the lamp faces the ground.
    scene.rectangles.push_back(Rectangle{Vec3f{-0.3f, 1.5f, -0.3f}, Vec3f{0.6f, 0.f, 0.f}, Vec3f{0.f, 0.f, 0.6f}, 1});
    return scene;
}

/// What one run measured.
struct Measured {
    uint64_t triangles = 0, vertices = 0;
    uint64_t positionBytes = 0, indexBytes = 0, bvhBytes = 0;
    uint64_t rssStart = 0, rssGenerated = 0, rssPrepared = 0, rssRendered = 0;
    double generateSeconds = 0, prepareSeconds = 0;
    RenderStats stats;
    double meanRadiance = 0;
};

Measured measure(const ScaleOptions& o) {
    Measured m;
    m.rssStart = peakRssBytes();
    auto t0 = Clock::now();
    Scene scene = heightfieldScene(o.triangles);
    const TriangleMesh& mesh = scene.meshes[0];
    m.positionBytes = mesh.positions.capacityBytes();
    m.indexBytes = mesh.indices.capacity() * sizeof(uint32_t);
    m.vertices = mesh.positions.size();
    m.generateSeconds = secondsSince(t0);
    m.rssGenerated = peakRssBytes();

    Logger log;
    PrepareOptions prep;
    prep.quality = *pnb::enumFromName<BuildQuality>(o.quality);
    t0 = Clock::now();
    PreparedScene prepared(std::move(scene), prep, log);
    m.prepareSeconds = secondsSince(t0);
    m.bvhBytes = prepared.accelerator().memoryBytes();
    m.rssPrepared = peakRssBytes();
    m.triangles = prepared.scene().triangleCount();

    CameraDesc camera;
    camera.eye = Vec3f{0.f, 1.1f, 2.2f};
    camera.lookAt = Vec3f{0.f, 0.f, 0.f};
    camera.vfovDegrees = 40.f;
    Film film = makeFilm(o.settings);
    m.stats = render(prepared, camera, o.settings, film).stats;
    m.rssRendered = peakRssBytes();
    if (!o.output.empty()) writeImage(o.output, film, {});
    for (size_t i = 0, n = size_t(film.width()) * film.height(); i < n; ++i) m.meanRadiance += film.radiance(i).average();
    m.meanRadiance /= double(film.width()) * film.height();
    return m;
}

void printReport(const ScaleOptions& o, const Measured& m) {
    const RenderSettings& s = o.settings;
    const double perTri = 1.0 / double(m.triangles);
    std::printf("penumbra-scale: %llu triangles, %llu vertices (one mesh, generated in memory)\n",
                (unsigned long long)m.triangles, (unsigned long long)m.vertices);
    std::printf("  generate   %7.2f s   peak RSS %8.1f MiB\n", m.generateSeconds, mib(m.rssGenerated));
    std::printf("  prepare    %7.2f s   peak RSS %8.1f MiB   (Embree BVH, quality %s)\n", m.prepareSeconds,
                mib(m.rssPrepared), o.quality.c_str());
    std::printf("  render     %7.2f s   peak RSS %8.1f MiB   (%dx%d, %d spp, %d threads, %.2f Mrays/s, mean %.4f)\n",
                m.stats.renderSeconds, mib(m.rssRendered), s.width, s.height, s.spp, m.stats.threads,
                m.stats.mraysPerSecond, m.meanRadiance);
    std::printf("  memory     positions %.1f MiB + indices %.1f MiB = %.1f bytes/triangle (Penumbra's arrays)\n",
                mib(m.positionBytes), mib(m.indexBytes), double(m.positionBytes + m.indexBytes) * perTri);
    std::printf("             Embree BVH %.1f MiB = %.1f bytes/triangle\n", mib(m.bvhBytes), double(m.bvhBytes) * perTri);
    std::printf("             peak RSS %.1f MiB = %.1f bytes/triangle (process start: %.1f MiB)\n", mib(m.rssRendered),
                double(m.rssRendered) * perTri, mib(m.rssStart));
}

void writeJson(const ScaleOptions& o, const Measured& m) {
    const RenderSettings& s = o.settings;
    const double perTri = 1.0 / double(m.triangles);
    nlohmann::json j;
    j["triangles"] = m.triangles;
    j["vertices"] = m.vertices;
    j["build_quality"] = o.quality;
    j["seconds"] = {{"generate", m.generateSeconds}, {"prepare", m.prepareSeconds}, {"render", m.stats.renderSeconds}};
    j["bytes"] = {{"positions", m.positionBytes},
                  {"indices", m.indexBytes},
                  {"embree_bvh", m.bvhBytes},
                  {"peak_rss_start", m.rssStart},
                  {"peak_rss_generated", m.rssGenerated},
                  {"peak_rss_prepared", m.rssPrepared},
                  {"peak_rss", m.rssRendered}};
    j["bytes_per_triangle"] = {{"penumbra_arrays", double(m.positionBytes + m.indexBytes) * perTri},
                               {"embree_bvh", double(m.bvhBytes) * perTri},
                               {"peak_rss", double(m.rssRendered) * perTri}};
    j["render"] = {{"width", s.width},     {"height", s.height},
                   {"spp", s.spp},         {"threads", m.stats.threads},
                   {"mrays_per_second", m.stats.mraysPerSecond}, {"mean_radiance", m.meanRadiance}};
    std::ofstream out(o.jsonPath);
    out << j.dump(2) << "\n";
    if (!out) throw Error(ErrorCode::IoError, o.jsonPath + ": cannot write the report");
}

int run(int argc, char** argv) {
    int exitCode = 0;
    const std::optional<ScaleOptions> o = parseOptions(argc, argv, exitCode);
    if (!o) return exitCode;
    const Measured m = measure(*o);
    printReport(*o, m);
    if (!o->jsonPath.empty()) writeJson(*o, m);
    return 0;
}

}  // namespace
}  // namespace penumbra::scale

int main(int argc, char** argv) {
    try {
        return penumbra::scale::run(argc, argv);
    } catch (const penumbra::Error& e) {
        std::fprintf(stderr, "penumbra-scale: error: %s\n", e.what());
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "penumbra-scale: error: out of memory\n");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra-scale: error: %s\n", e.what());
    }
    return 1;
}
