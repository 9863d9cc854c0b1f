// What the ranks of a penumbra-mpi job tell each other: the message tags, each
// rank's setup report (gathered on rank 0) and the job rank 0 decides on
// (broadcast), so every rank renders with rank 0's settings and camera.
#pragma once

#include <mpi.h>

#include <penumbra/penumbra.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::mpi {

/// Point-to-point messages between rank 0 and a worker.
enum Tag : int {
    kTagTile = 1,    ///< 0 -> worker: int[4], a crop window to render
    kTagStop = 2,    ///< 0 -> worker: no more tiles
    kTagResult = 3,  ///< worker -> 0: the tile's serialized framebuffer
    kTagFailed = 4,  ///< worker -> 0: a render failed; the message
    kTagDone = 5,    ///< worker -> 0: WorkerTotals, after kTagStop
};

/// How one rank's loading (and preparing) went.
struct SetupReport {
    std::string error;  ///< empty when it went well
    bool usageError = false;  ///< the error is a bad option value (exit code 2, as penumbra's)
    std::string host;   ///< MPI_Get_processor_name
    // What it loaded: ranks that read different scene files must not mix tiles.
    std::int64_t primitives = 0, triangles = 0, materials = 0;
    // From preparing (workers, or rank 0 rendering alone).
    std::int64_t lights = 0;
    double buildSeconds = 0.0;
    std::string accelerator;
};

/// Gathers every rank's report on rank 0 (index = rank); other ranks get {}.
/// Collective.
std::vector<SetupReport> gatherReports(const SetupReport& mine, int rank, int size);

/// The settings and camera every rank renders with.
struct Job {
    pnb::RenderSettings settings;
    pnb::Camera camera;
};
/// What rank 0 decided: render the job, or stop with an exit code (every rank
/// returns it, so that mpirun reports the code penumbra would).
struct Decision {
    std::optional<Job> job;
    int exitCode = 1;  ///< without a job
};
/// Rank 0 passes its decision; every rank returns it. Collective.
Decision broadcastDecision(const Decision& fromRoot, int rank);

/// A worker's sums over all its tiles, sent with kTagDone.
struct WorkerTotals {
    std::uint64_t cameraRays = 0, shadowRays = 0, reflectionRays = 0, invalidRays = 0, nonFiniteSamples = 0;
    std::uint64_t tiles = 0;
    double renderSeconds = 0.0;
    std::uint64_t transmissionRays = 0, indirectRays = 0, pathLengthSum = 0;
    std::uint32_t pathLengthMax = 0;
    std::uint64_t brdfRays = 0;

    std::uint64_t totalRays() const {
        return cameraRays + shadowRays + reflectionRays + transmissionRays + indirectRays + brdfRays;
    }

    /// Adds one render call's (or one worker's) counts.
    void add(const WorkerTotals& o);
};

/// One render call's counts as totals of one tile.
WorkerTotals totalsOf(const pnb::RenderStats& st);

/// "rank 2 on node7", for messages about another rank.
std::string rankName(int rank, const std::string& host);
std::string processorName();

}  // namespace penumbra::mpi
