#include "lights/environment_light.h"

#include "core/error.h"
#include "core/sampling.h"
#include "lights/light_lanes.h"

namespace penumbra {
namespace {

constexpr float kInv4Pi = 0.25f * kInvPi;

Rgb cleaned(Rgb c) {
    auto ok = [](float v) { return std::isfinite(v) && v > 0.f ? v : 0.f; };
    return {ok(c.r), ok(c.g), ok(c.b)};
}

// The compensated map (EnvironmentLight::misSampled): f less the mean of the
// brightness over the sphere, f holding brightness times sin(theta) per row;
// empty where nothing is above the mean (a constant image).
std::vector<float> compensated(const std::vector<float>& f, int w, int h) {
    double sum = 0.0, weight = 0.0;
    for (int y = 0; y < h; ++y) {
        const float sinTheta = std::sin(kPi * (float(y) + 0.5f) / float(h));
        for (int x = 0; x < w; ++x) sum += double(f[size_t(y) * size_t(w) + size_t(x)]);
        weight += double(sinTheta) * double(w);
    }
    const float mean = weight > 0.0 ? float(sum / weight) : 0.f;
    std::vector<float> out(f.size());
    bool any = false;
    for (int y = 0; y < h; ++y) {
        const float sinTheta = std::sin(kPi * (float(y) + 0.5f) / float(h));
        for (int x = 0; x < w; ++x) {
            const size_t i = size_t(y) * size_t(w) + size_t(x);
            const float above = sinTheta > 0.f ? f[i] / sinTheta - mean : 0.f;
            out[i] = above > 0.f ? above * sinTheta : 0.f;
            any |= out[i] > 0.f;
        }
    }
    if (!any) out.clear();
    return out;
}

}  // namespace

// misSampled(): the owner's sampling with its compensated map.
class EnvironmentLight::MisSampled final : public Light {
public:
    explicit MisSampled(const EnvironmentLight& env) : env_(env) {}
    std::optional<LightSample> sample(const Vec3f& p, Vec2f u) const override {
        return env_.sampleMap(kCompensated, p, u);
    }
    void sampleLanes(const LanePoints& at, const float* ux, const float* uy, const int32_t* want, int n,
                     LightLanes& out) const override {
        env_.sampleMapLanes(kCompensated, at, ux, uy, want, n, out);
    }
    void sampleMany(const Vec3f& p, std::span<const Vec2f> u,
                    std::span<std::optional<LightSample>> out) const override {
        env_.sampleMapMany(kCompensated, p, u, out);
    }
    float pdf(const Vec3f&, const Hit&) const override { return 0.f; }
    double power() const override { return env_.power(); }

private:
    const EnvironmentLight& env_;
};

EnvironmentLight::EnvironmentLight(Rgb radiance, float sceneRadius)
    : constant_(cleaned(radiance)), misSampled_(std::make_unique<MisSampled>(*this)), mean_(constant_) {
    power_ = channelMean(mean_) * kPi * kPi * double(sceneRadius) * double(sceneRadius);
}

EnvironmentLight::~EnvironmentLight() = default;

EnvironmentLight::EnvironmentLight(RgbImage image, float scale, float rotateDegrees, float sceneRadius)
    : width_(image.width), height_(image.height), scale_(std::isfinite(scale) && scale > 0.f ? scale : 0.f),
      misSampled_(std::make_unique<MisSampled>(*this)) {
    const int w = width_, h = height_;
    if (w <= 0 || h <= 0 || image.pixels.size() != size_t(w) * size_t(h))
        throw Error(ErrorCode::InvalidArgument, "environment image has no pixels");
    const double rot = std::isfinite(rotateDegrees) ? double(rotateDegrees) * double(kPi) / 180.0 : 0.0;
    cosRot_ = float(std::cos(rot));
    sinRot_ = float(std::sin(rot));
    // Brightness times sin(theta) at each row's centre: the lat-long map
    // squeezes rows towards the poles, whose texels cover less solid angle.
    std::vector<float> f(size_t(w) * size_t(h));
    double sum[3] = {0.0, 0.0, 0.0}, weight = 0.0;
    for (int y = 0; y < h; ++y) {
        const float sinTheta = std::sin(kPi * (float(y) + 0.5f) / float(h));
        for (int x = 0; x < w; ++x) {
            Rgb& c = image.pixels[size_t(y) * size_t(w) + size_t(x)];
            c = cleaned(c);
            f[size_t(y) * size_t(w) + size_t(x)] = c.average() * sinTheta;
            sum[0] += double(c.r) * sinTheta;
            sum[1] += double(c.g) * sinTheta;
            sum[2] += double(c.b) * sinTheta;
            weight += sinTheta;
        }
    }
    distributions_[kFull] = std::make_unique<Distribution2D>(f, w, h);
    const std::vector<float> g = compensated(f, w, h);
    distributions_[kCompensated] = g.empty() ? std::make_unique<Distribution2D>(f, w, h)
                                             : std::make_unique<Distribution2D>(g, w, h);
    texels_.resize(f.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            texels_[size_t(y) * size_t(w) + size_t(x)] = {
                image.at(x, y), {distribution(kFull).cellPdf(x, y), distribution(kCompensated).cellPdf(x, y)}};
    mean_ = weight > 0.0 ? Rgb{float(sum[0] / weight), float(sum[1] / weight), float(sum[2] / weight)} * scale_ : Rgb{};
    power_ = channelMean(mean_) * kPi * kPi * double(sceneRadius) * double(sceneRadius);
}

Vec3f EnvironmentLight::toWorld(const Vec3f& l) const {
    return {l.x * cosRot_ + l.z * sinRot_, l.y, -l.x * sinRot_ + l.z * cosRot_};
}

Vec3f EnvironmentLight::toLocal(const Vec3f& w) const {
    return {w.x * cosRot_ - w.z * sinRot_, w.y, w.x * sinRot_ + w.z * cosRot_};
}

RgbImage EnvironmentLight::image() const {
    RgbImage out;
    out.width = width_;
    out.height = height_;
    out.pixels.reserve(texels_.size());
    for (const Texel& t : texels_) out.pixels.push_back(t.radiance);
    return out;
}

const EnvironmentLight::Texel& EnvironmentLight::texelAt(Vec2f uv) const {
    // Nearest texel: the environment is the piecewise-constant function the
    // distribution samples, so pdf and radiance agree exactly.
    const int x = std::clamp(int(uv.x * float(width_)), 0, width_ - 1);
    const int y = std::clamp(int(uv.y * float(height_)), 0, height_ - 1);
    return texels_[size_t(y) * size_t(width_) + size_t(x)];
}

namespace {

// sin(theta) of a unit direction, from x and z: accurate near the poles,
// where sqrt(1 - y^2) loses all its digits.
float sinTheta(const Vec3f& d) { return std::sqrt(d.x * d.x + d.z * d.z); }

// Image coordinates of a unit direction in the environment's own frame.
Vec2f directionToUv(const Vec3f& d) {
    float u = 0.5f + std::atan2(d.x, -d.z) * kInv2Pi;
    if (!(u < 1.f)) u = 0.f;  // atan2 = pi and rounding land on the seam
    if (u < 0.f) u = 0.f;
    const float v = std::atan2(sinTheta(d), d.y) * kInvPi;
    return {u, v};
}

}  // namespace

EnvironmentLight::Lookup EnvironmentLight::lookup(const Vec3f& dir) const {
    if (!hasImage()) {
        const float pdf = constant_.isBlack() ? 0.f : kInv4Pi;
        return {constant_, pdf, pdf};
    }
    const Vec3f n = normalize(dir);
    if (!(lengthSquared(n) > 0.f)) return {Rgb{}, 0.f, 0.f};
    const Vec3f d = toLocal(n);
    const Texel& t = texelAt(directionToUv(d));
    const float s = sinTheta(d);
    if (!(s > 0.f)) return {t.radiance * scale_, 0.f, 0.f};
    const float toSolidAngle = 2.f * kPi * kPi * s;
    return {t.radiance * scale_, t.pdf[kFull] / toSolidAngle, t.pdf[kCompensated] / toSolidAngle};
}

std::optional<LightSample> EnvironmentLight::sample(const Vec3f& p, Vec2f u) const { return sampleMap(kFull, p, u); }

void EnvironmentLight::sampleLanes(const LanePoints& at, const float* ux, const float* uy, const int32_t* want, int n,
                                   LightLanes& out) const {
    sampleMapLanes(kFull, at, ux, uy, want, n, out);
}

void EnvironmentLight::sampleMany(const Vec3f& p, std::span<const Vec2f> u,
                                  std::span<std::optional<LightSample>> out) const {
    sampleMapMany(kFull, p, u, out);
}

std::optional<LightSample> EnvironmentLight::sampleMap(Map map, const Vec3f& p, Vec2f u) const {
    if (!hasImage()) {
        if (constant_.isBlack()) return std::nullopt;
        const Vec3f wi = squareToUniformSphere(u);
        return LightSample{constant_, wi, p + wi, kInfinity, kInv4Pi, false};
    }
    return sampleAt(map, p, distribution(map).locate(u));
}

std::optional<LightSample> EnvironmentLight::sampleAt(Map map, const Vec3f& p, const Distribution2D::Cell& c) const {
    const Texel& t = texelAt(c);
    if (!(t.pdf[map] > 0.f)) return std::nullopt;
    const float theta = kPi * c.uv.y, phi = 2.f * kPi * (c.uv.x - 0.5f);
    const float sinTheta = std::sin(theta);
    if (!(sinTheta > 0.f)) return std::nullopt;
    const Vec3f local{sinTheta * std::sin(phi), std::cos(theta), -sinTheta * std::cos(phi)};
    const Vec3f wi = normalize(toWorld(local));
    const float pdf = t.pdf[map] / (2.f * kPi * kPi * sinTheta);
    const Rgb L = t.radiance * scale_;
    if (L.isBlack()) return std::nullopt;
    return LightSample{L, wi, p + wi, kInfinity, pdf, false};
}

void EnvironmentLight::locateTexels(Map map, const float* ux, const float* uy, int n,
                                    Distribution2D::Cell* cells) const {
    distribution(map).locateLanes(ux, uy, n, cells);
    for (int k = 0; k < n; ++k) __builtin_prefetch(&texelAt(cells[k]));
}

void EnvironmentLight::sampleMapLanes(Map map, const LanePoints& at, const float* ux, const float* uy,
                                      const int32_t* want, int n, LightLanes& out) const {
    if (!hasImage()) return Light::sampleLanes(at, ux, uy, want, n, out);
    out.delta = false;
    // The wanted lanes' points side by side, located together.
    constexpr int kWidth = LightLanes::kWidth;
    alignas(64) float vx[kWidth], vy[kWidth];
    int lane[kWidth], m = 0;
    for (int l = 0; l < n; ++l) {
        out.ok[l] = 0;
        if (!want[l]) continue;
        vx[m] = ux[l];
        vy[m] = uy[l];
        lane[m++] = l;
    }
    Distribution2D::Cell cells[kWidth];
    locateTexels(map, vx, vy, m, cells);
    for (int k = 0; k < m; ++k) out.set(lane[k], sampleAt(map, at.p(lane[k]), cells[k]));
}

void EnvironmentLight::sampleMapMany(Map map, const Vec3f& p, std::span<const Vec2f> u,
                                     std::span<std::optional<LightSample>> out) const {
    if (!hasImage()) return Light::sampleMany(p, u, out);
    constexpr int kChunk = LightLanes::kWidth;
    for (size_t base = 0; base < u.size(); base += kChunk) {
        const int m = int(std::min(u.size() - base, size_t(kChunk)));
        alignas(64) float vx[kChunk], vy[kChunk];
        for (int k = 0; k < m; ++k) {
            vx[k] = u[base + size_t(k)].x;
            vy[k] = u[base + size_t(k)].y;
        }
        Distribution2D::Cell cells[kChunk];
        locateTexels(map, vx, vy, m, cells);
        for (int k = 0; k < m; ++k) out[base + size_t(k)] = sampleAt(map, p, cells[k]);
    }
}

}  // namespace penumbra
