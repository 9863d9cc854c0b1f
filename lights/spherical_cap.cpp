#include "lights/spherical_cap.h"

#include <cmath>

namespace penumbra {

namespace {

// 1 - cos(theta_max) for sin^2(theta_max) = r^2 / d^2, without the
// cancellation of 1 - sqrt(1 - x) for small lights: x / (1 + sqrt(1 - x)).
double oneMinusCosMax(double sin2) { return sin2 / (1.0 + std::sqrt(std::max(0.0, 1.0 - sin2))); }

constexpr double kTwoPi = 6.28318530717958647692;

// The cone is used only from points clearly outside the sphere. A point on
// the sphere itself (a hit on an emitting sphere that also reflects, or a
// shading point on the inside of an emitting enclosure) lies at d = r up to
// rounding, on either side; the cone of such a point degenerates (sin = 1)
// and its pdf would describe the wrong side. Those points are sampled by
// area, which is exact from anywhere.
constexpr double kConeMinDistance2 = 1.001;  // (d / r)^2

}  // namespace

float sphereConePdf(const Vec3f& o, const Vec3f& center, float radius) {
    const double d2 = double(lengthSquared(center - o)), r2 = double(radius) * radius;
    if (!(d2 > r2 * kConeMinDistance2)) return 0.f;
    return float(1.0 / (kTwoPi * oneMinusCosMax(r2 / d2)));
}

std::optional<SphereConeSample> sampleSphereCone(const Vec3f& o, const Vec3f& center, float radius, Vec2f u) {
    const Vec3f toCenter = center - o;
    const double d2 = double(lengthSquared(toCenter)), r2 = double(radius) * radius;
    if (!(d2 > r2 * kConeMinDistance2)) return std::nullopt;
    const double sin2Max = r2 / d2, sinMax = std::sqrt(sin2Max);
    const double omc = oneMinusCosMax(sin2Max);
    // cos(theta) uniform in [cos(theta_max), 1]; 1 - cos kept for precision.
    const double oneMinusCos = double(u.x) * omc;
    const double sin2 = oneMinusCos * (2.0 - oneMinusCos);
    const double cosTheta = 1.0 - oneMinusCos;
    // The angle alpha at the centre between -axis and the sphere point hit by
    // the sampled direction (law of sines on the triangle o, centre, point):
    // computing the point from alpha keeps it exactly on the sphere.
    const double cosAlpha = sin2 / sinMax + cosTheta * std::sqrt(std::max(0.0, 1.0 - sin2 / sin2Max));
    const double sinAlpha = std::sqrt(std::max(0.0, 1.0 - cosAlpha * cosAlpha));
    const double phi = kTwoPi * double(u.y);
    const Frame f = Frame::fromNormal(normalize(-toCenter));  // n points from the centre towards o
    const Vec3f n = f.toWorld(Vec3f{float(sinAlpha * std::cos(phi)), float(sinAlpha * std::sin(phi)), float(cosAlpha)});
    const Vec3f point = center + radius * n;
    const Vec3f d = point - o;
    const float dist = length(d);
    if (!(dist > 0.f)) return std::nullopt;
    return SphereConeSample{d / dist, point, n, float(1.0 / (kTwoPi * omc))};
}

}  // namespace penumbra
