#include "tile_plan.h"

#include <algorithm>

namespace penumbra::mpi {

std::vector<pnb::CropWindow> planTiles(const pnb::CropWindow& w, int workers) {
    const int width = w.x1 - w.x0, height = w.y1 - w.y0;
    const long wanted = 8L * std::max(workers, 1);
    int side = 8;
    for (int s : {64, 32, 16}) {
        const long count = long((width + s - 1) / s) * long((height + s - 1) / s);
        if (count >= wanted) {
            side = s;
            break;
        }
    }
    std::vector<pnb::CropWindow> tiles;
    for (int y = w.y0; y < w.y1; y += side)
        for (int x = w.x0; x < w.x1; x += side)
            tiles.push_back({x, y, std::min(x + side, w.x1), std::min(y + side, w.y1)});
    return tiles;
}

}  // namespace penumbra::mpi
