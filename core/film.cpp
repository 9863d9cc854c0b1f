#include "core/film.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "core/error.h"

namespace penumbra {

Film::Film(int fullWidth, int fullHeight, CropWindow window, bool aovs)
    : fullWidth_(fullWidth), fullHeight_(fullHeight), window_(window) {
    const size_t n = size_t(width()) * size_t(height());
    sum_.assign(3 * n, 0.0);
    if (aovs) {
        albedo_.assign(3 * n, 0.0);
        normal_.assign(n, Vec3f{});
        depth_.assign(n, 0.0);
    }
}

uint64_t Film::bytesNeeded(int64_t pixels, bool aovs) {
    uint64_t per = 3 * sizeof(double) + (aovs ? 3 * sizeof(double) + sizeof(Vec3f) + sizeof(double) : 0);
    return uint64_t(pixels) * per;
}

Rgb Film::radiance(size_t i) const {
    if (samples_ == 0) return {};
    double inv = 1.0 / samples_;
    return {float(sum_[3 * i] * inv), float(sum_[3 * i + 1] * inv), float(sum_[3 * i + 2] * inv)};
}

Rgb Film::albedo(size_t i) const {
    if (!samples_) return {};
    const double inv = 1.0 / samples_;
    return {float(albedo_[3 * i] * inv), float(albedo_[3 * i + 1] * inv), float(albedo_[3 * i + 2] * inv)};
}
Vec3f Film::normal(size_t i) const { return samples_ ? normal_[i] / float(samples_) : Vec3f{}; }
float Film::depth(size_t i) const { return samples_ ? float(depth_[i] / samples_) : 0.f; }

std::vector<float> Film::radianceBuffer(int channels) const {
    const size_t n = size_t(width()) * size_t(height());
    std::vector<float> out(n * size_t(channels), 1.f);
    for (size_t i = 0; i < n; ++i) {
        Rgb L = radiance(i);
        out[i * channels] = L.r;
        out[i * channels + 1] = L.g;
        out[i * channels + 2] = L.b;
    }
    return out;
}

void Film::clear() {
    std::fill(sum_.begin(), sum_.end(), 0.0);
    std::fill(albedo_.begin(), albedo_.end(), 0.0);
    std::fill(normal_.begin(), normal_.end(), Vec3f{});
    std::fill(depth_.begin(), depth_.end(), 0.0);
    samples_ = 0;
}

namespace {

// "PNBF" and the layout version, first in every serialized film.
constexpr uint32_t kFilmMagic = 0x46424e50u, kFilmVersion = 1;

// Copies `count` values to `at` and moves past them.
template <class T>
void put(uint8_t*& at, const T* values, size_t count) {
    if (count) std::memcpy(at, values, count * sizeof(T));
    at += count * sizeof(T);
}

template <class T>
void take(const uint8_t*& at, const uint8_t* end, T* values, size_t count) {
    const size_t bytes = count * sizeof(T);
    if (size_t(end - at) < bytes) throw Error(ErrorCode::InvalidArgument, "serialized film: truncated");
    if (bytes) std::memcpy(values, at, bytes);
    at += bytes;
}

std::string windowText(const CropWindow& w) {
    return std::to_string(w.x0) + "," + std::to_string(w.y0) + "," + std::to_string(w.x1) + "," + std::to_string(w.y1);
}

}  // namespace

void Film::paste(const Film& tile) {
    const CropWindow& t = tile.window_;
    if (tile.fullWidth_ != fullWidth_ || tile.fullHeight_ != fullHeight_)
        throw Error(ErrorCode::InvalidArgument, "paste: the tile belongs to a " + std::to_string(tile.fullWidth_) + "x" +
                                                    std::to_string(tile.fullHeight_) + " frame, this film to a " +
                                                    std::to_string(fullWidth_) + "x" + std::to_string(fullHeight_) + " one");
    if (t.x0 < window_.x0 || t.y0 < window_.y0 || t.x1 > window_.x1 || t.y1 > window_.y1)
        throw Error(ErrorCode::InvalidArgument,
                    "paste: tile window " + windowText(t) + " lies outside the film's window " + windowText(window_));
    if (tile.hasAovs() != hasAovs())
        throw Error(ErrorCode::InvalidArgument, "paste: one film has AOVs and the other has not");
    if (samples_ != 0 && tile.samples_ != samples_)
        throw Error(ErrorCode::InvalidArgument, "paste: the tile has " + std::to_string(tile.samples_) +
                                                    " samples per pixel, the film " + std::to_string(samples_));
    for (int y = t.y0; y < t.y1; ++y) {
        const size_t src = tile.index(t.x0, y), dst = index(t.x0, y), n = size_t(t.x1 - t.x0);
        std::copy_n(&tile.sum_[3 * src], 3 * n, &sum_[3 * dst]);
        if (hasAovs()) {
            std::copy_n(&tile.albedo_[3 * src], 3 * n, &albedo_[3 * dst]);
            std::copy_n(&tile.normal_[src], n, &normal_[dst]);
            std::copy_n(&tile.depth_[src], n, &depth_[dst]);
        }
    }
    samples_ = tile.samples_;
}

std::vector<uint8_t> Film::serialize() const {
    const int32_t header[7] = {fullWidth_, fullHeight_, window_.x0, window_.y0, window_.x1, window_.y1, hasAovs() ? 1 : 0};
    const uint32_t tag[3] = {kFilmMagic, kFilmVersion, samples_};
    const size_t bytes = sizeof tag + sizeof header + sum_.size() * sizeof(double) + albedo_.size() * sizeof(double) +
                         normal_.size() * sizeof(Vec3f) + depth_.size() * sizeof(double);
    std::vector<uint8_t> out(bytes);
    uint8_t* at = out.data();
    put(at, tag, 3);
    put(at, header, 7);
    put(at, sum_.data(), sum_.size());
    put(at, albedo_.data(), albedo_.size());
    put(at, normal_.data(), normal_.size());
    put(at, depth_.data(), depth_.size());
    return out;
}

Film Film::deserialize(const uint8_t* data, size_t size) {
    const uint8_t* at = data;
    const uint8_t* end = data + size;
    uint32_t tag[3];
    int32_t h[7];
    take(at, end, tag, 3);
    if (tag[0] != kFilmMagic || tag[1] != kFilmVersion)
        throw Error(ErrorCode::InvalidArgument, "serialized film: not a film of this Penumbra version");
    take(at, end, h, 7);
    const CropWindow w{h[2], h[3], h[4], h[5]};
    if (h[0] <= 0 || h[1] <= 0 || w.x0 < 0 || w.y0 < 0 || w.x1 <= w.x0 || w.y1 <= w.y0 || w.x1 > h[0] || w.y1 > h[1])
        throw Error(ErrorCode::InvalidArgument, "serialized film: bad frame or window");
    const size_t n = size_t(w.x1 - w.x0) * size_t(w.y1 - w.y0);
    const size_t need = 3 * n * sizeof(double) + (h[6] ? 3 * n * sizeof(double) + n * sizeof(Vec3f) + n * sizeof(double) : 0);
    if (size_t(end - at) != need)
        throw Error(ErrorCode::InvalidArgument, "serialized film: " + std::to_string(end - at) + " bytes of pixels, expected " +
                                                    std::to_string(need));
    Film f(h[0], h[1], w, h[6] != 0);
    f.samples_ = tag[2];
    take(at, end, f.sum_.data(), f.sum_.size());
    if (f.hasAovs()) {
        take(at, end, f.albedo_.data(), f.albedo_.size());
        take(at, end, f.normal_.data(), f.normal_.size());
        take(at, end, f.depth_.data(), f.depth_.size());
    }
    return f;
}

}  // namespace penumbra
