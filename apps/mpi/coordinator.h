// Rank 0 of a penumbra-mpi job with workers: hands out tiles as workers
// finish them and pastes the results into the frame.
#pragma once

#include <penumbra/penumbra.hpp>

#include <cstdint>
#include <functional>
#include <vector>

#include "job.h"

namespace penumbra::mpi {

struct FrameResult {
    pnb::Framebuffer image;        ///< the render window, assembled
    WorkerTotals totals;           ///< summed over the workers
    std::vector<std::uint64_t> tilesPerRank;
    std::size_t tileCount = 0;
    double wallSeconds = 0.0;      ///< first tile out to last tile back
};

/// Runs the frame over ranks 1..size-1. `progress` sees (tiles done, tiles).
/// A worker's failure is printed as one error line and ends the whole job
/// (MPI_Abort) before anything is written; a rank that dies ends it through
/// MPI's own error handling.
FrameResult runCoordinator(const Job& job, int size, const std::function<void(std::size_t, std::size_t)>& progress);

}  // namespace penumbra::mpi
