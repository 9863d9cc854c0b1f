#include "core/image_io.h"

#include <unistd.h>

#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <fstream>

#include "core/error.h"

namespace penumbra {
namespace fs = std::filesystem;
namespace {

std::string lowerExtension(const fs::path& p) {
    std::string e = p.extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

// A unique temporary name next to the target, keeping its extension so that
// OpenImageIO picks the same writer.
fs::path temporaryPathFor(const fs::path& target) {
    // pid + a clock tick keep concurrent writers (processes or threads) apart.
    auto tick = std::chrono::steady_clock::now().time_since_epoch().count();
    std::string name(".");
    name += target.stem().string();
    name += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(tick);
    name += target.extension().string();
    return target.parent_path() / name;
}

void writeRaw(const fs::path& path, const OIIO::ImageSpec& spec, const void* data, OIIO::TypeDesc type) {
    fs::path tmp = temporaryPathFor(path);
    std::string tmpName = tmp.string();
    auto fail = [&](const std::string& why) {
        std::error_code ec;
        fs::remove(tmp, ec);
        throw Error(ErrorCode::IoError, path.string() + ": cannot write image: " + why);
    };
    auto out = OIIO::ImageOutput::create(path.string());
    if (!out) fail("no writer for this format (" + OIIO::geterror() + ")");
    if (!out->open(tmpName, spec)) fail(out->geterror());
    if (!out->write_image(type, data)) {
        std::string e = out->geterror();
        out->close();
        fail(e);
    }
    if (!out->close()) fail(out->geterror());
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) fail(ec.message());
}

// Debian's OpenImageIO 2.4 reads PFM but has no PFM writer, and the format is
// a three-line header plus raw floats: colour "PF", little-endian (negative
// scale), rows stored bottom to top.
void writePfm(const fs::path& path, const Film& film) {
    fs::path tmp = temporaryPathFor(path);
    {
        std::ofstream out(tmp, std::ios::binary);
        if (!out) throw Error(ErrorCode::IoError, path.string() + ": cannot write image: cannot create a file in its folder");
        out << "PF\n" << film.width() << " " << film.height() << "\n-1.0\n";
        std::vector<float> px = film.radianceBuffer(3);
        const size_t row = size_t(film.width()) * 3;
        for (int y = film.height() - 1; y >= 0; --y)
            out.write(reinterpret_cast<const char*>(px.data() + size_t(y) * row), std::streamsize(row * sizeof(float)));
        out.close();
        if (!out) {
            std::error_code ec;
            fs::remove(tmp, ec);
            throw Error(ErrorCode::IoError, path.string() + ": cannot write image: write failed");
        }
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw Error(ErrorCode::IoError, path.string() + ": cannot write image: " + ec.message());
    }
}

void addMetadata(OIIO::ImageSpec& spec, const ImageMetadata& m) {
    spec.attribute("Software", m.software.empty() ? std::string("Penumbra") : m.software);
    spec.attribute("penumbra:spp", m.spp);
    spec.attribute("penumbra:seed", std::to_string(m.seed));
    spec.attribute("penumbra:render_seconds", static_cast<float>(m.renderSeconds));
}

// An EXR of a crop: data window at the crop's origin, display window the full frame.
void setDataWindow(OIIO::ImageSpec& spec, const ImageWriteOptions& o) {
    if (o.fullWidth <= 0 || o.fullHeight <= 0) return;
    spec.x = o.dataOriginX;
    spec.y = o.dataOriginY;
    spec.full_x = 0;
    spec.full_y = 0;
    spec.full_width = o.fullWidth;
    spec.full_height = o.fullHeight;
}

void writeAovExr(const fs::path& path, const Film& film, const ImageWriteOptions& options, bool withRadiance) {
    const ImageMetadata& meta = options.metadata;
    const int w = film.width(), h = film.height();
    const int nch = (withRadiance ? 3 : 0) + 7;
    OIIO::ImageSpec spec(w, h, nch, OIIO::TypeDesc::FLOAT);
    spec.channelnames.clear();
    if (withRadiance) spec.channelnames = {"R", "G", "B"};
    for (const char* c : {"albedo.R", "albedo.G", "albedo.B", "N.X", "N.Y", "N.Z", "Z"}) spec.channelnames.push_back(c);
    if (withRadiance) {
        spec.alpha_channel = -1;
    }
    addMetadata(spec, meta);
    setDataWindow(spec, options);
    std::vector<float> px(size_t(w) * h * nch);
    for (size_t i = 0, n = size_t(w) * h; i < n; ++i) {
        float* p = &px[i * nch];
        int c = 0;
        if (withRadiance) {
            Rgb L = film.radiance(i);
            p[c++] = L.r;
            p[c++] = L.g;
            p[c++] = L.b;
        }
        Rgb a = film.albedo(i);
        Vec3f nn = film.normal(i);
        p[c++] = a.r;
        p[c++] = a.g;
        p[c++] = a.b;
        p[c++] = nn.x;
        p[c++] = nn.y;
        p[c++] = nn.z;
        p[c++] = film.depth(i);
    }
    writeRaw(path, spec, px.data(), OIIO::TypeDesc::FLOAT);
}

}  // namespace

float linearToSrgb(float v) {
    v = std::clamp(v, 0.f, 1.f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.f / 2.4f) - 0.055f;
}

float srgbToLinear(float v) { return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f); }

ImageFormat imageFormatFromPath(const fs::path& path) {
    std::string e = lowerExtension(path);
    if (e == ".exr") return ImageFormat::Exr;
    if (e == ".hdr") return ImageFormat::Hdr;
    if (e == ".pfm") return ImageFormat::Pfm;
    if (e == ".png") return ImageFormat::Png;
    if (e == ".jpg" || e == ".jpeg") return ImageFormat::Jpg;
    if (e == ".tif" || e == ".tiff") return ImageFormat::Tif;
    throw Error(ErrorCode::InvalidArgument,
                path.string() + ": unknown image format '" + e + "' (expected .exr, .hdr, .pfm, .png, .jpg or .tif)");
}

bool isFloatFormat(ImageFormat f) { return f == ImageFormat::Exr || f == ImageFormat::Hdr || f == ImageFormat::Pfm; }

void checkWritable(const fs::path& path) {
    imageFormatFromPath(path);
    fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        throw Error(ErrorCode::IoError, path.string() + ": cannot write image: folder '" + dir.string() + "' does not exist");
    if (fs::is_directory(path, ec))
        throw Error(ErrorCode::IoError, path.string() + ": cannot write image: it is a directory");
    if (::access(dir.c_str(), W_OK) != 0)
        throw Error(ErrorCode::IoError, path.string() + ": cannot write image: folder '" + dir.string() + "' is not writable");
}

void writeImage(const fs::path& path, const Film& film, const ImageWriteOptions& options) {
    const ImageFormat fmt = imageFormatFromPath(path);
    const int w = film.width(), h = film.height();
    if (fmt == ImageFormat::Exr && options.aovs && film.hasAovs()) {
        writeAovExr(path, film, options, true);
        return;
    }
    // Other formats keep their AOVs in a sibling EXR. It is written first and
    // removed again if the main image fails, so a failure leaves neither.
    fs::path aovPath;
    if (options.aovs && film.hasAovs()) {
        aovPath = path.parent_path() / (path.stem().string() + ".aovs.exr");
        writeAovExr(aovPath, film, options, false);
    }
    try {
        static_assert(std::endian::native == std::endian::little, "the PFM writer assumes a little-endian host");
        if (fmt == ImageFormat::Pfm) {
            writePfm(path, film);
        } else if (isFloatFormat(fmt)) {
            OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
            addMetadata(spec, options.metadata);
            if (fmt == ImageFormat::Exr) setDataWindow(spec, options);
            std::vector<float> px = film.radianceBuffer(3);
            writeRaw(path, spec, px.data(), OIIO::TypeDesc::FLOAT);
        } else {
            OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
            addMetadata(spec, options.metadata);
            spec.attribute("oiio:ColorSpace", "sRGB");
            const float scale = std::exp2(options.exposure);
            std::vector<uint8_t> px(size_t(w) * h * 3);
            for (size_t i = 0, n = size_t(w) * h; i < n; ++i) {
                Rgb L = film.radiance(i) * scale;
                px[3 * i] = uint8_t(std::lround(linearToSrgb(L.r) * 255.f));
                px[3 * i + 1] = uint8_t(std::lround(linearToSrgb(L.g) * 255.f));
                px[3 * i + 2] = uint8_t(std::lround(linearToSrgb(L.b) * 255.f));
            }
            writeRaw(path, spec, px.data(), OIIO::TypeDesc::UINT8);
        }
    } catch (...) {
        if (!aovPath.empty()) {
            std::error_code ec;
            fs::remove(aovPath, ec);
        }
        throw;
    }
}

ImageData readImage(const fs::path& path) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) throw Error(ErrorCode::IoError, path.string() + ": cannot read image: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    ImageData img;
    img.width = spec.width;
    img.height = spec.height;
    img.channels = spec.nchannels;
    img.channelNames = spec.channelnames;
    img.pixels.resize(size_t(img.width) * img.height * img.channels);
    if (!in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::FLOAT, img.pixels.data()))
        throw Error(ErrorCode::IoError, path.string() + ": cannot read image: " + in->geterror());
    for (const auto& p : spec.extra_attribs) img.attributes.emplace_back(p.name().string(), p.get_string());
    in->close();
    return img;
}

}  // namespace penumbra
