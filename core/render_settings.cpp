#include "core/render_settings.h"

#include <string>

#include "core/error.h"

namespace penumbra {
namespace {
void require(bool ok, const std::string& what) {
    if (!ok) throw Error(ErrorCode::InvalidArgument, what);
}
}  // namespace

void validateSettings(const RenderSettings& s) {
    constexpr int kMaxDim = 1 << 16;
    require(s.width > 0 && s.width <= kMaxDim, "width must be in [1, 65536], got " + std::to_string(s.width));
    require(s.height > 0 && s.height <= kMaxDim, "height must be in [1, 65536], got " + std::to_string(s.height));
    require(s.spp > 0 && s.spp <= (1 << 20), "spp must be in [1, 1048576], got " + std::to_string(s.spp));
    require(s.lightSamples > 0 && s.lightSamples <= (1 << 16),
            "light samples must be in [1, 65536], got " + std::to_string(s.lightSamples));
    require(s.maxDepth >= 0 && s.maxDepth <= 1000000, "max depth must be in [0, 1000000], got " + std::to_string(s.maxDepth));
    require(s.threads >= 0 && s.threads <= 4096, "threads must be >= 0 (0 = all cores), got " + std::to_string(s.threads));
    require(s.tileSize > 0 && s.tileSize <= 4096, "tile size must be in [1, 4096], got " + std::to_string(s.tileSize));
    require(s.integrator == IntegratorKind::Whitted || s.integrator == IntegratorKind::Path,
            "integrator must be whitted or path, got " + std::to_string(int(s.integrator)));
    if (s.crop) {
        const CropWindow& c = *s.crop;
        require(c.x0 >= 0 && c.y0 >= 0 && c.x1 <= s.width && c.y1 <= s.height && c.x0 < c.x1 && c.y0 < c.y1,
                "crop window " + std::to_string(c.x0) + "," + std::to_string(c.y0) + "," + std::to_string(c.x1) + "," +
                    std::to_string(c.y1) + " must satisfy 0 <= x0 < x1 <= width and 0 <= y0 < y1 <= height");
    }
}

void SettingsPatch::applyTo(RenderSettings& s) const {
    if (width) s.width = *width;
    if (height) s.height = *height;
    if (spp) s.spp = *spp;
    if (lightSamples) s.lightSamples = *lightSamples;
    if (maxDepth) s.maxDepth = *maxDepth;
    if (threads) s.threads = *threads;
    if (tileSize) s.tileSize = *tileSize;
    if (seed) s.seed = *seed;
    if (lightSelection) s.lightSelection = *lightSelection;
    if (integrator) s.integrator = *integrator;
}

}  // namespace penumbra
