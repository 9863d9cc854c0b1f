#include "coordinator.h"

#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "tile_plan.h"

namespace penumbra::mpi {
namespace {

void sendTile(const pnb::CropWindow& t, int rank) {
    const int window[4] = {t.x0, t.y0, t.x1, t.y1};
    MPI_Send(window, 4, MPI_INT, rank, kTagTile, MPI_COMM_WORLD);
}

// Waits for the next message from any worker. Polls with short sleeps: a
// blocking MPI_Probe spins on a core, which the workers beside rank 0 on the
// same node need (with the next tile already queued on every worker, the
// 1 ms sleep delays no one).
MPI_Status nextMessage() {
    MPI_Status status;
    for (;;) {
        int flag = 0;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
        if (flag) return status;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
}

void sendStop(int rank) { MPI_Send(nullptr, 0, MPI_BYTE, rank, kTagStop, MPI_COMM_WORLD); }

[[noreturn]] void abortJob(const std::string& message) {
    std::fprintf(stderr, "penumbra-mpi: error: %s; no image written\n", message.c_str());
    std::fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, 1);
    std::_Exit(1);  // MPI_Abort does not return; this keeps the compiler sure of it
}

}  // namespace

FrameResult runCoordinator(const Job& job, int size, const std::function<void(std::size_t, std::size_t)>& progress) {
    const pnb::RenderSettings& s = job.settings;
    const pnb::CropWindow window = pnb::renderWindow(s);
    const std::vector<pnb::CropWindow> tiles = planTiles(window, size - 1);
    FrameResult result;
    result.image = pnb::Framebuffer(s);
    result.tilesPerRank.assign(size_t(size), 0);
    result.tileCount = tiles.size();
    const auto t0 = std::chrono::steady_clock::now();

    // Every worker starts with kInFlight tiles and gets the next one each time
    // it returns one, so a slow node renders fewer tiles instead of holding the
    // frame, and a worker never waits for rank 0 between tiles (the next one
    // is already queued while it renders). A worker with nothing left in flight
    // is told to stop and confirms with its totals (kTagDone); the frame is
    // complete when all have, so a rank lost before that point leaves no image.
    constexpr int kInFlight = 2;
    size_t next = 0, done = 0;
    int running = size - 1;
    std::vector<int> inFlight(size_t(size), 0);
    for (int round = 0; round < kInFlight; ++round)
        for (int r = 1; r < size; ++r)
            if (next < tiles.size()) {
                sendTile(tiles[next++], r);
                ++inFlight[size_t(r)];
            }
    for (int r = 1; r < size; ++r)
        if (inFlight[size_t(r)] == 0) sendStop(r);
    std::vector<std::uint8_t> bytes;
    while (running > 0) {
        const MPI_Status status = nextMessage();
        const int from = status.MPI_SOURCE;
        if (status.MPI_TAG == kTagFailed) {
            int length = 0;
            MPI_Get_count(&status, MPI_CHAR, &length);
            std::string message(size_t(length), '\0');
            MPI_Recv(message.data(), length, MPI_CHAR, from, kTagFailed, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            abortJob(message);
        }
        if (status.MPI_TAG == kTagDone) {
            WorkerTotals t;
            MPI_Recv(&t, int(sizeof t), MPI_BYTE, from, kTagDone, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            result.totals.add(t);
            --running;
            continue;
        }
        int length = 0;
        MPI_Get_count(&status, MPI_BYTE, &length);
        bytes.resize(size_t(length));
        MPI_Recv(bytes.data(), length, MPI_BYTE, from, kTagResult, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        try {
            result.image.paste(pnb::Framebuffer::deserialize(bytes.data(), bytes.size()));
        } catch (const std::exception& e) {
            abortJob("a tile from rank " + std::to_string(from) + ": " + e.what());
        }
        ++result.tilesPerRank[size_t(from)];
        if (progress) progress(++done, tiles.size());
        --inFlight[size_t(from)];
        if (next < tiles.size()) {
            sendTile(tiles[next++], from);
            ++inFlight[size_t(from)];
        } else if (inFlight[size_t(from)] == 0) {
            sendStop(from);
        }
    }
    result.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (done != tiles.size()) abortJob("the workers returned " + std::to_string(done) + " of " + std::to_string(tiles.size()) + " tiles");
    return result;
}

}  // namespace penumbra::mpi
