#include "cli_options.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <iterator>
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

void parseEnvironment(const std::string& text, Options& o) {
    if (text.find(',') != std::string::npos) {
        pnb::Vec3 c;
        try {
            c = parseVec3(text, "--env");
        } catch (const Error&) {
            throw Error(ErrorCode::InvalidArgument,
                        "--env: expected r,g,b (three finite numbers) or an image file, got '" + text + "'");
        }
        if (!(c.x >= 0.f && c.y >= 0.f && c.z >= 0.f) || !std::isfinite(c.x + c.y + c.z))
            throw Error(ErrorCode::InvalidArgument, "--env: radiance must be finite and >= 0, got '" + text + "'");
        o.envColor = pnb::Color{c.x, c.y, c.z};
        o.envImage.reset();
        return;
    }
    std::string ext = std::filesystem::path(text).extension().string();
    for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    static const char* const kImages[] = {".exr", ".hdr", ".pfm", ".png", ".jpg", ".jpeg", ".tif", ".tiff"};
    if (text.empty() || std::find(std::begin(kImages), std::end(kImages), ext) == std::end(kImages))
        throw Error(ErrorCode::InvalidArgument, "--env: expected r,g,b or an image file (.exr .hdr .pfm .png .jpg "
                                                ".tif), got '" + text + "'");
    o.envImage = std::filesystem::path(text);
    o.envColor.reset();
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

int reportUsageError(const std::string& message, const char* program) {
    std::string msg = message;
    for (char& c : msg)
        if (c == '\n' || c == '\r') c = ' ';
    std::fprintf(stderr, "%s: error: %s (see --help)\n", program, msg.c_str());
    return 2;
}

namespace {

// The checks of values CLI11 parsed; throws pnb::Error naming the option.
void readValues(Options& o, const std::string& eye, const std::string& lookAt, const std::string& up,
                const std::string& ambient, const std::string& background, const std::string& crop,
                const std::string& lightSelection, const std::string& model) {
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
        if (lightSelection != "auto" && lightSelection != "all" && lightSelection != "power" && lightSelection != "tree")
            throw Error(ErrorCode::InvalidArgument,
                        "--light-selection: expected auto, all, power or tree, got '" + lightSelection + "'");
        o.lightSelection = lightSelection;
    }
    if (!model.empty()) {
        if (model == "classic")
            o.model = pnb::PhongModel::Classic;
        else if (model == "normalized" || model == "normalised")
            o.model = pnb::PhongModel::Normalized;
        else
            throw Error(ErrorCode::InvalidArgument, "--model: expected classic or normalized, got '" + model + "'");
    }
    if (o.smoothAngle && !(*o.smoothAngle >= 0.f && *o.smoothAngle <= 180.f))
        throw Error(ErrorCode::InvalidArgument, "--smooth-angle: must lie in [0, 180] degrees");
    if (!std::isfinite(o.exposure)) throw Error(ErrorCode::InvalidArgument, "--exposure: must be finite");
    if (o.accel != "embree" && o.accel != "naive")
        throw Error(ErrorCode::InvalidArgument, "--accel: unknown accelerator '" + o.accel + "' (expected embree or naive)");
    if (o.buildQuality != "low" && o.buildQuality != "medium" && o.buildQuality != "high")
        throw Error(ErrorCode::InvalidArgument, "--build-quality: expected low, medium or high, got '" + o.buildQuality + "'");
}

}  // namespace

ParseResult parseCommandLine(int argc, char** argv, const char* program) {
    CLI::App app{"penumbra: render a scene (JSON, OBJ/MTL, or a model Assimp reads: PLY, STL, glTF, FBX, COLLADA, ...) "
                 "with Embree-accelerated Whitted ray tracing or path tracing"};
    // As most Unix tools: a repeated option takes its last value (aliases and wrappers add defaults before the user's).
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    Options o;
    std::string eye, lookAt, up, ambient, background, crop;
    int width = 0, height = 0, spp = 0, lightSamples = 0, maxDepth = 0, threads = 0, tileSize = 0;
    uint64_t seed = 0;
    float fov = 0, aperture = 0, focus = 0;
    std::string lightSelection, model;
    float smoothAngle = 0.f;
    std::string env;
    float envRotate = 0.f;
    std::string integrator, directLight;

    app.add_option("scene", o.scene, "Scene file (.json, .obj, or a model: .ply .stl .gltf .glb .fbx .dae ...)")->required();
    app.add_option("-o,--output", o.output, "Output image (.exr .hdr .pfm .png .jpg .tif)")->required();
    auto* oWidth = app.add_option("--width", width, "Image width in pixels");
    auto* oHeight = app.add_option("--height", height, "Image height in pixels");
    auto* oSpp = app.add_option("--spp", spp, "Camera samples per pixel (multi-jittered)");
    auto* oLs = app.add_option("--light-samples", lightSamples, "Area-light samples per light per shading point");
    auto* oDepth = app.add_option("--max-depth", maxDepth,
                                  "whitted: maximum mirror/refraction bounces (0 = none); path: maximum path length");
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
    app.add_option("--light-selection", lightSelection,
                   "auto (default: tree from 8 lights with path, from 256 with whitted, else all), all (every light, "
                   "N samples each), power or tree (N samples in all, lights picked by power or by a light hierarchy)");
    app.add_option("--exposure", o.exposure, "Exposure in stops for PNG/JPG/TIF output");
    app.add_flag("--aovs", o.aovs, "Also write albedo, normal and depth (EXR channels or <stem>.aovs.exr)");
    app.add_option("--integrator", integrator, "whitted (default: direct light + mirrors + glass) or path (path tracing)");
    app.add_option("--stats-json", o.statsJson, "Write render statistics as JSON to this file");
    app.add_flag("--strict", o.strict, "Treat skippable scene problems as errors");
    app.add_flag("-q,--quiet", o.quiet, "No progress and no summary");
    app.add_option("--direct-light", directLight,
                   "Area-light estimator: mis (light + BRDF samples, default) or light (solid-angle light samples)");
    auto* oEnv = app.add_option("--env", env, "Environment light: radiance r,g,b or a lat-long image (.exr .hdr ...)");
    auto* oEnvRotate = app.add_option("--env-rotate", envRotate, "Turn the --env image by DEG about +y");
    app.add_option("--model", model, "Phong model of mesh and model files' materials: classic or normalized (default)");
    auto* oSmooth = app.add_option("--smooth-angle", smoothAngle,
                                   "Smooth meshes without normals across edges under this angle in degrees (default 30; 0 = faceted)");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help ends the program successfully; anything else is a usage error:
        // one line, and exit code 2 (CLI11's own codes run from 100 to 115).
        if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return {std::nullopt, app.exit(e)};
        return {std::nullopt, reportUsageError(e.what(), program)};
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
    if (oSmooth->count()) o.smoothAngle = smoothAngle;
    try {
        readValues(o, eye, lookAt, up, ambient, background, crop, lightSelection, model);
    } catch (const Error& e) {
        return {std::nullopt, reportUsageError(e.what(), program)};
    }
    // --env problems are usage errors (exit 2), like CLI11's own.
    try {
        if (oEnv->count()) parseEnvironment(env, o);
        if (oEnvRotate->count()) {
            if (!o.envImage) throw Error(ErrorCode::InvalidArgument, "--env-rotate: needs --env FILE (an image)");
            if (!std::isfinite(envRotate)) throw Error(ErrorCode::InvalidArgument, "--env-rotate: must be finite");
            o.envRotate = envRotate;
        }
        if (!integrator.empty()) {
            if (integrator != "whitted" && integrator != "path")
                throw Error(ErrorCode::InvalidArgument, "--integrator: expected whitted or path, got '" + integrator + "'");
            o.integrator = integrator;
        }
        if (!directLight.empty()) {
            if (directLight != "mis" && directLight != "light")
                throw Error(ErrorCode::InvalidArgument, "--direct-light: expected mis or light, got '" + directLight + "'");
            o.directLight = directLight;
        }
    } catch (const Error& e) {
        return {std::nullopt, reportUsageError(e.what(), program)};
    }
    return {o, 0};
}

}  // namespace penumbra::cli
