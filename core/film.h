// The film: per-pixel sums of linear radiance over camera samples (box
// filter) plus first-hit AOVs. Samples are added to a pixel in sample order,
// so rendering in progressive passes gives the same sums, bit for bit, as one pass.
#pragma once

#include <cstdint>
#include <vector>

#include "core/color.h"
#include "core/math.h"
#include "core/render_settings.h"

namespace penumbra {

class Film {
public:
    Film() = default;
    /// A film for the window [x0, x1) x [y0, y1) of a fullWidth x fullHeight frame.
    Film(int fullWidth, int fullHeight, CropWindow window, bool aovs);
    /// Whole frame.
    Film(int width, int height, bool aovs) : Film(width, height, CropWindow{0, 0, width, height}, aovs) {}

    /// Bytes a film of this size needs (checked before allocating).
    static uint64_t bytesNeeded(int64_t pixels, bool aovs);

    int width() const { return window_.x1 - window_.x0; }
    int height() const { return window_.y1 - window_.y0; }
    int fullWidth() const { return fullWidth_; }
    int fullHeight() const { return fullHeight_; }
    const CropWindow& window() const { return window_; }
    bool hasAovs() const { return !albedo_.empty(); }
    /// Camera samples accumulated per pixel so far.
    uint32_t sampleCount() const { return samples_; }
    void setSampleCount(uint32_t n) { samples_ = n; }

    /// Index of full-frame pixel (x, y), which must lie in the window.
    size_t index(int x, int y) const { return size_t(y - window_.y0) * size_t(width()) + size_t(x - window_.x0); }

    /// One pixel's radiance sums, in the film's precision.
    struct RadianceSum {
        double r = 0.0, g = 0.0, b = 0.0;
        void add(const Rgb& L) {
            r += L.r;
            g += L.g;
            b += L.b;
        }
    };
    /// Pixel i's sums, read and set whole: a renderer adds a block's samples
    /// to copies and stores them once, the sums addRadiance would give.
    RadianceSum radianceSum(size_t i) const { return {sum_[3 * i], sum_[3 * i + 1], sum_[3 * i + 2]}; }
    void setRadianceSum(size_t i, const RadianceSum& s) {
        sum_[3 * i] = s.r;
        sum_[3 * i + 1] = s.g;
        sum_[3 * i + 2] = s.b;
    }
    void addRadiance(size_t i, const Rgb& L) {
        RadianceSum s = radianceSum(i);
        s.add(L);
        setRadianceSum(i, s);
    }
    void addAov(size_t i, const Rgb& albedo, const Vec3f& normal, float depth) {
        albedo_[3 * i] += albedo.r;
        albedo_[3 * i + 1] += albedo.g;
        albedo_[3 * i + 2] += albedo.b;
        normal_[i] += normal;
        depth_[i] += depth;
    }

    /// Average radiance of pixel i (0 before any sample).
    Rgb radiance(size_t i) const;
    Rgb albedo(size_t i) const;
    Vec3f normal(size_t i) const;
    float depth(size_t i) const;

    /// Interleaved RGB (or RGBA with alpha 1) floats of the averaged radiance, row 0 on top.
    std::vector<float> radianceBuffer(int channels = 3) const;

    void clear();

    /// Copies the pixels of `tile`, a film of the same full frame whose window
    /// lies inside this one's, into this film; the sample count becomes the
    /// tile's. Tiles rendered apart (other threads, processes or machines)
    /// assemble into the exact film of one render. Throws Error(InvalidArgument)
    /// when the frames, windows, AOVs or (on a film that has samples) the
    /// sample counts differ.
    void paste(const Film& tile);

    /// The film as bytes (frame, window, sample count, sums in native byte
    /// order) and back, for moving it between processes of one machine type.
    /// deserialize throws Error(InvalidArgument) for bytes that are not a film.
    std::vector<uint8_t> serialize() const;
    static Film deserialize(const uint8_t* data, size_t size);

private:
    int fullWidth_ = 0, fullHeight_ = 0;
    CropWindow window_;
    uint32_t samples_ = 0;
    std::vector<double> sum_;  // double: millions of samples per pixel keep their precision
    // Albedo and depth sums in double too: a huge albedo or distance summed
    // over samples would overflow float to inf. Unit normals cannot.
    std::vector<double> albedo_;
    std::vector<Vec3f> normal_;
    std::vector<double> depth_;
};

}  // namespace penumbra
