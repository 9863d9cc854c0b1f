// pnb::Framebuffer: the accumulated samples of a render window, read back
// or written as an image.
#include "api/api_internal.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/image_io.h"

namespace pnb {

namespace {

uint64_t physicalMemoryBytes() {
    long pages = ::sysconf(_SC_PHYS_PAGES), size = ::sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? uint64_t(pages) * uint64_t(size) : 0;
}

void copyInto(const std::vector<float>& src, float* dst, size_t floatCount, const char* what) {
    require(dst != nullptr || src.empty(), std::string(what) + ": destination is null");
    require(floatCount >= src.size(), std::string(what) + ": destination holds " + std::to_string(floatCount) +
                                          " floats, the image needs " + std::to_string(src.size()));
    std::copy(src.begin(), src.end(), dst);
}

}  // namespace

// ---------------------------------------------------------------- Framebuffer

Framebuffer::Framebuffer() : impl_(std::make_unique<Impl>()) {}

Framebuffer newFramebuffer(const RenderSettings& s) {
    const CropWindow w = renderWindow(s);
    const uint64_t bytes = pn::Film::bytesNeeded(int64_t(w.x1 - w.x0) * (w.y1 - w.y0), s.aovs);
    const uint64_t ram = physicalMemoryBytes();
    if (ram && bytes > ram / 2)
        fail(ErrorCode::OutOfMemory, "a " + std::to_string(w.x1 - w.x0) + "x" + std::to_string(w.y1 - w.y0) +
                                         " framebuffer needs " + std::to_string(bytes >> 20) +
                                         " MiB, more than half of this machine's memory");
    Framebuffer image;
    FramebufferImpl& impl = Access::of(image);
    impl.film = pn::makeFilm(s);
    impl.seed = s.seed;
    return image;
}

Framebuffer::Framebuffer(const RenderSettings& settings) : impl_(std::make_unique<Impl>()) {
    guarded([&] {
        pn::validateSettings(settings);
        *this = newFramebuffer(settings);
    });
}

std::uint64_t Framebuffer::bytesNeeded(const RenderSettings& settings) {
    return guarded([&] {
        pn::validateSettings(settings);
        const CropWindow w = renderWindow(settings);
        return pn::Film::bytesNeeded(int64_t(w.x1 - w.x0) * (w.y1 - w.y0), settings.aovs);
    });
}

Framebuffer::~Framebuffer() = default;
Framebuffer::Framebuffer(const Framebuffer& o) : impl_(guarded([&] { return std::make_unique<Impl>(*o.impl_); })) {}
Framebuffer& Framebuffer::operator=(const Framebuffer& o) {
    if (this != &o) impl_ = guarded([&] { return std::make_unique<Impl>(*o.impl_); });
    return *this;
}
Framebuffer::Framebuffer(Framebuffer&& o) noexcept : impl_(std::move(o.impl_)) {
    o.impl_ = std::unique_ptr<Impl>(new (std::nothrow) Impl());
}
Framebuffer& Framebuffer::operator=(Framebuffer&& o) noexcept {
    std::swap(impl_, o.impl_);
    return *this;
}

int Framebuffer::width() const noexcept { return impl_ ? impl_->film.width() : 0; }
int Framebuffer::height() const noexcept { return impl_ ? impl_->film.height() : 0; }
int Framebuffer::fullWidth() const noexcept { return impl_ ? impl_->film.fullWidth() : 0; }
int Framebuffer::fullHeight() const noexcept { return impl_ ? impl_->film.fullHeight() : 0; }
CropWindow Framebuffer::window() const noexcept {
    if (!impl_) return {};
    const CropWindow& w = impl_->film.window();
    return CropWindow{w.x0, w.y0, w.x1, w.y1};
}
std::uint32_t Framebuffer::sampleCount() const noexcept { return impl_ ? impl_->film.sampleCount() : 0; }
bool Framebuffer::hasAovs() const noexcept { return impl_ && impl_->film.hasAovs(); }
bool Framebuffer::incomplete() const noexcept { return impl_ && impl_->incomplete; }

std::vector<float> Framebuffer::rgba() const {
    return guarded([&] { return impl_->film.radianceBuffer(4); });
}

void Framebuffer::readRgba(float* dst, std::size_t floatCount) const {
    guarded([&] {
        const pn::Film& f = impl_->film;
        const size_t n = size_t(f.width()) * size_t(f.height());
        require(floatCount >= 4 * n, "readRgba: destination holds " + std::to_string(floatCount) +
                                         " floats, the image needs " + std::to_string(4 * n));
        require(dst != nullptr || n == 0, "readRgba: destination is null");
        for (size_t i = 0; i < n; ++i) {
            const pn::Rgb L = f.radiance(i);
            dst[4 * i] = L.r;
            dst[4 * i + 1] = L.g;
            dst[4 * i + 2] = L.b;
            dst[4 * i + 3] = 1.f;
        }
    });
}

std::vector<float> Framebuffer::albedo() const {
    return guarded([&] {
        const pn::Film& f = impl_->film;
        require(f.hasAovs(), "albedo: the framebuffer has no AOVs (set RenderSettings::aovs)");
        const size_t n = size_t(f.width()) * size_t(f.height());
        std::vector<float> v(3 * n);
        for (size_t i = 0; i < n; ++i) {
            const pn::Rgb a = f.albedo(i);
            v[3 * i] = a.r;
            v[3 * i + 1] = a.g;
            v[3 * i + 2] = a.b;
        }
        return v;
    });
}

std::vector<float> Framebuffer::normals() const {
    return guarded([&] {
        const pn::Film& f = impl_->film;
        require(f.hasAovs(), "normals: the framebuffer has no AOVs (set RenderSettings::aovs)");
        const size_t n = size_t(f.width()) * size_t(f.height());
        std::vector<float> v(3 * n);
        for (size_t i = 0; i < n; ++i) {
            const pn::Vec3f nn = f.normal(i);
            v[3 * i] = nn.x;
            v[3 * i + 1] = nn.y;
            v[3 * i + 2] = nn.z;
        }
        return v;
    });
}

std::vector<float> Framebuffer::depth() const {
    return guarded([&] {
        const pn::Film& f = impl_->film;
        require(f.hasAovs(), "depth: the framebuffer has no AOVs (set RenderSettings::aovs)");
        const size_t n = size_t(f.width()) * size_t(f.height());
        std::vector<float> v(n);
        for (size_t i = 0; i < n; ++i) v[i] = f.depth(i);
        return v;
    });
}

void Framebuffer::readAlbedo(float* dst, std::size_t floatCount) const {
    const std::vector<float> v = albedo();
    guarded([&] { copyInto(v, dst, floatCount, "readAlbedo"); });
}
void Framebuffer::readNormals(float* dst, std::size_t floatCount) const {
    const std::vector<float> v = normals();
    guarded([&] { copyInto(v, dst, floatCount, "readNormals"); });
}
void Framebuffer::readDepth(float* dst, std::size_t floatCount) const {
    const std::vector<float> v = depth();
    guarded([&] { copyInto(v, dst, floatCount, "readDepth"); });
}

Color Framebuffer::pixel(int x, int y) const {
    return guarded([&] {
        const pn::Film& f = impl_->film;
        require(x >= 0 && y >= 0 && x < f.width() && y < f.height(),
                "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") lies outside the " +
                    std::to_string(f.width()) + "x" + std::to_string(f.height()) + " framebuffer");
        return out(f.radiance(size_t(y) * size_t(f.width()) + size_t(x)));
    });
}

void Framebuffer::clear() {
    impl_->film.clear();
    impl_->incomplete = false;
    impl_->renderSeconds = 0.0;
}

void Framebuffer::paste(const Framebuffer& tile) {
    guarded([&] {
        impl_->film.paste(tile.impl_->film);
        impl_->renderSeconds += tile.impl_->renderSeconds;
        impl_->incomplete = impl_->incomplete || tile.impl_->incomplete;
    });
}

namespace {
// What travels beside the film: the seed and render time of its metadata.
struct FramebufferTrailer {
    std::uint64_t seed;
    double renderSeconds;
    std::uint64_t incomplete;
};
}  // namespace

std::vector<std::uint8_t> Framebuffer::serialize() const {
    return guarded([&] {
        std::vector<std::uint8_t> bytes = impl_->film.serialize();
        const FramebufferTrailer t{impl_->seed, impl_->renderSeconds, impl_->incomplete ? 1u : 0u};
        const auto* p = reinterpret_cast<const std::uint8_t*>(&t);
        bytes.insert(bytes.end(), p, p + sizeof t);
        return bytes;
    });
}

Framebuffer Framebuffer::deserialize(const std::uint8_t* data, std::size_t size) {
    Framebuffer f;
    guarded([&] {
        require(data != nullptr && size >= sizeof(FramebufferTrailer), "deserialize: not a serialized framebuffer");
        FramebufferTrailer t;
        std::memcpy(&t, data + size - sizeof t, sizeof t);
        f.impl_->film = pn::Film::deserialize(data, size - sizeof t);
        f.impl_->seed = t.seed;
        f.impl_->renderSeconds = t.renderSeconds;
        f.impl_->incomplete = t.incomplete != 0;
    });
    return f;
}

void Framebuffer::writeImage(const std::string& path, const ImageOptions& options) const {
    guarded([&] {
        require(impl_->film.width() > 0, path + ": cannot write an empty framebuffer");
        require(std::isfinite(options.exposure), path + ": exposure must be finite");
        pn::ImageWriteOptions wo;
        wo.exposure = options.exposure;
        wo.aovs = options.aovs;
        // A crop's EXR says where its pixels lie in the full frame.
        const pn::CropWindow& w = impl_->film.window();
        wo.dataOriginX = w.x0;
        wo.dataOriginY = w.y0;
        wo.fullWidth = impl_->film.fullWidth();
        wo.fullHeight = impl_->film.fullHeight();
        wo.metadata = pn::ImageMetadata{int(impl_->film.sampleCount()), impl_->seed, impl_->renderSeconds,
                                        std::string("Penumbra ") + PENUMBRA_VERSION};
        pn::writeImage(path, impl_->film, wo);
    });
}

void checkImagePath(const std::string& path) {
    guarded([&] { pn::checkWritable(path); });
}

}  // namespace pnb
