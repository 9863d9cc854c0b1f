#include "core/transform.h"

#include <cstring>

namespace penumbra {

Transform::Transform(const float m[3][4]) { std::memcpy(m_, m, sizeof(m_)); }

Transform Transform::translate(const Vec3f& t) {
    Transform r;
    r.m_[0][3] = t.x;
    r.m_[1][3] = t.y;
    r.m_[2][3] = t.z;
    return r;
}

Transform Transform::scale(const Vec3f& s) {
    Transform r;
    r.m_[0][0] = s.x;
    r.m_[1][1] = s.y;
    r.m_[2][2] = s.z;
    return r;
}

Transform Transform::rotate(float degrees, const Vec3f& axis) {
    Vec3f a = normalize(axis);
    float rad = degrees * kPi / 180.f;
    float s = std::sin(rad), c = std::cos(rad);
    Transform r;
    r.m_[0][0] = a.x * a.x + (1 - a.x * a.x) * c;
    r.m_[0][1] = a.x * a.y * (1 - c) - a.z * s;
    r.m_[0][2] = a.x * a.z * (1 - c) + a.y * s;
    r.m_[1][0] = a.x * a.y * (1 - c) + a.z * s;
    r.m_[1][1] = a.y * a.y + (1 - a.y * a.y) * c;
    r.m_[1][2] = a.y * a.z * (1 - c) - a.x * s;
    r.m_[2][0] = a.x * a.z * (1 - c) - a.y * s;
    r.m_[2][1] = a.y * a.z * (1 - c) + a.x * s;
    r.m_[2][2] = a.z * a.z + (1 - a.z * a.z) * c;
    return r;
}

Transform Transform::operator*(const Transform& o) const {
    Transform r;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 4; ++j) {
            float v = m_[i][0] * o.m_[0][j] + m_[i][1] * o.m_[1][j] + m_[i][2] * o.m_[2][j];
            if (j == 3) v += m_[i][3];
            r.m_[i][j] = v;
        }
    }
    return r;
}

Vec3f Transform::applyNormal(const Vec3f& n) const {
    // Inverse transpose of the linear part equals the cofactor matrix / det;
    // the scale does not matter for a normal, so use the cofactors directly.
    // c0, c1, c2 are the rows of the cofactor matrix.
    const auto& m = m_;
    Vec3f c0{m[1][1] * m[2][2] - m[1][2] * m[2][1], m[1][2] * m[2][0] - m[1][0] * m[2][2], m[1][0] * m[2][1] - m[1][1] * m[2][0]};
    Vec3f c1{m[0][2] * m[2][1] - m[0][1] * m[2][2], m[0][0] * m[2][2] - m[0][2] * m[2][0], m[0][1] * m[2][0] - m[0][0] * m[2][1]};
    Vec3f c2{m[0][1] * m[1][2] - m[0][2] * m[1][1], m[0][2] * m[1][0] - m[0][0] * m[1][2], m[0][0] * m[1][1] - m[0][1] * m[1][0]};
    Vec3f r{dot(c0, n), dot(c1, n), dot(c2, n)};
    return determinant() < 0.f ? -r : r;
}

float Transform::determinant() const {
    const auto& m = m_;
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

bool Transform::inverse(Transform& out) const {
    float det = determinant();
    if (!(std::fabs(det) > 1e-30f) || !std::isfinite(det)) return false;
    const auto& m = m_;
    float inv = 1.f / det;
    Transform r;
    r.m_[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) * inv;
    r.m_[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * inv;
    r.m_[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * inv;
    r.m_[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) * inv;
    r.m_[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * inv;
    r.m_[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * inv;
    r.m_[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) * inv;
    r.m_[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * inv;
    r.m_[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * inv;
    for (int i = 0; i < 3; ++i)
        r.m_[i][3] = -(r.m_[i][0] * m[0][3] + r.m_[i][1] * m[1][3] + r.m_[i][2] * m[2][3]);
    out = r;
    return true;
}

bool Transform::isIdentity() const {
    Transform id;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j)
            if (m_[i][j] != id.m_[i][j]) return false;
    return true;
}

}  // namespace penumbra
