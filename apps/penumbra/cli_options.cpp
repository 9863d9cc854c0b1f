#include "cli_options.h"

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <stdexcept>
#include <utility>
#include <variant>
#include <vector>

#include "option_values.h"
#include <penumbra/names.hpp>

namespace penumbra::cli {
namespace {

using Refusal = std::function<std::string(const std::string& value)>;

// An enum option: CLI11's IsMember refuses any text but the names of
// pnb::EnumNames<E> ("expected auto, all, power or tree, got 'x'" unless
// `refusal` says otherwise), its Transformer turns a name into the value.
template <class E>
CLI::Validator oneOf(Refusal refusal = nullptr) {
    std::vector<std::pair<std::string, E>> names;
    std::vector<std::string> keys;
    for (const auto& entry : pnb::EnumNames<E>::table) {
        names.emplace_back(entry.name, entry.value);
        keys.emplace_back(entry.name);
    }
    if (!refusal) {
        const std::string list = pnb::enumNameList<E>();
        refusal = [list](const std::string& value) { return "expected " + list + ", got '" + value + "'"; };
    }
    // Held as plain Validators: copying the derived classes would pick their catch-all constructors.
    const CLI::Validator member = CLI::IsMember(keys);
    const CLI::Validator toValue = CLI::Transformer(names);
    return CLI::Validator(
        [member, toValue, refusal](std::string& value) {
            std::string probe = value;
            return member(probe).empty() ? toValue(value) : refusal(value);
        },
        member.get_description());
}

// A finite number (inside `range`, when given), refused with the commands'
// message; text that is not a number is left to CLI11's conversion error.
CLI::Validator finiteNumber(const std::string& message, const std::optional<CLI::Validator>& range = std::nullopt) {
    return CLI::Validator(
        [range, message](std::string& value) {
            double v = 0.0;
            if (!CLI::detail::lexical_cast(value, v)) return std::string();
            std::string probe = value;
            return std::isfinite(v) && (!range || (*range)(probe).empty()) ? std::string() : message;
        },
        range ? range->get_description() : "FINITE");
}

// An option whose text `apply` takes (with a parser of option_values.h); the
// parser's std::invalid_argument becomes CLI11's error naming the option.
CLI::Option* addParsed(CLI::App& app, const std::string& name, std::function<void(const std::string&)> apply,
                       const std::string& help) {
    return app.add_option_function<std::string>(
        name,
        [apply = std::move(apply), name](const std::string& text) {
            try {
                apply(text);
            } catch (const std::invalid_argument& e) {
                throw CLI::ValidationError(name, e.what());
            }
        },
        help);
}

template <class T, class Parse>
CLI::Option* addParsed(CLI::App& app, const std::string& name, std::optional<T>& field, Parse parse,
                       const std::string& help) {
    return addParsed(app, name, [&field, parse](const std::string& text) { field = parse(text); }, help);
}

void addImageOptions(CLI::App& app, Options& o) {
    app.add_option("scene", o.scene, "Scene file (.json, .obj, or a model: .ply .stl .gltf .glb .fbx .dae ...)")->required();
    app.add_option("-o,--output", o.output, "Output image (.exr .hdr .pfm .png .jpg .tif); optional with --preview");
    app.add_option("--width", o.width, "Image width in pixels");
    app.add_option("--height", o.height, "Image height in pixels");
    addParsed(app, "--crop", o.crop, parseCrop, "Render only the window x0,y0,x1,y1 of the full frame");
    app.add_option("--exposure", o.exposure, "Exposure in stops for PNG/JPG/TIF output")
        ->check(finiteNumber("must be finite"));
    app.add_flag("--aovs", o.aovs, "Also write albedo, normal and depth (EXR channels or <stem>.aovs.exr)");
    app.add_option("--stats-json", o.statsJson, "Write render statistics as JSON to this file");
    app.add_flag("--strict", o.strict, "Treat skippable scene problems as errors");
    app.add_flag("-q,--quiet", o.quiet, "No progress and no summary");
}

void addSamplingOptions(CLI::App& app, Options& o) {
    using pnb::DirectLightSampling;
    using pnb::IntegratorKind;
    using pnb::LightSelection;
    app.add_option("--spp", o.spp, "Camera samples per pixel (multi-jittered)");
    app.add_option("--light-samples", o.lightSamples, "Area-light samples per light per shading point");
    app.add_option("--max-depth", o.maxDepth,
                   "whitted: maximum mirror/refraction bounces (0 = none); path: maximum path length");
    app.add_option("--seed", o.seed, "Random seed")
        ->check(CLI::Validator([](std::string& v) { return seedProblem(v); }, "UINT64"));
    app.add_option("--threads", o.threads, "Render threads (0 = all cores; at most the cores there are)");
    app.add_option("--tile-size", o.tileSize, "Tile size in pixels");
    app.add_option("--light-selection", o.lightSelection,
                   "auto (default: tree from 8 lights with path, from 256 with whitted, else all), all (every light, "
                   "N samples each), power or tree (N samples in all, lights picked by power or by a light hierarchy)")
        ->transform(oneOf<LightSelection>());
    app.add_option("--integrator", o.integrator, "whitted (default: direct light + mirrors + glass) or path (path tracing)")
        ->transform(oneOf<IntegratorKind>());
    app.add_option("--direct-light", o.directLight,
                   "Area-light estimator: mis (light + BRDF samples, default) or light (solid-angle light samples)")
        ->transform(oneOf<DirectLightSampling>());
    app.add_option("--accel", o.accel, "Accelerator: embree or naive")
        ->transform(oneOf<pnb::AcceleratorKind>([](const std::string& v) {
            return "unknown accelerator '" + v + "' (expected " + pnb::enumNameList<pnb::AcceleratorKind>() + ")";
        }));
    app.add_option("--build-quality", o.buildQuality, "Embree BVH quality: low, medium or high (default)")
        ->transform(oneOf<pnb::BuildQuality>());
}

void addSceneOptions(CLI::App& app, Options& o) {
    addParsed(app, "--eye", o.eye, parseVec3, "Camera position x,y,z");
    addParsed(app, "--look-at", o.lookAt, parseVec3, "Camera target x,y,z");
    addParsed(app, "--up", o.up, parseVec3, "Camera up vector x,y,z");
    app.add_option("--fov", o.fov, "Vertical field of view in degrees, in (0, 180)");
    app.add_option("--aperture", o.aperture, "Lens radius (0 = pinhole)");
    app.add_option("--focus-distance", o.focusDistance, "Focus distance (0 = distance to look-at)");
    addParsed(app, "--ambient", o.ambient, parseColor, "Ambient light r,g,b (OBJ scenes have none unless asked)");
    addParsed(app, "--background", o.background, parseColor, "Background radiance r,g,b");
    addParsed(
        app, "--env",
        [&o](const std::string& text) {
            const auto env = parseEnvironment(text);
            o.envColor.reset();
            o.envImage.reset();
            if (const auto* color = std::get_if<pnb::Color>(&env))
                o.envColor = *color;
            else
                o.envImage = std::get<std::filesystem::path>(env);
        },
        "Environment light: radiance r,g,b or a lat-long image (.exr .hdr ...); a value that names an existing "
        "file, or holds a '/', is a file");
    app.add_option("--env-rotate", o.envRotate, "Turn the --env image by DEG about +y")
        ->check(finiteNumber("must be finite"));
    app.add_option("--model", o.model, "Phong model of mesh and model files' materials: classic or normalized (default)")
        ->transform(oneOf<pnb::PhongModel>());
    app.add_option("--smooth-angle", o.smoothAngle,
                   "Smooth meshes without normals across edges under this angle in degrees (default 30; 0 = faceted)")
        ->check(finiteNumber("must lie in [0, 180] degrees", CLI::Range(0.0, 180.0)));
}

void addPreviewOptions(CLI::App& app, Options& o) {
    app.add_flag("--preview", o.preview,
                 "Serve a live view of the render on 127.0.0.1 (orbit, zoom and pan restart it); prints its address");
    app.add_option("--preview-port", o.previewPort, "Port of the --preview server (default 0: a free port)")
        ->check(CLI::Range(0, 65535));
    app.add_flag("--preview-exit", o.previewExit,
                 "With --preview: exit when the render completes instead of serving the final image until Ctrl-C");
}

// What one option asks of another, once all are parsed.
void checkCombinations(const Options& o) {
    if (o.envRotate && !o.envImage) throw CLI::ValidationError("--env-rotate", "needs --env FILE (an image)");
    if (!o.preview && (o.previewPort != 0 || o.previewExit))
        throw CLI::ValidationError(o.previewExit ? "--preview-exit" : "--preview-port", "needs --preview");
    if (o.output.empty() && !o.preview) throw CLI::RequiredError("--output");
    if (o.output.empty() && !o.statsJson.empty())
        throw CLI::ValidationError("--stats-json", "describes the image -o writes: give -o too");
}

}  // namespace

int reportUsageError(const std::string& message, const char* program) {
    std::string msg = message;
    for (char& c : msg)
        if (c == '\n' || c == '\r') c = ' ';
    std::fprintf(stderr, "%s: error: %s (see --help)\n", program, msg.c_str());
    return 2;
}

ParseResult parseCommandLine(int argc, char** argv, const char* program, bool previewOptions) {
    CLI::App app{"penumbra: render a scene (JSON, OBJ/MTL, or a model Assimp reads: PLY, STL, glTF, FBX, COLLADA, ...) "
                 "with Embree-accelerated Whitted ray tracing or path tracing"};
    // As most Unix tools: a repeated option takes its last value (aliases and wrappers add defaults before the user's).
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    Options o;
    addImageOptions(app, o);
    addSamplingOptions(app, o);
    addSceneOptions(app, o);
    if (previewOptions) addPreviewOptions(app, o);
    try {
        app.parse(argc, argv);
        checkCombinations(o);
    } catch (const CLI::ParseError& e) {
        // --help ends the program successfully; anything else is a usage error:
        // one line, and exit code 2 (CLI11's own codes run from 100 to 115).
        if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return {std::nullopt, app.exit(e)};
        return {std::nullopt, reportUsageError(e.what(), program)};
    }
    return {o, 0};
}

}  // namespace penumbra::cli
