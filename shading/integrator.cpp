#include "shading/integrator.h"

#include "core/multi_jitter.h"
#include "core/texture_cache.h"
#include "shading/phong.h"

namespace penumbra {
Integrator::Integrator(const Scene& scene, const Accelerator& accel, const LightSet& lights,
                       const TextureCache* textures, const RenderSettings& settings)
    : scene_(scene), accel_(accel), lights_(lights), textures_(textures), settings_(settings) {}

Rgb Integrator::diffuseAlbedo(const Material& m, const Hit& hit, float pathLength, const Vec3f& wo) const {
    if (m.diffuseTexture < 0 || !textures_) return m.kd;
    // Filter footprint in uv: the pixel's cone width at the hit (a ray cone:
    // distance travelled times the pixel's angle, stretched by the grazing
    // angle), converted to uv units with the triangle's uv-per-world scale.
    float footprint = 0.f;
    if (pixelSpread_ > 0.f && hit.ref.kind == ShapeKind::Mesh) {
        const TriangleMesh& mesh = scene_.meshes[hit.ref.object];
        if (!mesh.uvs.empty()) {
            const uint32_t* idx = &mesh.indices[3 * hit.ref.prim];
            const Vec2f &a = mesh.uvs[idx[0]], &b = mesh.uvs[idx[1]], &c = mesh.uvs[idx[2]];
            const float uvArea = std::fabs((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
            const Vec3f &p0 = mesh.positions[idx[0]], &p1 = mesh.positions[idx[1]], &p2 = mesh.positions[idx[2]];
            const float worldArea = length(cross(p1 - p0, p2 - p0));
            if (worldArea > 0.f) {
                const float cosTheta = std::max(std::fabs(dot(wo, hit.ns)), 0.2f);
                footprint = pathLength * pixelSpread_ / cosTheta * std::sqrt(uvArea / worldArea);
            }
        }
    }
    return m.kd * textures_->lookup(m.diffuseTexture, hit.uv, footprint);
}

Rgb Integrator::directLight(const Hit& hit, const Material& m, const Rgb& kd, const Vec3f& ng, const Vec3f& ns,
                            const Vec3f& wo, const SampleKey& key, int depth, RayCounts& counts) const {
    const size_t nLights = lights_.size();
    if (nLights == 0) return {};
    if (kd.isBlack() && m.ks.isBlack()) return {};
    const uint32_t n = static_cast<uint32_t>(settings_.lightSamples);
    const uint64_t dimBase = kFirstLightDimension + uint64_t(depth) * (nLights + 1);

    // The samples of one shading point are traced as packets: each candidate
    // (above the surface, non-zero f) becomes a shadow ray with its weight
    // f * L / pdf (the cosine and f live in phongResponse); the unoccluded
    // weights are then summed in sample order, so results do not depend on
    // how the rays were grouped.
    constexpr uint32_t kBatch = 16;
    Ray shadow[kBatch];
    Rgb weight[kBatch];
    uint8_t blocked[kBatch];
    uint32_t pending = 0;
    Rgb acc;
    auto flush = [&] {
        if (pending == 0) return;
        accel_.occludedBatch(std::span<const Ray>(shadow, pending), std::span<uint8_t>(blocked, pending));
        counts.shadow += pending;
        for (uint32_t i = 0; i < pending; ++i)
            if (!blocked[i]) acc += weight[i];
        pending = 0;
    };
    auto add = [&](const LightSample& ls, float scale) {
        if (dot(ls.wi, ng) <= 0.f) return;  // below the geometric surface
        const Rgb f = phongResponse(m, kd, ns, wo, ls.wi, ls.delta);
        if (f.isBlack()) return;
        shadow[pending] = std::isinf(ls.distance) ? spawnRay(hit.p, ng, ls.wi) : spawnRayTo(hit.p, ng, ls.point);
        weight[pending] = f * ls.L * (scale / ls.pdf);
        if (++pending == kBatch) flush();
    };

    Rgb sum;
    if (settings_.lightSelection == LightSelection::All) {
        for (size_t j = 0; j < nLights; ++j) {
            const Light& light = lights_[j];
            acc = Rgb{};
            if (light.isDelta()) {
                if (auto ls = light.sample(hit.p, Vec2f{0.5f, 0.5f})) add(*ls, 1.f);
                flush();
                sum += acc;
                continue;
            }
            const MultiJitterSet set(n, mjPattern(key.seed, key.pixel, key.index, dimBase + j));
            for (uint32_t k = 0; k < n; ++k)
                if (auto ls = light.sample(hit.p, set.sample(k))) add(*ls, 1.f);
            flush();
            sum += acc / float(n);
        }
        return sum;
    }
    // Power-proportional selection: n samples in total, each picks one light.
    const MultiJitterSet set(n, mjPattern(key.seed, key.pixel, key.index, dimBase + nLights));
    const MultiJitterSet pickSet(n, mjPattern(key.seed, key.pixel, key.index, dimBase + nLights + 0x9e37ULL));
    for (uint32_t k = 0; k < n; ++k) {
        const LightSet::Pick pick = lights_.pickByPower(pickSet.sample(k).x);
        if (!(pick.probability > 0.f)) continue;
        if (auto ls = lights_[pick.index].sample(hit.p, set.sample(k))) add(*ls, 1.f / pick.probability);
    }
    flush();
    return acc / float(n);
}

Rgb Integrator::Li(const Ray& cameraRay, const SampleKey& key, RayCounts& counts, FirstHit* firstHit) const {
    return Li(cameraRay, accel_.intersect(cameraRay), key, counts, firstHit);
}

Rgb Integrator::Li(const Ray& cameraRay, const std::optional<Hit>& primaryHit, const SampleKey& key, RayCounts& counts,
                   FirstHit* firstHit) const {
    Rgb L;
    Rgb throughput(1.f);
    Ray ray = cameraRay;
    float pathLength = 0.f;
    ++counts.camera;
    for (int depth = 0;; ++depth) {
        const std::optional<Hit> hit = depth == 0 ? primaryHit : accel_.intersect(ray);
        if (!hit) {
            L += throughput * scene_.background;
            break;
        }
        const Material& m = scene_.material(hit->material);
        const Vec3f wo = -ray.d;
        pathLength += hit->t;
        // Emission is one-sided: only the side the geometric normal faces emits.
        const bool front = dot(wo, hit->ng) > 0.f;
        if (m.isEmissive() && (front || m.twoSidedEmission)) L += throughput * m.ke;

        // Shading is two-sided: flip both normals to the viewer's side.
        const Vec3f ng = front ? hit->ng : -hit->ng;
        const Vec3f ns = front ? hit->ns : -hit->ns;
        const Rgb kd = diffuseAlbedo(m, *hit, pathLength, wo);
        if (depth == 0 && firstHit) *firstHit = FirstHit{kd, ns, hit->t};

        L += throughput * (m.ka * scene_.ambient);
        L += throughput * directLight(*hit, m, kd, ng, ns, wo, key, depth, counts);

        if (!m.isMirror() || depth >= settings_.maxDepth) break;
        // r = d - 2(d.n)n about the shading normal; fall back to the geometric
        // normal when smooth normals would send the ray below the surface.
        Vec3f r = reflect(ray.d, ns);
        if (dot(r, ng) <= 0.f) r = reflect(ray.d, ng);
        throughput *= m.kr;
        if (throughput.isBlack()) break;
        ray = spawnRay(hit->p, ng, normalize(r));
        ++counts.reflection;
    }
    if (!L.isFinite()) {
        ++counts.nonFinite;
        return {};
    }
    return L;
}

}  // namespace penumbra
