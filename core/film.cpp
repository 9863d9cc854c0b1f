#include "core/film.h"

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

}  // namespace penumbra
