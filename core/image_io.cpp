#include "core/image_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/oiio_library.h"
#include "core/png_encoder.h"
#include "core/srgb8.h"

namespace penumbra {
namespace fs = std::filesystem;
namespace {

using Bytes = std::vector<unsigned char>;

std::string lowerExtension(const fs::path& p) {
    std::string e = p.extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

[[noreturn]] void writeFailed(const fs::path& path, const std::string& why) {
    throw Error(ErrorCode::IoError, path.string() + ": cannot write image: " + why);
}

constexpr int kPngDeflateLevel = 4;

// libjpeg ends the process (exit) on a dimension it cannot store; refuse first.
constexpr int kMaxJpegSide = 65500;

// Debian's OpenImageIO 2.4 reads PFM but has no PFM writer, and the format is
// a three-line header plus raw floats: colour "PF", little-endian (negative
// scale), rows stored bottom to top.
Bytes encodePfm(const Film& film) {
    static_assert(std::endian::native == std::endian::little, "the PFM writer assumes a little-endian host");
    const std::string header = "PF\n" + std::to_string(film.width()) + " " + std::to_string(film.height()) + "\n-1.0\n";
    const std::vector<float> px = film.radianceBuffer(3);
    const size_t row = size_t(film.width()) * 3 * sizeof(float);
    Bytes out(header.begin(), header.end());
    out.resize(header.size() + row * size_t(film.height()));
    unsigned char* dst = out.data() + header.size();
    for (int y = film.height() - 1; y >= 0; --y, dst += row) std::memcpy(dst, px.data() + size_t(y) * film.width() * 3, row);
    return out;
}

std::vector<oiio::Attribute> metadataAttributes(const ImageMetadata& m) {
    using K = oiio::Attribute::Kind;
    std::vector<oiio::Attribute> a(4);
    a[0] = {"Software", K::String, 0, 0.f, m.software.empty() ? std::string("Penumbra") : m.software};
    a[1] = {"penumbra:spp", K::Int, m.spp, 0.f, {}};
    a[2] = {"penumbra:seed", K::String, 0, 0.f, std::to_string(m.seed)};
    a[3] = {"penumbra:render_seconds", K::Float, 0, static_cast<float>(m.renderSeconds), {}};
    return a;
}

// OpenImageIO encodes into memory; the bytes are written by StagedFile.
Bytes encodeWithOiio(const fs::path& path, const oiio::EncodeRequest& rq) {
    Bytes out;
    std::string error;
    const oiio::Api* api = nullptr;
    try {
        api = &oiioLibrary();
    } catch (const Error& e) {
        writeFailed(path, e.what());
    }
    if (!api->encode(rq, out, error)) writeFailed(path, error.empty() ? std::string("encoding failed") : error);
    return out;
}

// A crop's EXR records its place in the full frame, so compositors assemble crops without offsets.
void placeCrop(oiio::EncodeRequest& rq, const ImageWriteOptions& o) {
    if (o.fullWidth <= 0 || o.fullHeight <= 0) return;
    rq.dataX = o.dataOriginX;
    rq.dataY = o.dataOriginY;
    rq.fullWidth = o.fullWidth;
    rq.fullHeight = o.fullHeight;
}

Bytes encodeAovExr(const fs::path& path, const Film& film, const ImageWriteOptions& options, bool withRadiance) {
    const int w = film.width(), h = film.height();
    const int nch = (withRadiance ? 3 : 0) + 7;
    oiio::EncodeRequest rq;
    rq.format = "exr";
    rq.width = w;
    rq.height = h;
    rq.channels = nch;
    rq.type = oiio::PixelType::F32;
    if (withRadiance) rq.channelNames = {"R", "G", "B"};
    for (const char* c : {"albedo.R", "albedo.G", "albedo.B", "N.X", "N.Y", "N.Z", "Z"}) rq.channelNames.push_back(c);
    rq.attributes = metadataAttributes(options.metadata);
    placeCrop(rq, options);
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
    rq.pixels = px.data();
    return encodeWithOiio(path, rq);
}

// The shortest decimal text that reads back as `v`.
std::string shortestText(float v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

// The film's radiance, exposure-scaled, as 8-bit sRGB codes (PNG, JPEG, TIFF).
std::vector<uint8_t> srgbPixels(const Film& film, float exposure) {
    const float scale = std::exp2(exposure);
    const Srgb8 srgb8;
    const size_t n = size_t(film.width()) * film.height();
    std::vector<uint8_t> px(n * 3);
    // 1,024 pixels' linear values at a time, then their codes in one loop
    // (Srgb8::codes), which vectorises where code by code it could not.
    constexpr size_t kChunk = 1024;
    float linear[3 * kChunk];
    for (size_t first = 0; first < n; first += kChunk) {
        const size_t m = std::min(kChunk, n - first);
        for (size_t k = 0; k < m; ++k) {
            const Rgb L = film.radiance(first + k) * scale;
            linear[3 * k] = L.r;
            linear[3 * k + 1] = L.g;
            linear[3 * k + 2] = L.b;
        }
        srgb8.codes(linear, 3 * m, &px[3 * first]);
    }
    return px;
}

// PNG by core/png_encoder.h, the metadata as text entries. libdeflate's level 4: all of the
// encoding comes after the render, and higher levels take longer for a few percent less
// (figures: README, "Output").
Bytes encodePngFile(const fs::path& path, int w, int h, const std::vector<uint8_t>& px,
                    const std::vector<oiio::Attribute>& metadata) {
    std::vector<std::pair<std::string, std::string>> text;
    for (const oiio::Attribute& a : metadata) {
        switch (a.kind) {
            case oiio::Attribute::Kind::Int: text.emplace_back(a.name, std::to_string(a.i)); break;
            case oiio::Attribute::Kind::Float: text.emplace_back(a.name, shortestText(a.f)); break;
            case oiio::Attribute::Kind::String: text.emplace_back(a.name, a.s); break;
        }
    }
    Bytes out;
    std::string error;
    if (!encodePng(PngImage{w, h, px.data(), text, kPngDeflateLevel}, out, error)) writeFailed(path, error);
    return out;
}

// The whole file's bytes in memory, for every format (radiance only).
Bytes encodeRadiance(const fs::path& path, ImageFormat fmt, const Film& film, const ImageWriteOptions& options) {
    if (fmt == ImageFormat::Pfm) return encodePfm(film);
    const int w = film.width(), h = film.height();
    oiio::EncodeRequest rq;
    rq.width = w;
    rq.height = h;
    rq.channels = 3;
    rq.attributes = metadataAttributes(options.metadata);
    switch (fmt) {
        case ImageFormat::Exr: rq.format = "exr"; break;
        case ImageFormat::Hdr: rq.format = "hdr"; break;
        case ImageFormat::Png: rq.format = "png"; break;
        case ImageFormat::Jpg: rq.format = "jpg"; break;
        case ImageFormat::Tif: rq.format = "tif"; break;
        case ImageFormat::Pfm: break;
    }
    if (isFloatFormat(fmt)) {
        rq.type = oiio::PixelType::F32;
        if (fmt == ImageFormat::Exr) placeCrop(rq, options);
        const std::vector<float> px = film.radianceBuffer(3);
        rq.pixels = px.data();
        return encodeWithOiio(path, rq);
    }
    if (fmt == ImageFormat::Jpg && (w > kMaxJpegSide || h > kMaxJpegSide))
        writeFailed(path, "JPEG stores at most " + std::to_string(kMaxJpegSide) + " pixels a side, the image is " +
                              std::to_string(w) + "x" + std::to_string(h));
    const std::vector<uint8_t> px = srgbPixels(film, options.exposure);
    if (fmt == ImageFormat::Png) return encodePngFile(path, w, h, px, rq.attributes);
    rq.type = oiio::PixelType::U8;
    rq.attributes.push_back({"oiio:ColorSpace", oiio::Attribute::Kind::String, 0, 0.f, "sRGB"});
    // OpenImageIO 2.4's TIFF writer corrupts the file it writes through an
    // IOProxy when it adds an Exif directory (the header then lacks
    // ImageLength); the Exif block only repeated the colour space.
    if (fmt == ImageFormat::Tif) rq.attributes.push_back({"tiff:write_exif", oiio::Attribute::Kind::Int, 0, 0.f, {}});
    rq.pixels = px.data();
    return encodeWithOiio(path, rq);
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

Bytes encodeImage(ImageFormat format, const Film& film, const ImageWriteOptions& options, const std::string& name) {
    if (!options.aovs || !film.hasAovs()) return encodeRadiance(name, format, film, options);
    if (format != ImageFormat::Exr)
        throw Error(ErrorCode::InvalidArgument, name + ": AOVs are encoded only as the channels of an EXR image");
    return encodeAovExr(name, film, options, true);
}

void writeImage(const fs::path& path, const Film& film, const ImageWriteOptions& options) {
    const ImageFormat fmt = imageFormatFromPath(path);
    // Everything is encoded before anything is written, and every file is
    // complete on disk (as a temporary) before any is renamed into place, so a
    // failure leaves the old images (main and AOV sibling) as they were.
    if (fmt == ImageFormat::Exr || !options.aovs || !film.hasAovs()) {
        writeFileAtomically(path, encodeImage(fmt, film, options, path.string()), "image");
        return;
    }
    // Other formats have no room for AOVs: they go to a sibling EXR, and both
    // files are complete before either is renamed.
    const Bytes main = encodeRadiance(path, fmt, film, options);
    const fs::path aovPath = path.parent_path() / (path.stem().string() + ".aovs.exr");
    const Bytes aovs = encodeAovExr(aovPath, film, options, false);
    StagedFile stagedAovs(aovPath, aovs, "image");
    StagedFile stagedMain(path, main, "image");
    stagedAovs.commit();
    stagedMain.commit();
}

ImageData readImage(const fs::path& path) {
    auto fail = [&](const std::string& why) -> void {
        throw Error(ErrorCode::IoError, path.string() + ": cannot read image: " + why);
    };
    const oiio::Api* api = nullptr;
    try {
        api = &oiioLibrary();
    } catch (const Error& e) {
        fail(e.what());
    }
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) fail(std::strerror(errno));
    oiio::DecodeRequest rq;
    rq.fd = fd;
    rq.name = path.string();
    oiio::Decoded d;
    std::string error;
    const oiio::Status st = api->decode(rq, d, error);
    ::close(fd);
    if (st != oiio::Status::Ok) fail(error);
    ImageData img;
    img.width = d.width;
    img.height = d.height;
    img.channels = d.decodedChannels;
    img.channelNames = std::move(d.channelNames);
    img.pixels.resize(size_t(img.width) * img.height * img.channels);
    std::memcpy(img.pixels.data(), d.pixels.data(), img.pixels.size() * sizeof(float));
    img.attributes = std::move(d.attributes);
    return img;
}

}  // namespace penumbra
