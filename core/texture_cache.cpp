#include "core/texture_cache.h"

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include <algorithm>
#include <cmath>
#include <new>
#include <string>

#include "core/image_io.h"

namespace penumbra {
namespace {

// Larger decoded textures are refused (with a warning) rather than allocated.
constexpr double kMaxTextureBytes = 2.0 * double(1 << 30);

// OIIO 2.4's TextureOpt cannot convert colour spaces, so lookups linearise the
// filtered value. Files say what they hold through oiio:ColorSpace; without it,
// 8-bit images are taken to be sRGB (what PNG and JPEG textures almost always are).
bool isSrgb(const OIIO::ImageSpec& spec) {
    std::string cs = spec.get_string_attribute("oiio:ColorSpace");
    if (!cs.empty()) return OIIO::Strutil::iequals(cs, "sRGB") || OIIO::Strutil::istarts_with(cs, "sRGB");
    return spec.format == OIIO::TypeDesc::UINT8;
}

}  // namespace

struct TextureCache::Impl {
    struct Entry {
        OIIO::TextureSystem::TextureHandle* handle = nullptr;
        int channels = 0;
        bool srgb = false;
        bool enabled = false;
    };
    OIIO::TextureSystem* ts = nullptr;
    std::vector<Entry> entries;

    bool fetch(const Entry& e, float s, float t, float footprint, float out[3]) const {
        OIIO::TextureOpt opt;
        opt.swrap = opt.twrap = OIIO::TextureOpt::WrapPeriodic;
        opt.mipmode = OIIO::TextureOpt::MipModeTrilinear;
        opt.interpmode = OIIO::TextureOpt::InterpBilinear;
        // dsdx = dtdy = footprint: an axis-aligned square filter footprint wide.
        return ts->texture(e.handle, nullptr, opt, s, t, footprint, 0.f, 0.f, footprint, 3, out);
    }
};

TextureCache::TextureCache(const std::vector<std::string>& paths, const Logger& log) : impl_(std::make_unique<Impl>()) {
    impl_->ts = OIIO::TextureSystem::create(/*shared=*/false);
    // Textures referenced by OBJ files are plain images; MIP-map them on load for trilinear filtering.
    impl_->ts->attribute("automip", 1);
    impl_->entries.resize(paths.size());
    for (size_t i = 0; i < paths.size(); ++i) {
        Impl::Entry& e = impl_->entries[i];
        OIIO::ustring file(paths[i]);
        e.handle = impl_->ts->get_texture_handle(file);
        OIIO::ImageSpec spec;
        bool ok = e.handle && impl_->ts->good(e.handle) && impl_->ts->get_imagespec(e.handle, nullptr, 0, spec);
        std::string why;
        if (ok) {
            e.channels = spec.nchannels;
            e.srgb = isSrgb(spec);
            // A header may claim any size; OpenImageIO would try to allocate it.
            const double bytes = double(spec.width) * double(spec.height) * double(std::max(spec.depth, 1)) *
                                 double(spec.nchannels) * double(spec.format.size());
            if (bytes > kMaxTextureBytes) {
                ok = false;
                why = "its header claims " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                      " pixels, more than the " + std::to_string(int(kMaxTextureBytes / double(1 << 30))) +
                      " GiB Penumbra accepts for a texture";
            }
        }
        if (ok) {
            // Reading a texel now makes a file with a good header but bad pixels fail here, not mid-render.
            float probe[3];
            try {
                ok = impl_->fetch(e, 0.5f, 0.5f, 0.f, probe);
            } catch (const std::bad_alloc&) {
                ok = false;
                why = "out of memory while reading it";
            }
        }
        if (!ok) {
            if (why.empty()) why = impl_->ts->geterror();
            std::replace(why.begin(), why.end(), '\n', ' ');  // keep the warning on one line
            log.warn(paths[i] + ": cannot read texture" + (why.empty() ? std::string() : " (" + why + ")") +
                     "; rendering without it");
            continue;
        }
        e.enabled = true;
    }
}

TextureCache::~TextureCache() {
    if (impl_ && impl_->ts) OIIO::TextureSystem::destroy(impl_->ts);
}

size_t TextureCache::size() const { return impl_->entries.size(); }

bool TextureCache::enabled(int texture) const {
    return texture >= 0 && static_cast<size_t>(texture) < impl_->entries.size() && impl_->entries[texture].enabled;
}

Rgb TextureCache::lookup(int texture, Vec2f uv, float footprint) const {
    if (!enabled(texture) || !std::isfinite(uv.x) || !std::isfinite(uv.y)) return Rgb(1.f);
    const Impl::Entry& e = impl_->entries[texture];
    float fp = std::isfinite(footprint) && footprint > 0.f ? footprint : 0.f;
    float c[3] = {1.f, 1.f, 1.f};
    // OBJ texture coordinates have v pointing up; image rows (OIIO's t) go down.
    if (!impl_->fetch(e, uv.x, 1.f - uv.y, fp, c)) {
        (void)impl_->ts->geterror();  // clear this thread's error; the texture stays neutral
        return Rgb(1.f);
    }
    if (e.channels < 3) c[1] = c[2] = c[0];  // grey (+ alpha)
    if (e.srgb)
        for (float& v : c) v = srgbToLinear(std::clamp(v, 0.f, 1.f));
    return {c[0], c[1], c[2]};
}

}  // namespace penumbra
