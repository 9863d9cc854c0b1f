#include "core/texture_cache.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <new>
#include <string>

#include "core/error.h"
#include "core/image_io.h"
#include "core/oiio_library.h"

namespace penumbra {
namespace {

// One MIP level: texels of 1 (grey) or 3 channels, 8-bit or float, row 0 on top.
struct Level {
    int w = 0, h = 0;
    std::vector<uint8_t> u8;
    std::vector<float> f32;
};

struct Texture {
    std::vector<Level> levels;
    int channels = 0;  // 1 or 3
    bool is8bit = false;
    bool srgb = false;
    bool enabled = false;

    float texel(const Level& l, int x, int y, int c) const {
        const size_t i = (size_t(y) * size_t(l.w) + size_t(x)) * size_t(channels) + size_t(c);
        return is8bit ? float(l.u8[i]) * (1.f / 255.f) : l.f32[i];
    }
    // Bilinear with periodic wrap; (s, t) in texture space, t pointing down the rows.
    void bilinear(const Level& l, float s, float t, float out[3]) const {
        const float x = s * float(l.w) - 0.5f, y = t * float(l.h) - 0.5f;
        const float fx0 = std::floor(x), fy0 = std::floor(y);
        const float ax = x - fx0, ay = y - fy0;
        auto wrap = [](float v, int n) {
            const double m = std::fmod(double(v), double(n));
            int i = int(m < 0 ? m + n : m);
            return i >= n ? 0 : i;
        };
        const int x0 = wrap(fx0, l.w), y0 = wrap(fy0, l.h);
        const int x1 = x0 + 1 == l.w ? 0 : x0 + 1, y1 = y0 + 1 == l.h ? 0 : y0 + 1;
        for (int c = 0; c < channels; ++c) {
            const float top = (1.f - ax) * texel(l, x0, y0, c) + ax * texel(l, x1, y0, c);
            const float bottom = (1.f - ax) * texel(l, x0, y1, c) + ax * texel(l, x1, y1, c);
            out[c] = (1.f - ay) * top + ay * bottom;
        }
    }
};

// Box-filtered half-size level (odd sizes repeat their last row/column).
Level downsample(const Level& src, int channels, bool is8bit) {
    Level dst;
    dst.w = std::max(1, (src.w + 1) / 2);
    dst.h = std::max(1, (src.h + 1) / 2);
    const size_t n = size_t(dst.w) * size_t(dst.h) * size_t(channels);
    if (is8bit) dst.u8.resize(n);
    else dst.f32.resize(n);
    for (int y = 0; y < dst.h; ++y)
        for (int x = 0; x < dst.w; ++x) {
            const int xs[2] = {std::min(2 * x, src.w - 1), std::min(2 * x + 1, src.w - 1)};
            const int ys[2] = {std::min(2 * y, src.h - 1), std::min(2 * y + 1, src.h - 1)};
            for (int c = 0; c < channels; ++c) {
                double sum = 0.0;
                for (int yy : ys)
                    for (int xx : xs) {
                        const size_t i = (size_t(yy) * size_t(src.w) + size_t(xx)) * size_t(channels) + size_t(c);
                        sum += is8bit ? double(src.u8[i]) : double(src.f32[i]);
                    }
                const size_t o = (size_t(y) * size_t(dst.w) + size_t(x)) * size_t(channels) + size_t(c);
                if (is8bit) dst.u8[o] = uint8_t(std::lround(sum / 4.0));
                else dst.f32[o] = float(sum / 4.0);
            }
        }
    return dst;
}

std::string mib(double bytes) {
    const double m = bytes / double(1 << 20);
    return std::to_string(static_cast<long long>(std::ceil(m))) + " MiB";
}

// Opens a texture named in code (no loader descriptor): once, without
// blocking on a FIFO; only regular files are read.
int openTexture(const std::string& path, std::string& why) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
    if (fd < 0) why = std::strerror(errno);
    return fd;
}

}  // namespace

struct TextureCache::Impl {
    std::vector<Texture> textures;
    uint64_t bytes = 0;

    // Decodes texture from `fd` within `left` bytes; returns false with `why`.
    bool decode(Texture& tex, int fd, const std::string& name, uint64_t left, std::string& why) {
        struct stat st {};
        if (::fstat(fd, &st) != 0) {
            why = std::strerror(errno);
            return false;
        }
        if (!S_ISREG(st.st_mode)) {
            why = "it is not a regular file";
            return false;
        }
        const oiio::Api* api = nullptr;
        try {
            api = &oiioLibrary();
        } catch (const Error& e) {
            why = e.what();
            return false;
        }
        oiio::DecodeRequest rq;
        rq.fd = fd;
        rq.name = name;
        rq.maxChannels = 3;
        rq.floatPixels = false;
        // MIP levels add a third to level 0; the module checks level 0 against the rest, from the header alone.
        rq.maxBytes = std::max<uint64_t>(1, left / 4 * 3);
        oiio::Decoded d;
        const oiio::Status status = api->decode(rq, d, why);
        if (status == oiio::Status::OverBudget && d.width == 0) {
            why = "the file alone is " + mib(double(d.fileBytes)) + ", more than the " + mib(double(left)) +
                  " left of the texture budget";
            return false;
        }
        if (status == oiio::Status::OverBudget) {
            const double texels = double(d.width) * double(d.height);
            const double need = texels * std::min(d.channels, 3) * (d.floatData || d.bytesPerChannel != 1 ? 4 : 1) * 4 / 3;
            why = "its header says " + std::to_string(d.width) + "x" + std::to_string(d.height) + " pixels, " +
                  mib(need) + " decoded with its MIP levels, more than the " + mib(double(left)) +
                  " left of the texture budget";
            return false;
        }
        if (status != oiio::Status::Ok) return false;
        tex.is8bit = d.type == oiio::PixelType::U8;
        tex.channels = d.decodedChannels >= 3 ? 3 : 1;
        // Files say what they hold through oiio:ColorSpace; without it, 8-bit
        // images are taken to be sRGB (what PNG and JPEG textures almost always are).
        const std::string& cs = d.colorSpace;
        tex.srgb = !cs.empty() ? (cs.size() >= 4 && (cs.compare(0, 4, "sRGB") == 0 || cs.compare(0, 4, "srgb") == 0 ||
                                                     cs.compare(0, 4, "SRGB") == 0))
                               : (d.bytesPerChannel == 1 && !d.floatData);
        Level base;
        base.w = d.width;
        base.h = d.height;
        const size_t texels = size_t(d.width) * size_t(d.height);
        // Keep channel 0 of grey (+ alpha) images, the first three of colour ones.
        const int srcCh = d.decodedChannels;
        if (tex.is8bit) {
            if (srcCh == tex.channels) base.u8 = std::move(d.pixels);
            else {
                base.u8.resize(texels * size_t(tex.channels));
                for (size_t i = 0; i < texels; ++i)
                    for (int c = 0; c < tex.channels; ++c) base.u8[i * tex.channels + c] = d.pixels[i * srcCh + c];
            }
        } else {
            base.f32.resize(texels * size_t(tex.channels));
            const float* src = reinterpret_cast<const float*>(d.pixels.data());
            for (size_t i = 0; i < texels; ++i)
                for (int c = 0; c < tex.channels; ++c) base.f32[i * tex.channels + c] = src[i * srcCh + c];
        }
        d.pixels = {};
        tex.levels.push_back(std::move(base));
        while (tex.levels.back().w > 1 || tex.levels.back().h > 1)
            tex.levels.push_back(downsample(tex.levels.back(), tex.channels, tex.is8bit));
        for (const Level& l : tex.levels) bytes += l.u8.size() + l.f32.size() * sizeof(float);
        return true;
    }
};

TextureCache::TextureCache(const std::vector<std::string>& paths, const Logger& log, const std::vector<int>& fds,
                           TextureBudget budget)
    : impl_(std::make_unique<Impl>()) {
    impl_->textures.resize(paths.size());
    for (size_t i = 0; i < paths.size(); ++i) {
        Texture& tex = impl_->textures[i];
        std::string why;
        const bool handedOver = i < fds.size() && fds[i] >= 0;
        const int fd = handedOver ? fds[i] : openTexture(paths[i], why);
        bool ok = false;
        if (fd >= 0) {
            const uint64_t left = budget.maxBytes > impl_->bytes ? budget.maxBytes - impl_->bytes : 0;
            try {
                ok = impl_->decode(tex, fd, paths[i], left, why);
            } catch (const std::bad_alloc&) {
                why = "out of memory while decoding it";
            }
            if (!handedOver) ::close(fd);
        }
        if (!ok) {
            tex = Texture{};
            std::replace(why.begin(), why.end(), '\n', ' ');  // keep the warning on one line
            log.warn(paths[i] + ": cannot read texture" + (why.empty() ? std::string() : " (" + why + ")") +
                     "; rendering without it");
            continue;
        }
        tex.enabled = true;
    }
}

TextureCache::~TextureCache() = default;

size_t TextureCache::size() const { return impl_->textures.size(); }

uint64_t TextureCache::memoryBytes() const { return impl_->bytes; }

bool TextureCache::enabled(int texture) const {
    return texture >= 0 && static_cast<size_t>(texture) < impl_->textures.size() && impl_->textures[texture].enabled;
}

Rgb TextureCache::lookup(int texture, Vec2f uv, float footprint) const {
    if (!enabled(texture) || !std::isfinite(uv.x) || !std::isfinite(uv.y)) return Rgb(1.f);
    const Texture& tex = impl_->textures[texture];
    const float fp = std::isfinite(footprint) && footprint > 0.f ? footprint : 0.f;
    // OBJ texture coordinates have v pointing up; image rows go down.
    const float s = uv.x, t = 1.f - uv.y;
    // The level whose texels are as wide as the footprint, blended with the next.
    const Level& base = tex.levels.front();
    const float width = fp * float(std::max(base.w, base.h));
    const float lod = width > 1.f ? std::min(std::log2(width), float(tex.levels.size() - 1)) : 0.f;
    const int l0 = int(lod);
    const float frac = lod - float(l0);
    float c[3] = {1.f, 1.f, 1.f};
    tex.bilinear(tex.levels[size_t(l0)], s, t, c);
    if (frac > 0.f && size_t(l0) + 1 < tex.levels.size()) {
        float n[3] = {1.f, 1.f, 1.f};
        tex.bilinear(tex.levels[size_t(l0) + 1], s, t, n);
        for (int k = 0; k < tex.channels; ++k) c[k] = (1.f - frac) * c[k] + frac * n[k];
    }
    if (tex.channels < 3) c[1] = c[2] = c[0];
    if (tex.srgb)
        for (float& v : c) v = srgbToLinear(std::clamp(v, 0.f, 1.f));
    return {c[0], c[1], c[2]};
}

}  // namespace penumbra
