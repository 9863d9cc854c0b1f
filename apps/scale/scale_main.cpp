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
#include <new>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/image_io.h"
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

int run(int argc, char** argv) {
    uint64_t triangles = 10'000'000;
    RenderSettings settings;
    settings.width = 320;
    settings.height = 240;
    settings.spp = 4;
    settings.lightSamples = 1;
    settings.maxDepth = 1;
    settings.aovs = false;
    std::string quality = "high", output, jsonPath;

    CLI::App app{"penumbra-scale: build and render an N-triangle scene generated in memory; report memory and time"};
    app.add_option("--triangles", triangles, "Triangle count")->capture_default_str()->check(CLI::Range(1ull, 1ull << 31));
    app.add_option("--width", settings.width, "Image width")->capture_default_str();
    app.add_option("--height", settings.height, "Image height")->capture_default_str();
    app.add_option("--spp", settings.spp, "Samples per pixel")->capture_default_str();
    app.add_option("--threads", settings.threads, "Render threads (0 = all cores)")->capture_default_str();
    app.add_option("--quality", quality, "Embree BVH quality: low, medium or high")
        ->capture_default_str()
        ->check(CLI::IsMember({"low", "medium", "high"}));
    app.add_option("-o,--output", output, "Also write the image (.exr, .png, ...)");
    app.add_option("--json", jsonPath, "Write the report as JSON");
    CLI11_PARSE(app, argc, argv);
    validateSettings(settings);

    const uint64_t rssStart = peakRssBytes();
    auto t0 = Clock::now();
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
    const TriangleMesh& mesh = scene.meshes[0];
    const uint64_t positionBytes = mesh.positions.capacityBytes();
    const uint64_t indexBytes = mesh.indices.capacity() * sizeof(uint32_t);
    const uint64_t vertexCount = mesh.positions.size();
    const double generateSeconds = secondsSince(t0);
    const uint64_t rssGenerated = peakRssBytes();

    Logger log;
    PrepareOptions prep;
    prep.quality = quality == "low" ? BuildQuality::Low : quality == "medium" ? BuildQuality::Medium : BuildQuality::High;
    t0 = Clock::now();
    PreparedScene prepared(std::move(scene), prep, log);
    const double prepareSeconds = secondsSince(t0);
    const uint64_t bvhBytes = prepared.accelerator().memoryBytes();
    const uint64_t rssPrepared = peakRssBytes();
    const uint64_t triangleCount = prepared.scene().triangleCount();

    CameraDesc camera;
    camera.eye = Vec3f{0.f, 1.1f, 2.2f};
    camera.lookAt = Vec3f{0.f, 0.f, 0.f};
    camera.vfovDegrees = 40.f;
    Film film = makeFilm(settings);
    RenderStats stats = render(prepared, camera, settings, film).stats;
    const uint64_t rssRendered = peakRssBytes();
    if (!output.empty()) writeImage(output, film, {});

    double mean = 0.0;
    for (size_t i = 0, n = size_t(film.width()) * film.height(); i < n; ++i) mean += film.radiance(i).average();
    mean /= double(film.width()) * film.height();

    const double perTri = 1.0 / double(triangleCount);
    std::printf("penumbra-scale: %llu triangles, %llu vertices (one mesh, generated in memory)\n",
                (unsigned long long)triangleCount, (unsigned long long)vertexCount);
    std::printf("  generate   %7.2f s   peak RSS %8.1f MiB\n", generateSeconds, mib(rssGenerated));
    std::printf("  prepare    %7.2f s   peak RSS %8.1f MiB   (Embree BVH, quality %s)\n", prepareSeconds,
                mib(rssPrepared), quality.c_str());
    std::printf("  render     %7.2f s   peak RSS %8.1f MiB   (%dx%d, %d spp, %d threads, %.2f Mrays/s, mean %.4f)\n",
                stats.renderSeconds, mib(rssRendered), settings.width, settings.height, settings.spp, stats.threads,
                stats.mraysPerSecond, mean);
    std::printf("  memory     positions %.1f MiB + indices %.1f MiB = %.1f bytes/triangle (Penumbra's arrays)\n",
                mib(positionBytes), mib(indexBytes), double(positionBytes + indexBytes) * perTri);
    std::printf("             Embree BVH %.1f MiB = %.1f bytes/triangle\n", mib(bvhBytes), double(bvhBytes) * perTri);
    std::printf("             peak RSS %.1f MiB = %.1f bytes/triangle (process start: %.1f MiB)\n", mib(rssRendered),
                double(rssRendered) * perTri, mib(rssStart));

    if (!jsonPath.empty()) {
        nlohmann::json j;
        j["triangles"] = triangleCount;
        j["vertices"] = vertexCount;
        j["build_quality"] = quality;
        j["seconds"] = {{"generate", generateSeconds}, {"prepare", prepareSeconds}, {"render", stats.renderSeconds}};
        j["bytes"] = {{"positions", positionBytes},
                      {"indices", indexBytes},
                      {"embree_bvh", bvhBytes},
                      {"peak_rss_start", rssStart},
                      {"peak_rss_generated", rssGenerated},
                      {"peak_rss_prepared", rssPrepared},
                      {"peak_rss", rssRendered}};
        j["bytes_per_triangle"] = {{"penumbra_arrays", double(positionBytes + indexBytes) * perTri},
                                   {"embree_bvh", double(bvhBytes) * perTri},
                                   {"peak_rss", double(rssRendered) * perTri}};
        j["render"] = {{"width", settings.width},     {"height", settings.height},
                       {"spp", settings.spp},         {"threads", stats.threads},
                       {"mrays_per_second", stats.mraysPerSecond}, {"mean_radiance", mean}};
        std::ofstream out(jsonPath);
        out << j.dump(2) << "\n";
        if (!out) throw Error(ErrorCode::IoError, jsonPath + ": cannot write the report");
    }
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
