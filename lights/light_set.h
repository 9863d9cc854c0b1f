// All lights of a scene: explicit point/directional lights plus one area light
// per emissive rectangle, disk and sphere and per (mesh, emissive material).
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "core/rgb_image.h"
#include "core/scene.h"
#include "lights/light.h"
#include "lights/bvh_light_picker.h"
#include "lights/light_lanes.h"
#include "lights/power_light_picker.h"
#include "lights/spherical_cap.h"

namespace penumbra {

class TextureCache;

class EnvironmentLight;

class LightSet {
public:
    /// Builds the lights of a finalized scene (which must outlive the set).
    /// When scene.environment names an image, `environmentImage` holds its
    /// decoded pixels (the caller reads the file: PreparedScene); an environment
    /// with an image but no pixels here throws Error(InvalidArgument).
    /// `textures` (may be null) are the scene's decoded textures: emissive
    /// meshes with an emissive texture emit it (core/emission.h).
    explicit LightSet(const Scene& scene, RgbImage environmentImage = {}, const TextureCache* textures = nullptr);
    ~LightSet();

    size_t size() const { return lights_.size(); }
    /// The textures emission is read from (null: none).
    const TextureCache* textures() const { return textures_; }
    const Light& operator[](size_t i) const { return *lights_[i]; }

    /// Selection of lights in proportion to their power (Light::power).
    const PowerLightPicker& powerPicker() const { return *powerPicker_; }
    /// Selection of lights by the light hierarchy (lights/bvh_light_picker.h).
    const BVHLightPicker& bvhPicker() const { return *bvhPicker_; }

    /// Index of the area light the hit lies on (from its PrimRef and
    /// material); nullopt for surfaces that are no light. Which side was hit
    /// is not checked: Light::pdf is 0 and the material's ke is not seen on the
    /// back of a one-sided emitter.
    std::optional<size_t> lightOf(const Hit& hit) const;

    /// Where a ray first meets the surface of an area light: the light's
    /// index and the primitive's thin hit (complete it with
    /// Scene::completeHit). Either side counts, as for a closest hit.
    struct EmitterHit {
        size_t light;
        PrimRef ref;
        PrimHit hit;
    };
    /// The closest area-light primitive along ray, by the same shape tests as
    /// the naive accelerator; nullopt where the ray meets none (what lies in
    /// front of it is not looked at). Only where emittersTestable().
    std::optional<EmitterHit> firstEmitterHit(const Ray& ray) const;
    /// Whether the area lights have few enough primitives (kMaxTestedEmitters)
    /// for firstEmitterHit to cost less than a closest-hit query.
    bool emittersTestable() const { return emitterPrims_.size() <= kMaxTestedEmitters; }
    static constexpr size_t kMaxTestedEmitters = 16;

    /// Whether area light i may subtend more than omega at p: whether its
    /// bounding sphere does (always inside it; never for delta lights).
    /// Cheap (a multiply and a compare): for deciding where BRDF samples pay.
    bool mayExceedSolidAngle(size_t i, const Vec3f& p, float omega) const {
        const BoundingSphere& b = bounds_[i];
        return b.radius2 >= 0.f && subtendsAtLeast(b.center, b.radius2, p, omega);
    }
    /// mayExceedSolidAngle at the first n points of `at`, lane l's against
    /// omega[l], into exceed[l] (1 or 0); returns whether any lane's does.
    bool mayExceedSolidAngleLanes(size_t i, const LanePoints& at, const float* omega, int n, int32_t* exceed) const {
        const BoundingSphere& b = bounds_[i];
        if (!(b.radius2 >= 0.f)) return false;
        int32_t any = 0;
        for (int l = 0; l < n; ++l) {
            exceed[l] = subtendsAtLeast(b.center, b.radius2, at.p(l), omega[l]);
            any |= exceed[l];
        }
        return any != 0;
    }

    /// A sphere holding every primitive of area light i (its squared
    /// radius, rounded to float, can fall short by an ulp or so; radius2 < 0
    /// for delta lights).
    struct BoundingSphere {
        Vec3f center;
        float radius2 = -1.f;
    };
    const BoundingSphere& boundingSphere(size_t i) const { return bounds_[i]; }
    /// The primitives of area light i (firstEmitterHit's).
    std::span<const PrimRef> emitterPrims(size_t i) const {
        return std::span<const PrimRef>(emitterPrims_).subspan(emitters_[i].first, emitters_[i].count);
    }

    size_t areaLightCount() const { return areaLights_; }
    float totalEmitterArea() const { return totalArea_; }

    /// The scene's environment light (also one of the lights, the last one);
    /// nullptr when it has none: escaped rays then see Scene::background.
    const EnvironmentLight* environment() const { return environment_; }

private:
    // The constructor's steps: the mesh lights, the area lights' bounding
    // spheres and primitives, then the point, directional and environment lights.
    void addMeshLights();
    void addEmitterBounds();
    void addDeltaAndEnvironmentLights(RgbImage environmentImage);

    const Scene& scene_;
    const TextureCache* textures_;
    std::vector<std::unique_ptr<Light>> lights_;
    // Every area-light primitive, light by light; emitters_[i]: light i's
    // range of them (area lights come first among the lights).
    std::vector<PrimRef> emitterPrims_;
    struct EmitterRange {
        uint32_t first, count;
    };
    std::vector<EmitterRange> emitters_;
    // Light index per rectangle, disk and sphere (-1: not emissive), and per
    // mesh its (material, light index) pairs.
    std::vector<int32_t> rectangleLight_, diskLight_, sphereLight_;
    std::vector<std::vector<std::pair<uint32_t, uint32_t>>> meshLights_;
    std::vector<BoundingSphere> bounds_;
    std::unique_ptr<PowerLightPicker> powerPicker_;
    std::unique_ptr<BVHLightPicker> bvhPicker_;
    size_t areaLights_ = 0;
    float totalArea_ = 0.f;
    const EnvironmentLight* environment_ = nullptr;
};

}  // namespace penumbra
