#include "core/texture_cache.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <new>
#include <string>

#include "core/error.h"
#include "core/image_io.h"
#include "core/oiio_library.h"
#include "core/parallel.h"
#include "core/srgb8.h"

namespace penumbra {
namespace {

// Linear values of the 8-bit sRGB codes: texels are decoded as they are read,
// so that filtering and MIP averaging happen on light, not on its encoding.
const std::array<float, 256> kSrgbDecode = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = srgbToLinear(float(i) / 255.f);
    return t;
}();

// One MIP level: texels of 1 to 4 channels (grey, grey + alpha, RGB, RGBA), 8-bit or float, row 0 on top.
struct Level {
    int w = 0, h = 0;
    std::vector<uint8_t> u8;
    std::vector<float> f32;
};

// The remainder of an integral v by period, in [0, period): by integers where v
// fits them (fmod's exact loop is slow, and every filtered lookup wraps four
// indices), else by fmod; both are exact, so the value is the same.
double wrapped(double v, int period) {
    if (std::fabs(v) < 0x1p52) {  // false for NaN: fmod's way
        const int64_t m = int64_t(v) % period;
        return double(m < 0 ? m + period : m);
    }
    const double m = std::fmod(v, double(period));
    return m < 0 ? m + period : m;
}

// The texel index along an axis of n texels for the texel at (integral) v,
// which may lie anywhere: glTF's wrap modes.
int wrapIndex(double v, int n, TextureWrap mode) {
    switch (mode) {
        case TextureWrap::ClampToEdge: return v < 0.0 ? 0 : v >= double(n) ? n - 1 : int(v);
        case TextureWrap::MirroredRepeat: {
            int i = int(wrapped(v, 2 * n));
            if (i >= 2 * n) i = 0;
            return i < n ? i : 2 * n - 1 - i;
        }
        case TextureWrap::Repeat: break;
    }
    const int i = int(wrapped(v, n));
    return i >= n ? 0 : i;
}

// The index after the texel at v and index i: what the bilinear filter blends with.
int nextIndex(double v, int i, int n, TextureWrap mode) {
    if (mode == TextureWrap::Repeat) return i + 1 == n ? 0 : i + 1;
    return wrapIndex(v + 1.0, n, mode);
}

struct Texture {
    std::vector<Level> levels;
    int channels = 0;  // 1 to 4
    bool is8bit = false;
    int srgbChannels = 0;  // leading 8-bit channels that hold sRGB-encoded colour (alpha never does)
    bool enabled = false;
    bool transparent = false;  // an alpha channel with a texel below 1

    float texel(const Level& l, int x, int y, int c) const {
        const size_t i = (size_t(y) * size_t(l.w) + size_t(x)) * size_t(channels) + size_t(c);
        if (!is8bit) return l.f32[i];
        return c < srgbChannels ? kSrgbDecode[l.u8[i]] : float(l.u8[i]) * (1.f / 255.f);
    }
    // Bilinear; (s, t) in texture space, t pointing down the rows.
    void bilinear(const Level& l, float s, float t, TextureWrap ws, TextureWrap wt, float out[4]) const {
        const float x = s * float(l.w) - 0.5f, y = t * float(l.h) - 0.5f;
        const float fx0 = std::floor(x), fy0 = std::floor(y);
        const float ax = x - fx0, ay = y - fy0;
        const int x0 = wrapIndex(fx0, l.w, ws), y0 = wrapIndex(fy0, l.h, wt);
        const int x1 = nextIndex(fx0, x0, l.w, ws), y1 = nextIndex(fy0, y0, l.h, wt);
        for (int c = 0; c < channels; ++c) {
            const float top = (1.f - ax) * texel(l, x0, y0, c) + ax * texel(l, x1, y0, c);
            const float bottom = (1.f - ax) * texel(l, x0, y1, c) + ax * texel(l, x1, y1, c);
            out[c] = (1.f - ay) * top + ay * bottom;
        }
    }
    void nearest(const Level& l, float s, float t, TextureWrap ws, TextureWrap wt, float out[4]) const {
        const int x = wrapIndex(std::floor(s * float(l.w)), l.w, ws), y = wrapIndex(std::floor(t * float(l.h)), l.h, wt);
        for (int c = 0; c < channels; ++c) out[c] = texel(l, x, y, c);
    }
    // The raw channels at (s, t), trilinear over the MIP level whose texels are as wide as the footprint.
    void filtered(float s, float t, float footprint, TextureWrap ws, TextureWrap wt, TextureFilter filter,
                  float c[4]) const {
        if (filter == TextureFilter::Nearest) return nearest(levels.front(), s, t, ws, wt, c);
        const float fp = std::isfinite(footprint) && footprint > 0.f ? footprint : 0.f;
        const Level& base = levels.front();
        const float width = fp * float(std::max(base.w, base.h));
        const float lod = width > 1.f ? std::min(std::log2(width), float(levels.size() - 1)) : 0.f;
        const int l0 = int(lod);
        const float frac = lod - float(l0);
        bilinear(levels[size_t(l0)], s, t, ws, wt, c);
        if (frac > 0.f && size_t(l0) + 1 < levels.size()) {
            float n[4] = {1.f, 1.f, 1.f, 1.f};
            bilinear(levels[size_t(l0) + 1], s, t, ws, wt, n);
            for (int k = 0; k < channels; ++k) c[k] = (1.f - frac) * c[k] + frac * n[k];
        }
    }
};

// Box-filtered half-size level (odd sizes repeat their last row/column),
// averaged in linear values; sRGB channels are encoded again to their nearest code.
Level downsample(const Texture& tex, const Level& src, const Srgb8& encode) {
    const int channels = tex.channels;
    const bool is8bit = tex.is8bit;
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
                // Linear 8-bit channels average their codes exactly.
                const bool codes = is8bit && c >= tex.srgbChannels;
                double sum = 0.0;
                for (int yy : ys)
                    for (int xx : xs) {
                        const size_t i = (size_t(yy) * size_t(src.w) + size_t(xx)) * size_t(channels) + size_t(c);
                        sum += codes ? double(src.u8[i]) : double(tex.texel(src, xx, yy, c));
                    }
                const size_t o = (size_t(y) * size_t(dst.w) + size_t(x)) * size_t(channels) + size_t(c);
                if (codes) dst.u8[o] = uint8_t(std::lround(sum / 4.0));
                else if (is8bit) dst.u8[o] = encode(float(sum / 4.0));
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

// One texture on its way in: where its bytes are, what the header said, and why it was refused.
struct Pending {
    int fd = -1;
    bool owned = false;  // opened here (no descriptor handed over): closed here
    const std::vector<unsigned char>* bytes = nullptr;
    bool ok = false;
    uint64_t need = 0;   // decoded bytes with MIP levels, from the header
    oiio::Decoded header;
    std::string why;
};

constexpr int kMaxChannels = 4;

uint64_t bytesWithMips(const oiio::Decoded& d) {
    const uint64_t level0 = uint64_t(d.width) * uint64_t(d.height) * uint64_t(std::min(d.channels, kMaxChannels)) *
                            (d.bytesPerChannel == 1 && !d.floatData ? 1u : 4u);
    return level0 + level0 / 3;
}

oiio::DecodeRequest requestFor(const Pending& p, const std::string& name) {
    oiio::DecodeRequest rq;
    rq.fd = p.fd;
    if (p.bytes) {
        rq.bytes = p.bytes->data();
        rq.size = p.bytes->size();
    }
    rq.name = name;
    rq.maxChannels = kMaxChannels;
    rq.floatPixels = false;
    return rq;
}

// Header of the texture: a regular file (or bytes), an image, and within `budget` on its own.
void readHeader(const oiio::Api& api, const std::string& name, uint64_t budget, Pending& p) {
    struct stat st {};
    if (!p.bytes && ::fstat(p.fd, &st) != 0) {
        p.why = std::strerror(errno);
        return;
    }
    if (!p.bytes && !S_ISREG(st.st_mode)) {
        p.why = "it is not a regular file";
        return;
    }
    oiio::DecodeRequest rq = requestFor(p, name);
    rq.maxBytes = std::max<uint64_t>(1, budget / 4 * 3);
    rq.headerOnly = true;
    const oiio::Status status = api.decode(rq, p.header, p.why);
    if (status == oiio::Status::OverBudget && p.header.width == 0) {
        p.why = std::string(p.bytes ? "the encoded image" : "the file") + " alone is " + mib(double(p.header.fileBytes)) +
                ", more than the " + mib(double(budget)) + " texture budget";
        return;
    }
    p.need = bytesWithMips(p.header);
    if (status == oiio::Status::OverBudget) p.need = std::max(p.need, budget + 1);  // reported with the running total
    else if (status != oiio::Status::Ok) return;
    p.ok = true;
}

// Whether the colour channels are sRGB-encoded: as the source says, else as
// the file says through oiio:ColorSpace; without a word, 8-bit images are
// taken to be sRGB (what PNG and JPEG textures almost always are).
bool isSrgb(TextureColorSpace space, const oiio::Decoded& d) {
    if (space != TextureColorSpace::FromFile) return space == TextureColorSpace::Srgb;
    const std::string& cs = d.colorSpace;
    if (cs.empty()) return d.bytesPerChannel == 1 && !d.floatData;
    return cs.size() >= 4 && (cs.compare(0, 4, "sRGB") == 0 || cs.compare(0, 4, "srgb") == 0 || cs.compare(0, 4, "SRGB") == 0);
}

bool anyTransparent(const Level& l, int channels, bool is8bit) {
    if (channels != 2 && channels != 4) return false;
    const size_t n = size_t(l.w) * size_t(l.h);
    for (size_t i = 0; i < n; ++i) {
        const size_t a = i * size_t(channels) + size_t(channels - 1);
        if (is8bit ? l.u8[a] < 255 : l.f32[a] < 1.f) return true;
    }
    return false;
}

// Decodes `p` completely and MIP-maps it; false with p.why.
bool decodePixels(const oiio::Api& api, const std::string& name, TextureColorSpace space, const Srgb8& encode,
                  Pending& p, Texture& tex) {
    oiio::DecodeRequest rq = requestFor(p, name);
    rq.maxBytes = p.need;  // the file may have changed since its header was read
    oiio::Decoded d;
    const oiio::Status status = api.decode(rq, d, p.why);
    if (status == oiio::Status::OverBudget) p.why = "it grew past the texture budget while being read";
    if (status != oiio::Status::Ok) return false;
    tex.is8bit = d.type == oiio::PixelType::U8;
    tex.channels = std::clamp(d.decodedChannels, 1, kMaxChannels);
    const bool srgb = isSrgb(space, d);
    const int colourChannels = tex.channels >= 3 ? 3 : 1;
    Level base;
    base.w = d.width;
    base.h = d.height;
    if (tex.is8bit) {
        base.u8 = std::move(d.pixels);
        tex.srgbChannels = srgb ? colourChannels : 0;
    } else {
        const size_t n = size_t(d.width) * size_t(d.height) * size_t(tex.channels);
        base.f32.resize(n);
        std::memcpy(base.f32.data(), d.pixels.data(), n * sizeof(float));
        if (srgb)  // float texels are decoded once, here
            for (size_t i = 0; i < n; ++i)
                if (int(i % size_t(tex.channels)) < colourChannels)
                    base.f32[i] = srgbToLinear(std::clamp(base.f32[i], 0.f, 1.f));
    }
    d.pixels = {};
    tex.transparent = anyTransparent(base, tex.channels, tex.is8bit);
    tex.levels.push_back(std::move(base));
    while (tex.levels.back().w > 1 || tex.levels.back().h > 1)
        tex.levels.push_back(downsample(tex, tex.levels.back(), encode));
    return true;
}

}  // namespace

struct TextureCache::Impl {
    std::vector<Texture> textures;
    uint64_t bytes = 0;

    const Texture* usable(int texture) const {
        return texture >= 0 && size_t(texture) < textures.size() && textures[size_t(texture)].enabled
                   ? &textures[size_t(texture)]
                   : nullptr;
    }
};

TextureCache::TextureCache(const std::vector<TextureSource>& sources, const Logger& log, TextureBudget budget)
    : impl_(std::make_unique<Impl>()) {
    const size_t n = sources.size();
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
        const TextureSource& s = sources[i];
        if (s.bytes) {
            p.bytes = s.bytes.get();
        } else if (s.fd >= 0) {
            p.fd = s.fd;
        } else {
            p.fd = openTexture(s.name, p.why);
            p.owned = p.fd >= 0;
        }
        if (!api && (p.fd >= 0 || p.bytes)) p.why = noModule;
    }
    // Headers in parallel, then the budget in texture order (the same textures
    // fit whatever the thread count), then the pixels of those that fit in parallel.
    if (api)
        parallelFor(n, 0, [&](size_t i) {
            if (pending[i].fd >= 0 || pending[i].bytes) readHeader(*api, sources[i].name, budget.maxBytes, pending[i]);
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
    if (api) {
        const Srgb8 encode;
        parallelFor(n, 0, [&](size_t i) {
            Pending& p = pending[i];
            if (!p.ok) return;
            try {
                p.ok = decodePixels(*api, sources[i].name, sources[i].colorSpace, encode, p, impl_->textures[i]);
            } catch (const std::bad_alloc&) {
                p.ok = false;
                p.why = "out of memory while decoding it";
            }
            if (!p.ok) impl_->textures[i] = Texture{};
        });
    }
    for (size_t i = 0; i < n; ++i) {
        Pending& p = pending[i];
        if (p.owned) ::close(p.fd);
        Texture& tex = impl_->textures[i];
        if (!p.ok) {
            std::replace(p.why.begin(), p.why.end(), '\n', ' ');  // keep the warning on one line
            log.warn(sources[i].name + ": cannot read texture" + (p.why.empty() ? std::string() : " (" + p.why + ")") +
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

bool TextureCache::enabled(int texture) const { return impl_->usable(texture) != nullptr; }

bool TextureCache::hasTransparency(int texture) const {
    const Texture* tex = impl_->usable(texture);
    return tex && tex->transparent;
}

Rgb TextureCache::lookup(int texture, Vec2f uv, float footprint) const {
    const Texture* tex = impl_->usable(texture);
    if (!tex || !std::isfinite(uv.x) || !std::isfinite(uv.y)) return Rgb(1.f);
    // OBJ texture coordinates have v pointing up; image rows go down.
    float c[4] = {1.f, 1.f, 1.f, 1.f};
    tex->filtered(uv.x, 1.f - uv.y, footprint, TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Linear, c);
    if (tex->channels < 3) c[1] = c[2] = c[0];
    return {c[0], c[1], c[2]};
}

Rgba TextureCache::sample(const TextureRef& slot, Vec2f uv, float footprint) const {
    const Texture* tex = impl_->usable(slot.texture);
    if (!tex || !std::isfinite(uv.x) || !std::isfinite(uv.y)) return {};
    const Vec2f st = slot.imageCoordinates(uv);
    if (!std::isfinite(st.x) || !std::isfinite(st.y)) return {};
    // The transform stretches the footprint by the square root of its area scale.
    const float stretch = std::sqrt(std::fabs(slot.m[0] * slot.m[4] - slot.m[1] * slot.m[3]));
    float c[4] = {1.f, 1.f, 1.f, 1.f};
    tex->filtered(st.x, st.y, footprint * stretch, slot.wrapS, slot.wrapT, slot.filter, c);
    Rgba out;
    switch (tex->channels) {
        case 1: out = {Rgb(c[0]), 1.f}; break;
        case 2: out = {Rgb(c[0]), c[1]}; break;
        case 3: out = {Rgb(c[0], c[1], c[2]), 1.f}; break;
        default: out = {Rgb(c[0], c[1], c[2]), c[3]}; break;
    }
    return out;
}

float TextureCache::sampleChannel(const TextureRef& slot, Vec2f uv, float footprint) const {
    const Rgba t = sample(slot, uv, footprint);
    const Texture* tex = impl_->usable(slot.texture);
    switch (slot.channel) {
        case 0: return t.rgb.r;
        case 1: return t.rgb.g;
        case 2: return t.rgb.b;
        default: return tex && (tex->channels == 2 || tex->channels == 4) ? t.a : t.rgb.r;  // MTL's matte channel
    }
}

Vec3f TextureCache::sampleNormal(const TextureRef& slot, Vec2f uv, float footprint, float scale) const {
    if (!impl_->usable(slot.texture)) return {0.f, 0.f, 1.f};
    const Rgb c = sample(slot, uv, footprint).rgb;
    const Vec3f n{(2.f * c.r - 1.f) * scale, (2.f * c.g - 1.f) * scale, 2.f * c.b - 1.f};
    const float l = length(n);
    return l > 0.f && std::isfinite(l) ? n / l : Vec3f{0.f, 0.f, 1.f};
}

Vec3f TextureCache::sampleHeightNormal(const TextureRef& slot, Vec2f uv, float footprint, float scale) const {
    const Texture* tex = impl_->usable(slot.texture);
    const Vec3f flat{0.f, 0.f, 1.f};
    if (!tex || !std::isfinite(uv.x) || !std::isfinite(uv.y)) return flat;
    // Texels crossed per unit of u and of v, through the slot's transform ((s, t) = M (u, 1 - v) + offset).
    const Level& base = tex->levels.front();
    const float perU = std::hypot(float(base.w) * slot.m[0], float(base.h) * slot.m[3]);
    const float perV = std::hypot(float(base.w) * slot.m[1], float(base.h) * slot.m[4]);
    if (!(perU > 0.f) || !(perV > 0.f) || !std::isfinite(perU) || !std::isfinite(perV)) return flat;
    const float fp = std::isfinite(footprint) && footprint > 0.f ? footprint : 0.f;
    const float du = std::max(1.f / perU, fp), dv = std::max(1.f / perV, fp);
    const auto height = [&](float u, float v) { return sampleChannel(slot, {u, v}, fp); };
    const float slopeU = (height(uv.x + du, uv.y) - height(uv.x - du, uv.y)) / (2.f * du * perU);
    const float slopeV = (height(uv.x, uv.y + dv) - height(uv.x, uv.y - dv)) / (2.f * dv * perV);
    const Vec3f n{-scale * slopeU, -scale * slopeV, 1.f};
    const float l = length(n);
    return l > 0.f && std::isfinite(l) ? n / l : flat;
}

}  // namespace penumbra
