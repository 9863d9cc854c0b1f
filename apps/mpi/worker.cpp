#include "worker.h"

#include <mpi.h>

#include <csignal>
#include <cstdlib>
#include <string>
#include <vector>

namespace penumbra::mpi {
namespace {

// Test hook (tests/mpi): the rank named here kills itself when its first
// tile arrives, as a crashed or OOM-killed node would.
bool killedForTest(int rank) {
    const char* v = std::getenv("PENUMBRA_MPI_TEST_KILL_RANK");
    return v && *v && std::atoi(v) == rank;
}

}  // namespace

void runWorker(const pnb::Renderer& renderer, const pnb::PreparedScene& scene, const Job& job, int rank,
               const std::string& host) {
    WorkerTotals totals;
    for (;;) {
        MPI_Status status;
        MPI_Probe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &status);
        if (status.MPI_TAG == kTagStop) {
            MPI_Recv(nullptr, 0, MPI_BYTE, 0, kTagStop, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            MPI_Send(&totals, int(sizeof totals), MPI_BYTE, 0, kTagDone, MPI_COMM_WORLD);
            return;
        }
        int window[4];
        MPI_Recv(window, 4, MPI_INT, 0, kTagTile, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (killedForTest(rank)) std::raise(SIGKILL);
        std::vector<std::uint8_t> bytes;
        std::string error;
        try {
            pnb::RenderSettings tile = job.settings;
            tile.crop = pnb::CropWindow{window[0], window[1], window[2], window[3]};
            pnb::Framebuffer image(tile);
            const pnb::RenderStats st = renderer.render(scene, job.camera, tile, image);
            totals.add(totalsOf(st));
            bytes = image.serialize();
        } catch (const std::exception& e) {
            error = rankName(rank, host) + ": " + e.what();
        }
        if (!error.empty()) {
            // Rank 0 reports it and aborts the job; this rank waits for that.
            MPI_Send(error.data(), int(error.size()), MPI_CHAR, 0, kTagFailed, MPI_COMM_WORLD);
            MPI_Recv(nullptr, 0, MPI_BYTE, 0, kTagStop, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            return;
        }
        MPI_Send(bytes.data(), int(bytes.size()), MPI_BYTE, 0, kTagResult, MPI_COMM_WORLD);
    }
}

}  // namespace penumbra::mpi
