// Phong material, as in the lecture notes (see docs/ and shading/phong.h for the BRDF).
#pragma once

#include <string>

#include "core/color.h"

namespace penumbra {

enum class PhongModel {
    /// f = kd/pi + ks (n+2)/(2 pi) cos^n(alpha): energy-conserving when kd + ks <= 1.
    Normalized,
    /// The lecture's empirical formula L = ka La + sum kd Lj (n.s) + ks Lj (v.r)^n.
    Classic,
};

struct Material {
    std::string name;
    Rgb ka{0.f};        // ambient reflectance, multiplies the scene's ambient light
    Rgb kd{0.8f};       // diffuse albedo
    Rgb ks{0.f};        // specular (Phong lobe) reflectance
    float exponent = 1.f;  // Phong exponent n
    Rgb kr{0.f};        // mirror reflectance
    Rgb ke{0.f};        // emitted radiance
    bool twoSidedEmission = false;
    PhongModel model = PhongModel::Normalized;
    int diffuseTexture = -1;  // index into Scene::textures, multiplies kd

    bool isEmissive() const { return ke.maxComponent() > 0.f; }
    bool isMirror() const { return kr.maxComponent() > 0.f; }
};

}  // namespace penumbra
