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
#include "core/parallel.h"

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

// One texture on its way in: its descriptor, what the header said, and why it was refused.
struct Pending {
    int fd = -1;
    bool owned = false;  // opened here (no descriptor handed over): closed here
    bool ok = false;
    uint64_t need = 0;   // decoded bytes with MIP levels, from the header
    oiio::Decoded header;
    std::string why;
};

uint64_t bytesWithMips(const oiio::Decoded& d) {
    const uint64_t level0 = uint64_t(d.width) * uint64_t(d.height) * uint64_t(std::min(d.channels, 3)) *
                            (d.bytesPerChannel == 1 && !d.floatData ? 1u : 4u);
    return level0 + level0 / 3;
}

// Header of `p.fd`: a regular file, an image, and within `budget` on its own.
void readHeader(const oiio::Api& api, const std::string& name, uint64_t budget, Pending& p) {
    struct stat st {};
    if (::fstat(p.fd, &st) != 0) {
        p.why = std::strerror(errno);
        return;
    }
    if (!S_ISREG(st.st_mode)) {
        p.why = "it is not a regular file";
        return;
    }
    oiio::DecodeRequest rq;
    rq.fd = p.fd;
    rq.name = name;
    rq.maxChannels = 3;
    rq.floatPixels = false;
    rq.maxBytes = std::max<uint64_t>(1, budget / 4 * 3);
    rq.headerOnly = true;
    const oiio::Status status = api.decode(rq, p.header, p.why);
    if (status == oiio::Status::OverBudget && p.header.width == 0) {
        p.why = "the file alone is " + mib(double(p.header.fileBytes)) + ", more than the " + mib(double(budget)) +
                " texture budget";
        return;
    }
    p.need = bytesWithMips(p.header);
    if (status == oiio::Status::OverBudget) p.need = std::max(p.need, budget + 1);  // reported with the running total
    else if (status != oiio::Status::Ok) return;
    p.ok = true;
}

// Decodes `p` completely and MIP-maps it; false with p.why.
bool decodePixels(const oiio::Api& api, const std::string& name, Pending& p, Texture& tex) {
    oiio::DecodeRequest rq;
    rq.fd = p.fd;
    rq.name = name;
    rq.maxChannels = 3;
    rq.floatPixels = false;
    rq.maxBytes = p.need;  // the file may have changed since its header was read
    oiio::Decoded d;
    const oiio::Status status = api.decode(rq, d, p.why);
    if (status == oiio::Status::OverBudget) p.why = "it grew past the texture budget while being read";
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
    return true;
}

}  // namespace

struct TextureCache::Impl {
    std::vector<Texture> textures;
    uint64_t bytes = 0;
};

TextureCache::TextureCache(const std::vector<std::string>& paths, const Logger& log, const std::vector<int>& fds,
                           TextureBudget budget)
    : impl_(std::make_unique<Impl>()) {
    const size_t n = paths.size();
    impl_->textures.resize(n);
    std::vector<Pending> pending(n);
    const oiio::Api* api = nullptr;
    std::string noModule;
    if (n > 0) {
        try {
            api = &oiioLibrary();
        } catch (const Error& e) {
            noModule = e.what();
        }
    }
    for (size_t i = 0; i < n; ++i) {
        Pending& p = pending[i];
        if (i < fds.size() && fds[i] >= 0) {
            p.fd = fds[i];
        } else {
            p.fd = openTexture(paths[i], p.why);
            p.owned = p.fd >= 0;
        }
        if (!api && p.fd >= 0) p.why = noModule;
    }
    // Headers in parallel, then the budget in texture order (the same textures
    // fit whatever the thread count), then the pixels of those that fit in parallel.
    if (api)
        parallelFor(n, 0, [&](size_t i) {
            if (pending[i].fd >= 0) readHeader(*api, paths[i], budget.maxBytes, pending[i]);
        });
    uint64_t total = 0;
    for (size_t i = 0; i < n; ++i) {
        Pending& p = pending[i];
        if (!p.ok) continue;
        const uint64_t left = budget.maxBytes - total;
        if (p.need > left) {
            p.ok = false;
            p.why = "its header says " + std::to_string(p.header.width) + "x" + std::to_string(p.header.height) +
                    " pixels, " + mib(double(bytesWithMips(p.header))) + " decoded with its MIP levels, more than the " +
                    mib(double(left)) + " left of the texture budget";
            continue;
        }
        total += p.need;
    }
    if (api)
        parallelFor(n, 0, [&](size_t i) {
            Pending& p = pending[i];
            if (!p.ok) return;
            try {
                p.ok = decodePixels(*api, paths[i], p, impl_->textures[i]);
            } catch (const std::bad_alloc&) {
                p.ok = false;
                p.why = "out of memory while decoding it";
            }
            if (!p.ok) impl_->textures[i] = Texture{};
        });
    for (size_t i = 0; i < n; ++i) {
        Pending& p = pending[i];
        if (p.owned) ::close(p.fd);
        Texture& tex = impl_->textures[i];
        if (!p.ok) {
            std::replace(p.why.begin(), p.why.end(), '\n', ' ');  // keep the warning on one line
            log.warn(paths[i] + ": cannot read texture" + (p.why.empty() ? std::string() : " (" + p.why + ")") +
                     "; rendering without it");
            continue;
        }
        tex.enabled = true;
        for (const Level& l : tex.levels) impl_->bytes += l.u8.size() + l.f32.size() * sizeof(float);
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
