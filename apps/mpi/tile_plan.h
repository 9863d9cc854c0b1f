// How penumbra-mpi cuts the render window into the tiles rank 0 hands out.
#pragma once

#include <penumbra/penumbra.hpp>

#include <vector>

namespace penumbra::mpi {

/// Square tiles (the last row and column may be narrower) covering `window`
/// row by row, in full-frame coordinates. The side is the largest of 64, 32,
/// 16, 8 pixels that still gives each worker at least 8 tiles, so that
/// handing them out as workers finish keeps every rank busy to the end.
std::vector<pnb::CropWindow> planTiles(const pnb::CropWindow& window, int workers);

}  // namespace penumbra::mpi
