#include "accel/accelerator.h"

#include "core/error.h"

namespace penumbra {

std::unique_ptr<Accelerator> makeAccelerator(const std::string& name, const Scene& scene, BuildQuality quality) {
    if (name == "embree") return makeEmbreeAccelerator(scene, quality);
    if (name == "naive") return makeNaiveAccelerator(scene);
    throw Error(ErrorCode::InvalidArgument, "unknown accelerator '" + name + "' (expected embree or naive)");
}

}  // namespace penumbra
