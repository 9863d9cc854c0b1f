#include "core/rgb_image.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <new>

#include "core/error.h"
#include "core/image_io.h"
#include "core/oiio_library.h"

namespace penumbra {
namespace {

[[noreturn]] void fail(const std::string& name, std::string why) {
    std::replace(why.begin(), why.end(), '\n', ' ');  // one line
    throw Error(ErrorCode::IoError, name + ": cannot read image (" + why + ")");
}

std::string mib(uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB"; }

}  // namespace

RgbImage decodeRgbImage(const std::string& name, int fd, const TextureBudget& budget, RgbImageFixups* fixups) {
    struct stat st {};
    if (::fstat(fd, &st) != 0) fail(name, std::strerror(errno));
    if (!S_ISREG(st.st_mode)) fail(name, "it is not a regular file");
    const oiio::Api& api = oiioLibrary();

    // Header first: the budget is checked before any pixel is decoded. Every
    // pixel is decoded as 3 floats, whatever the file stores.
    oiio::DecodeRequest rq;
    rq.fd = fd;
    rq.name = name;
    rq.maxChannels = 3;
    rq.floatPixels = true;
    rq.maxBytes = std::max<uint64_t>(1, budget.maxBytes);
    rq.headerOnly = true;
    oiio::Decoded d;
    std::string why;
    oiio::Status status = api.decode(rq, d, why);
    if (status == oiio::Status::OverBudget) {
        if (d.width == 0) fail(name, "the file alone is more than the " + mib(budget.maxBytes) + " image budget");
        fail(name, "its header says " + std::to_string(d.width) + "x" + std::to_string(d.height) +
                       " pixels, more than the " + mib(budget.maxBytes) + " image budget");
    }
    if (status != oiio::Status::Ok) fail(name, why);
    if (d.width <= 0 || d.height <= 0) fail(name, "it has no pixels");

    rq.headerOnly = false;
    d = oiio::Decoded{};
    try {
        status = api.decode(rq, d, why);
    } catch (const std::bad_alloc&) {
        fail(name, "out of memory while decoding it");
    }
    if (status == oiio::Status::OverBudget) fail(name, "it grew past the image budget while being read");
    if (status != oiio::Status::Ok) fail(name, why);
    if (d.type != oiio::PixelType::F32 || d.decodedChannels < 1) fail(name, "unexpected pixel layout");

    // Files say what they hold through oiio:ColorSpace; without it 8-bit
    // images are taken to be sRGB, float ones linear (as textures are).
    const std::string& cs = d.colorSpace;
    const bool srgb = !cs.empty() ? (cs.size() >= 4 && (cs.compare(0, 4, "sRGB") == 0 || cs.compare(0, 4, "srgb") == 0 ||
                                                        cs.compare(0, 4, "SRGB") == 0))
                                  : (d.bytesPerChannel == 1 && !d.floatData);
    RgbImage img;
    img.width = d.width;
    img.height = d.height;
    const size_t n = size_t(d.width) * size_t(d.height);
    img.pixels.resize(n);
    const float* src = reinterpret_cast<const float*>(d.pixels.data());
    const int ch = d.decodedChannels;
    RgbImageFixups fix;
    for (size_t i = 0; i < n; ++i) {
        float c[3];
        for (int k = 0; k < 3; ++k) {
            float v = src[i * size_t(ch) + size_t(ch >= 3 ? k : 0)];
            if (!std::isfinite(v)) {
                ++fix.nonFinite;
                v = 0.f;
            } else if (v < 0.f) {
                ++fix.negative;
                v = 0.f;
            }
            c[k] = srgb ? srgbToLinear(std::min(v, 1.f)) : v;
        }
        img.pixels[i] = Rgb{c[0], c[1], c[2]};
    }
    if (fixups) *fixups = fix;
    return img;
}

RgbImage decodeRgbImage(const std::string& path, const TextureBudget& budget, RgbImageFixups* fixups) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
    if (fd < 0) {
        const int err = errno;
        throw Error(err == ENOENT ? ErrorCode::FileNotFound : ErrorCode::IoError,
                    path + ": cannot read image (" + std::strerror(err) + ")");
    }
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    return decodeRgbImage(path, fd, budget, fixups);
}

}  // namespace penumbra
