#include "shading/integrator.h"

#include "core/error.h"
#include "shading/path_integrator.h"
#include "shading/whitted_integrator.h"

namespace penumbra {

Rgb Integrator::Li(const Ray& cameraRay, const SampleKey& key, RayCounts& counts, FirstHit* firstHit) const {
    const std::optional<Hit> hit = accel_.intersect(cameraRay);
    Rgb L;
    FirstHit first;
    radianceBatch(std::span<const Ray>(&cameraRay, 1), std::span<const std::optional<Hit>>(&hit, 1),
                  std::span<const SampleKey>(&key, 1), std::span<Rgb>(&L, 1),
                  firstHit ? std::span<FirstHit>(&first, 1) : std::span<FirstHit>(), counts);
    if (firstHit) *firstHit = first;
    return L;
}

std::unique_ptr<Integrator> makeIntegrator(const IntegratorInputs& in) {
    switch (in.settings.integrator) {
        case IntegratorKind::Whitted: return std::make_unique<WhittedIntegrator>(in);
        case IntegratorKind::Path: return std::make_unique<PathIntegrator>(in);
    }
    throw Error(ErrorCode::InvalidArgument, "unknown integrator " + std::to_string(int(in.settings.integrator)));
}

}  // namespace penumbra
