// Affine transforms (3x4 matrices) for oriented boxes and placed meshes.
// Names read right to left: worldFromObject maps object space to world space.
#pragma once

#include "core/math.h"

namespace penumbra {

class Transform {
public:
    /// Identity.
    Transform() : m_{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}} {}
    Transform(const float m[3][4]);

    static Transform translate(const Vec3f& t);
    static Transform scale(const Vec3f& s);
    /// Rotation by angle degrees about axis (right-handed).
    static Transform rotate(float degrees, const Vec3f& axis);

    /// this * other: apply other first.
    Transform operator*(const Transform& other) const;

    // Inline: boxes apply them on every hit and every slab test.
    Vec3f applyPoint(const Vec3f& p) const {
        return {m_[0][0] * p.x + m_[0][1] * p.y + m_[0][2] * p.z + m_[0][3],
                m_[1][0] * p.x + m_[1][1] * p.y + m_[1][2] * p.z + m_[1][3],
                m_[2][0] * p.x + m_[2][1] * p.y + m_[2][2] * p.z + m_[2][3]};
    }
    Vec3f applyVector(const Vec3f& v) const {
        return {m_[0][0] * v.x + m_[0][1] * v.y + m_[0][2] * v.z, m_[1][0] * v.x + m_[1][1] * v.y + m_[1][2] * v.z,
                m_[2][0] * v.x + m_[2][1] * v.y + m_[2][2] * v.z};
    }
    /// Transforms a normal with the inverse transpose; the result is not normalised.
    Vec3f applyNormal(const Vec3f& n) const;

    /// Inverse; returns false (and leaves out untouched) for a singular matrix.
    bool inverse(Transform& out) const;
    float determinant() const;
    bool isIdentity() const;
    float operator()(int r, int c) const { return m_[r][c]; }

private:
    float m_[3][4];
};

}  // namespace penumbra
