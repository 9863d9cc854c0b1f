// Phong material, as in the lecture notes (see docs/ and shading/phong.h for the BRDF).
#pragma once

#include <penumbra/types.hpp>

#include <string>

#include "core/color.h"

namespace penumbra {

using PhongModel = pnb::PhongModel;  // api/include/penumbra/types.hpp

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
