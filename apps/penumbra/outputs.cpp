#include "outputs.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <optional>
#include <penumbra/names.hpp>
#include <penumbra/penumbra.hpp>

namespace penumbra::cli {
namespace {

namespace fs = std::filesystem;
using pnb::Error;
using pnb::ErrorCode;

[[noreturn]] void statisticsFailed(const fs::path& path, int error) {
    throw Error(ErrorCode::IoError, path.string() + ": cannot write statistics: " + std::strerror(error));
}

// Every byte or an error (a full disk, /dev/full); EINTR retried.
bool writeAll(int fd, const std::string& text) {
    size_t done = 0;
    while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            if (n == 0) errno = ENOSPC;
            return false;
        }
        done += size_t(n);
    }
    return true;
}

}  // namespace

bool isExr(const fs::path& p) {
    std::string e = p.extension().string();
    for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
    return e == ".exr";
}

std::vector<OutputFile> outputsOf(const Options& o) {
    std::vector<OutputFile> out;
    if (o.output.empty()) return out;  // --preview without -o writes nothing
    out.push_back({o.output, "-o"});
    if (o.aovs && !isExr(o.output))
        out.push_back({o.output.parent_path() / (o.output.stem().string() + ".aovs.exr"), "-o (its AOV image)"});
    if (!o.statsJson.empty()) out.push_back({o.statsJson, "--stats-json"});
    return out;
}

void precheckOutputs(const Options& o) {
    if (!o.output.empty()) pnb::checkImagePath(o.output.string());
    if (!o.statsJson.empty()) {
        auto dir = o.statsJson.parent_path().empty() ? fs::path(".") : o.statsJson.parent_path();
        if (!fs::is_directory(dir))
            throw Error(ErrorCode::IoError, o.statsJson.string() + ": folder '" + dir.string() + "' does not exist");
    }
    const std::vector<OutputFile> outputs = outputsOf(o);
    for (size_t i = 0; i < outputs.size(); ++i) {
        refuseOverwrite(outputs[i], o.scene, "the scene file");
        if (o.envImage) refuseOverwrite(outputs[i], *o.envImage, "the environment image");
        for (size_t k = 0; k < i; ++k) refuseSameOutput(outputs[k], outputs[i]);
    }
}

pnb::LoadOptions loadOptionsFor(const Options& o, SceneReads& reads) {
    pnb::LoadOptions options;
    options.strict = o.strict;
    options.meshModel = o.model;
    if (o.smoothAngle) options.smoothAngleDegrees = *o.smoothAngle;
    // The commands read whatever the scene names, but say so when that is
    // outside the scene's folder, and never write over what they read.
    options.restrictPaths = false;
    options.onRead = [&reads](const std::string& file, bool isOutside) {
        reads.all.insert(file);
        if (isOutside) reads.outside.insert(file);
    };
    return options;
}

void checkSceneReads(const Options& o, const SceneReads& reads, const char* program) {
    for (const OutputFile& output : outputsOf(o))
        for (const fs::path& input : reads.all) refuseOverwrite(output, input, "a file the scene reads");
    if (program && !reads.outside.empty())
        std::fprintf(stderr, "%s: warning: %s: reads %zu file(s) outside the scene's folder, first %s\n", program,
                     o.scene.string().c_str(), reads.outside.size(), reads.outside.begin()->string().c_str());
}

void warnIfEmptyImage(const Options& o, const pnb::Framebuffer& image, const pnb::RenderStats& stats, bool scenery,
                      const char* program) {
    // Black: no pixel reaches a tenth of the darkest non-zero 8-bit sRGB value.
    constexpr float kBlack = 3e-5f;
    // Nearly all background: at most this share of the pixels see a surface.
    constexpr double kBackgroundShare = 0.01;
    // Pixel by pixel up to the first that is not black (mostly the first one):
    // a copy of the whole image cost a few milliseconds of every render.
    bool black = true;
    for (int y = 0; y < image.height() && black; ++y)
        for (int x = 0; x < image.width() && black; ++x) {
            const pnb::Color c = image.pixel(x, y);
            black = !(c.r > kBlack || c.g > kBlack || c.b > kBlack);
        }
    const double pixels = double(image.width()) * double(image.height());
    const bool empty = scenery && pixels > 0 && double(stats.pixelsHit) <= kBackgroundShare * pixels;
    if (!black && !empty) return;
    std::fprintf(stderr, "%s: warning: %s: the image is %s; the camera may be outside a closed model; try --eye/--look-at\n",
                 program, o.output.string().c_str(),
                 black ? "black" : "nearly all background (its pixels see no surface)");
}

nlohmann::json statisticsHeader(const Options& o, const pnb::RenderSettings& s, const std::string& accelerator) {
    nlohmann::json j;
    j["scene"] = o.scene.string();
    j["output"] = o.output.string();
    j["accelerator"] = accelerator;
    j["width"] = s.width;
    j["height"] = s.height;
    j["spp"] = s.spp;
    j["light_samples"] = s.lightSamples;
    j["max_depth"] = s.maxDepth;
    j["seed"] = s.seed;
    j["integrator"] = std::string(pnb::enumName(s.integrator));
    return j;
}

StagedStatistics::StagedStatistics(const fs::path& path, const std::string& text) : path_(path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
        // Not a file to replace (a device, a FIFO, /dev/stdout): write it in place, now.
        const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
        if (fd < 0) statisticsFailed(path, errno);
        const bool ok = writeAll(fd, text);
        const int error = errno;
        ::close(fd);
        if (!ok) statisticsFailed(path, error);
        return;
    }
    const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    // Appended piece by piece: GCC 12 warns (-Wrestrict, falsely) on "." + string.
    std::string name(".");
    name += path.filename().string();
    name += ".tmp-";
    name += std::to_string(::getpid());
    name += '-';
    name += std::to_string(std::chrono::steady_clock::now().time_since_epoch().count());
    const fs::path temp = dir / name;
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) statisticsFailed(path, errno);
    bool ok = writeAll(fd, text) && ::fsync(fd) == 0;
    int error = errno;
    if (::close(fd) != 0 && ok) {
        ok = false;
        error = errno;
    }
    if (!ok) {
        ::unlink(temp.c_str());
        statisticsFailed(path, error);
    }
    temp_ = temp;
}

StagedStatistics::~StagedStatistics() {
    if (!temp_.empty()) ::unlink(temp_.c_str());
}

void StagedStatistics::commit() {
    if (temp_.empty()) return;
    if (::rename(temp_.c_str(), path_.c_str()) != 0) statisticsFailed(path_, errno);
    temp_.clear();
}

void writeOutputs(const Options& o, const pnb::Framebuffer& image, const std::function<std::string()>& statistics) {
    std::optional<StagedStatistics> staged;
    if (!o.statsJson.empty()) staged.emplace(o.statsJson, statistics());
    pnb::ImageOptions options;
    options.exposure = o.exposure;
    options.aovs = o.aovs;
    image.writeImage(o.output.string(), options);
    if (staged) staged->commit();
}

}  // namespace penumbra::cli
