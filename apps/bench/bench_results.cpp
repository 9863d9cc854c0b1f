#include "bench_results.h"

namespace penumbra::bench {
namespace {

std::optional<double> ratio(double a, double b) {
    if (!(a > 0.0) || !(b > 0.0)) return std::nullopt;
    return a / b;
}

}  // namespace

SceneRatios ratiosOf(const SceneResult& r) {
    SceneRatios q;
    const auto cam = size_t(RayKind::Camera);
    if (r.raw.present) {
        q.cameraOverRaw1 = ratio(r.embree.kinds[cam].mrays1(), r.raw.kinds[cam].mrays1());
        q.cameraOverRawAll = ratio(r.embree.kinds[cam].mraysAll(), r.raw.kinds[cam].mraysAll());
        for (size_t k = 0; k < kRayKindCount; ++k)
            q.kindOverRawAll[k] = ratio(r.embree.kinds[k].mraysAll(), r.raw.kinds[k].mraysAll());
        q.buildOverRaw = ratio(r.embree.buildSeconds, r.raw.buildSeconds);
        q.buildOverRawWithDevice = ratio(r.embree.buildSeconds, r.raw.buildSeconds + r.raw.deviceSeconds);
        q.memoryOverRaw = ratio(double(r.embree.memoryBytes), double(r.raw.memoryBytes));
    }
    // The frame's rays, each at the pure query rate of its kind, with the
    // closest-hit queries after the camera's (reflection and transmission
    // rays, and the BRDF-sampled rays of direct light) at the incoherent
    // set's rate, and the frame's thread count: raw
    // Embree's where the raw harness holds the scene (triangles only), else
    // the renderer's accelerator answering single rays with nothing else
    // (intersectPrim, occluded).
    if (r.embree.frame.measured) {
        const AccelFigures& query = r.raw.present ? r.raw : r.embreeThin;
        const RayCounts& n = r.embree.frame.rays;
        const double counts[kRayKindCount] = {double(n.camera), double(n.shadow),
                                              double(n.reflection + n.transmission + n.indirect + n.brdf)};
        double pure = 0.0;
        bool ok = true;
        for (size_t k = 0; k < kRayKindCount; ++k) {
            if (counts[k] == 0.0) continue;
            const double rate = query.kinds[k].mraysAll() * 1e6;
            if (!(rate > 0.0)) ok = false;
            else pure += counts[k] / rate;
        }
        if (ok) q.frameOverQuery = ratio(r.embree.frame.secondsAll, pure);
    }
    if (r.raw.present && r.rawFast.present)
        for (size_t k = 0; k < kRayKindCount; ++k)
            q.notRobustOverRaw[k] = ratio(r.rawFast.kinds[k].mraysAll(), r.raw.kinds[k].mraysAll());
    if (r.embree.frame.measured) q.renderScaling = ratio(r.embree.frame.mraysAll(), r.embree.frame.mrays1());
    if (r.naive.present)
        for (size_t k = 0; k < kRayKindCount; ++k)
            q.embreeOverNaive[k] = ratio(r.embree.kinds[k].mrays1(), r.naive.kinds[k].mrays1());
    return q;
}

AgreementSummary summarizeAgreement(const std::vector<SceneResult>& results) {
    AgreementSummary s;
    for (const auto& r : results)
        for (size_t k = 0; k < kRayKindCount; ++k) {
            s.naiveVsEmbree += r.naiveVsEmbree[k];
            s.rawVsEmbree += r.rawVsEmbree[k];
        }
    return s;
}

}  // namespace penumbra::bench
