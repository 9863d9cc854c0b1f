// A worker rank of penumbra-mpi: renders the tiles rank 0 hands it.
#pragma once

#include <penumbra/penumbra.hpp>

#include <string>

#include "job.h"

namespace penumbra::mpi {

/// Renders tiles (the job's settings with the crop set to each tile) until
/// rank 0 says stop, sending each tile's framebuffer back; then its totals.
/// A failed render is reported to rank 0 (kTagFailed), which ends the job.
void runWorker(const pnb::Renderer& renderer, const pnb::PreparedScene& scene, const Job& job, int rank,
               const std::string& host);

}  // namespace penumbra::mpi
