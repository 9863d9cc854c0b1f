#include "accel/accelerator.h"

#include "core/error.h"

namespace penumbra {

std::unique_ptr<Accelerator> makeAccelerator(AcceleratorKind kind, const Scene& scene, BuildQuality quality,
                                             std::shared_ptr<const TextureCache> textures) {
    switch (kind) {
        case AcceleratorKind::Embree: return makeEmbreeAccelerator(scene, quality, std::move(textures));
        case AcceleratorKind::Naive: return makeNaiveAccelerator(scene, std::move(textures));
    }
    throw Error(ErrorCode::InvalidArgument, "accelerator " + std::to_string(int(kind)) + " is not an AcceleratorKind");
}

}  // namespace penumbra
