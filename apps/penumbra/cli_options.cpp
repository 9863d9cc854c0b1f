#include "cli_options.h"

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <vector>


namespace penumbra::cli {
namespace {

using pnb::Error;
using pnb::ErrorCode;

std::vector<std::string> splitCommas(const std::string& s) {
    std::vector<std::string> parts;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) parts.push_back(item);
    if (!s.empty() && s.back() == ',') parts.push_back("");
    return parts;
}

double parseNumber(const std::string& text, const std::string& option) {
    size_t used = 0;
    double v = 0.0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size() || !std::isfinite(v))
        throw Error(ErrorCode::InvalidArgument, option + ": '" + text + "' is not a finite number");
    return v;
}

}  // namespace

pnb::Vec3 parseVec3(const std::string& text, const std::string& option) {
    auto parts = splitCommas(text);
    if (parts.size() != 3) throw Error(ErrorCode::InvalidArgument, option + ": expected x,y,z, got '" + text + "'");
    return {float(parseNumber(parts[0], option)), float(parseNumber(parts[1], option)),
            float(parseNumber(parts[2], option))};
}

pnb::CropWindow parseCrop(const std::string& text) {
    auto parts = splitCommas(text);
    if (parts.size() != 4) throw Error(ErrorCode::InvalidArgument, "--crop: expected x0,y0,x1,y1, got '" + text + "'");
    int v[4];
    for (int i = 0; i < 4; ++i) {
        double d = parseNumber(parts[i], "--crop");
        if (d != std::floor(d) || d < 0 || d > 1e9)
            throw Error(ErrorCode::InvalidArgument, "--crop: '" + parts[i] + "' is not a pixel coordinate");
        v[i] = int(d);
    }
    return {v[0], v[1], v[2], v[3]};
}

// "" when `v` is a seed: a decimal integer in [0, 2^64 - 1] (CLI11 would read
// "-1" as 2^64 - 1 and clamp larger values to it).
std::string seedProblem(const std::string& v) {
    if (!v.empty() && v[0] == '-') return "must be >= 0";
    if (v.empty() || v.find_first_not_of("0123456789") != std::string::npos) return "'" + v + "' is not an integer";
    errno = 0;
    (void)std::strtoull(v.c_str(), nullptr, 10);
    if (errno == ERANGE) return "'" + v + "' is above the largest seed, 18446744073709551615";
    return {};
}

ParseResult parseCommandLine(int argc, char** argv) {
    CLI::App app{"penumbra: render an OBJ/MTL or JSON scene with Embree-accelerated Whitted ray tracing"};
    Options o;
    std::string eye, lookAt, up, ambient, background, crop;
    int width = 0, height = 0, spp = 0, lightSamples = 0, maxDepth = 0, threads = 0, tileSize = 0;
    uint64_t seed = 0;
    float fov = 0, aperture = 0, focus = 0;
    std::string lightSelection, directLight;

    app.add_option("scene", o.scene, "Scene file (.obj or .json)")->required();
    app.add_option("-o,--output", o.output, "Output image (.exr .hdr .pfm .png .jpg .tif)")->required();
    auto* oWidth = app.add_option("--width", width, "Image width in pixels");
    auto* oHeight = app.add_option("--height", height, "Image height in pixels");
    auto* oSpp = app.add_option("--spp", spp, "Camera samples per pixel (multi-jittered)");
    auto* oLs = app.add_option("--light-samples", lightSamples, "Area-light samples per light per shading point");
    auto* oDepth = app.add_option("--max-depth", maxDepth, "Maximum mirror bounces (0 = no reflection rays)");
    auto* oSeed = app.add_option("--seed", seed, "Random seed")
                      ->check(CLI::Validator([](std::string& v) { return seedProblem(v); }, "UINT64"));
    auto* oThreads = app.add_option("--threads", threads, "Render threads (0 = all cores)");
    auto* oTile = app.add_option("--tile-size", tileSize, "Tile size in pixels");
    app.add_option("--accel", o.accel, "Accelerator: embree or naive")->capture_default_str();
    app.add_option("--build-quality", o.buildQuality, "Embree BVH quality: low, medium or high")->capture_default_str();
    app.add_option("--eye", eye, "Camera position x,y,z");
    app.add_option("--look-at", lookAt, "Camera target x,y,z");
    app.add_option("--up", up, "Camera up vector x,y,z");
    auto* oFov = app.add_option("--fov", fov, "Vertical field of view in degrees, in (0, 180)");
    auto* oAperture = app.add_option("--aperture", aperture, "Lens radius (0 = pinhole)");
    auto* oFocus = app.add_option("--focus-distance", focus, "Focus distance (0 = distance to look-at)");
    app.add_option("--ambient", ambient, "Ambient light r,g,b (OBJ scenes have none unless asked)");
    app.add_option("--background", background, "Background radiance r,g,b");
    app.add_option("--crop", crop, "Render only the window x0,y0,x1,y1 of the full frame");
    app.add_option("--light-selection", lightSelection, "all (every light, N samples each) or power");
    app.add_option("--exposure", o.exposure, "Exposure in stops for PNG/JPG/TIF output");
    app.add_flag("--aovs", o.aovs, "Also write albedo, normal and depth (EXR channels or <stem>.aovs.exr)");
    app.add_option("--stats-json", o.statsJson, "Write render statistics as JSON to this file");
    app.add_flag("--strict", o.strict, "Treat skippable scene problems as errors");
    app.add_flag("-q,--quiet", o.quiet, "No progress and no summary");
    app.add_option("--direct-light", directLight,
                   "Area-light estimator: mis (light + BRDF samples, default), light (solid-angle light samples) "
                   "or area (uniform-area light samples, the old estimator)");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help ends the program successfully; anything else is a usage error:
        // one line, and exit code 2 (CLI11's own codes run from 100 to 115).
        if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return {std::nullopt, app.exit(e)};
        std::string msg = e.what();
        for (char& c : msg)
            if (c == '\n' || c == '\r') c = ' ';
        std::fprintf(stderr, "penumbra: error: %s (see --help)\n", msg.c_str());
        return {std::nullopt, 2};
    }
    if (oWidth->count()) o.width = width;
    if (oHeight->count()) o.height = height;
    if (oSpp->count()) o.spp = spp;
    if (oLs->count()) o.lightSamples = lightSamples;
    if (oDepth->count()) o.maxDepth = maxDepth;
    if (oSeed->count()) o.seed = seed;
    if (oThreads->count()) o.threads = threads;
    if (oTile->count()) o.tileSize = tileSize;
    if (oFov->count()) o.fov = fov;
    if (oAperture->count()) o.aperture = aperture;
    if (oFocus->count()) o.focusDistance = focus;
    if (!eye.empty()) o.eye = parseVec3(eye, "--eye");
    if (!lookAt.empty()) o.lookAt = parseVec3(lookAt, "--look-at");
    if (!up.empty()) o.up = parseVec3(up, "--up");
    // Their limits (finite as 32-bit floats, >= 0) are the scene's: pnb::Scene checks them when they are applied.
    if (!ambient.empty()) {
        const pnb::Vec3 a = parseVec3(ambient, "--ambient");
        o.ambient = pnb::Color{a.x, a.y, a.z};
    }
    if (!background.empty()) {
        const pnb::Vec3 b = parseVec3(background, "--background");
        o.background = pnb::Color{b.x, b.y, b.z};
    }
    if (!crop.empty()) o.crop = parseCrop(crop);
    if (!lightSelection.empty()) {
        if (lightSelection != "all" && lightSelection != "power")
            throw Error(ErrorCode::InvalidArgument, "--light-selection: expected all or power, got '" + lightSelection + "'");
        o.lightSelection = lightSelection;
    }
    if (!directLight.empty()) {
        if (directLight != "mis" && directLight != "light" && directLight != "area")
            throw Error(ErrorCode::InvalidArgument, "--direct-light: expected mis, light or area, got '" + directLight + "'");
        o.directLight = directLight;
    }
    if (!std::isfinite(o.exposure)) throw Error(ErrorCode::InvalidArgument, "--exposure: must be finite");
    if (o.accel != "embree" && o.accel != "naive")
        throw Error(ErrorCode::InvalidArgument, "--accel: unknown accelerator '" + o.accel + "' (expected embree or naive)");
    if (o.buildQuality != "low" && o.buildQuality != "medium" && o.buildQuality != "high")
        throw Error(ErrorCode::InvalidArgument, "--build-quality: expected low, medium or high, got '" + o.buildQuality + "'");
    return {o, 0};
}

}  // namespace penumbra::cli
