#include "orbit_camera.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace penumbra::preview {
namespace {

// The moves are worked out in double precision and stored as the camera's floats.
struct V {
    double x, y, z;
};
V operator+(V a, V b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V operator-(V a, V b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V operator*(V a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(V a, V b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V cross(V a, V b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double length(V a) { return std::sqrt(dot(a, a)); }
V normalize(V a) { return a * (1.0 / length(a)); }
V in(const pnb::Vec3& v) { return {v.x, v.y, v.z}; }
pnb::Vec3 out(V v) { return {float(v.x), float(v.y), float(v.z)}; }

constexpr double kDegrees = 3.14159265358979323846 / 180.0;

// Rodrigues' rotation of v by `radians` about the unit axis k.
V rotate(V v, V k, double radians) {
    const double c = std::cos(radians), s = std::sin(radians);
    return v * c + cross(k, v) * s + k * (dot(k, v) * (1.0 - c));
}

// The view's unit right and up vectors (up as seen on the image).
struct Frame {
    V right, up;
};
Frame viewFrame(const pnb::Camera& c) {
    const V forward = normalize(in(c.lookAt) - in(c.eye));
    const V right = normalize(cross(forward, in(c.up)));
    return {right, cross(right, forward)};
}

void appendNumber(std::string& s, double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);  // 9 significant digits read back as the same float
    s += buf;
}

void appendOption(std::string& s, const char* name, const pnb::Vec3& v) {
    s += name;
    appendNumber(s, v.x);
    s += ',';
    appendNumber(s, v.y);
    s += ',';
    appendNumber(s, v.z);
}

}  // namespace

pnb::Camera orbit(const pnb::Camera& camera, double yawDegrees, double pitchDegrees) {
    const V target = in(camera.lookAt), up = normalize(in(camera.up));
    V offset = rotate(in(camera.eye) - target, up, yawDegrees * kDegrees);
    const double r = length(offset);
    // The angle between the eye's direction and up, moved by the pitch and kept off the poles.
    const double along = dot(offset, up) / r;
    const double angle = std::acos(std::clamp(along, -1.0, 1.0));
    const double moved = std::clamp(angle - pitchDegrees * kDegrees, 1.0 * kDegrees, 179.0 * kDegrees);
    V level = offset - up * (along * r);
    if (length(level) < 1e-12 * r) level = viewFrame(camera).right;  // on a pole: any horizontal direction
    offset = (up * std::cos(moved) + normalize(level) * std::sin(moved)) * r;
    pnb::Camera c = camera;
    c.eye = out(target + offset);
    return c;
}

pnb::Camera zoom(const pnb::Camera& camera, double factor) {
    const V target = in(camera.lookAt);
    pnb::Camera c = camera;
    c.eye = out(target + (in(camera.eye) - target) * factor);
    c.focusDistance = float(camera.focusDistance * factor);
    return c;
}

pnb::Camera pan(const pnb::Camera& camera, double right, double up) {
    const Frame f = viewFrame(camera);
    const double height = 2.0 * length(in(camera.lookAt) - in(camera.eye)) * std::tan(0.5 * camera.vfovDegrees * kDegrees);
    const V shift = (f.right * right + f.up * up) * height;
    pnb::Camera c = camera;
    c.eye = out(in(camera.eye) + shift);
    c.lookAt = out(in(camera.lookAt) + shift);
    return c;
}

std::string cameraOptions(const pnb::Camera& camera) {
    std::string s;
    appendOption(s, "--eye=", camera.eye);
    appendOption(s, " --look-at=", camera.lookAt);
    appendOption(s, " --up=", camera.up);
    s += " --fov=";
    appendNumber(s, camera.vfovDegrees);
    if (camera.aperture > 0.f) {
        s += " --aperture=";
        appendNumber(s, camera.aperture);
        s += " --focus-distance=";
        appendNumber(s, camera.focusDistance);
    }
    return s;
}

}  // namespace penumbra::preview
