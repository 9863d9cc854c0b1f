#include "job.h"

#include <algorithm>
#include <cstring>

namespace penumbra::mpi {
namespace {

// The fixed part of a SetupReport as it travels (the strings follow apart).
struct ReportWire {
    std::int64_t primitives, triangles, materials, lights;
    double buildSeconds;
    std::int32_t errorLength, acceleratorLength, hostLength;
    std::int32_t usageError;
};

// A Job as it travels: plain numbers only, so MPI_BYTE is exact.
struct JobWire {
    std::int32_t go;
    std::int32_t exitCode;  // without go
    std::int32_t width, height, spp, lightSamples, maxDepth, threads, tileSize;
    std::int32_t hasCrop, x0, y0, x1, y1;
    std::int32_t lightSelection, aovs;
    std::int32_t integrator;
    std::uint64_t seed;
    float eye[3], lookAt[3], up[3], vfov, aperture, focusDistance;
    std::int32_t directLight;
};

std::vector<char> gatherStrings(const std::string& mine, const std::vector<int>& lengths, int rank, int size,
                                std::vector<int>& offsets) {
    std::vector<char> all;
    if (rank == 0) {
        offsets.assign(size_t(size), 0);
        int total = 0;
        for (int r = 0; r < size; ++r) {
            offsets[size_t(r)] = total;
            total += lengths[size_t(r)];
        }
        all.resize(size_t(total) + 1);
    }
    MPI_Gatherv(mine.data(), int(mine.size()), MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0,
                MPI_COMM_WORLD);
    return all;
}

}  // namespace

std::vector<SetupReport> gatherReports(const SetupReport& mine, int rank, int size) {
    const ReportWire w{mine.primitives, mine.triangles, mine.materials, mine.lights, mine.buildSeconds,
                       std::int32_t(mine.error.size()), std::int32_t(mine.accelerator.size()),
                       std::int32_t(mine.host.size()), std::int32_t(mine.usageError ? 1 : 0)};
    std::vector<ReportWire> wires(rank == 0 ? size_t(size) : 0);
    MPI_Gather(&w, int(sizeof w), MPI_BYTE, wires.data(), int(sizeof w), MPI_BYTE, 0, MPI_COMM_WORLD);
    std::vector<int> errorLengths, accelLengths, hostLengths, errorOffsets, accelOffsets, hostOffsets;
    for (const ReportWire& r : wires) {
        errorLengths.push_back(r.errorLength);
        accelLengths.push_back(r.acceleratorLength);
        hostLengths.push_back(r.hostLength);
    }
    const std::vector<char> errors = gatherStrings(mine.error, errorLengths, rank, size, errorOffsets);
    const std::vector<char> accels = gatherStrings(mine.accelerator, accelLengths, rank, size, accelOffsets);
    const std::vector<char> hosts = gatherStrings(mine.host, hostLengths, rank, size, hostOffsets);
    std::vector<SetupReport> reports;
    for (int r = 0; r < int(wires.size()); ++r) {
        const ReportWire& x = wires[size_t(r)];
        SetupReport s;
        s.error.assign(errors.data() + errorOffsets[size_t(r)], size_t(x.errorLength));
        s.accelerator.assign(accels.data() + accelOffsets[size_t(r)], size_t(x.acceleratorLength));
        s.host.assign(hosts.data() + hostOffsets[size_t(r)], size_t(x.hostLength));
        s.usageError = x.usageError != 0;
        s.primitives = x.primitives;
        s.triangles = x.triangles;
        s.materials = x.materials;
        s.lights = x.lights;
        s.buildSeconds = x.buildSeconds;
        reports.push_back(std::move(s));
    }
    return reports;
}

Decision broadcastDecision(const Decision& fromRoot, int rank) {
    JobWire w{};
    if (rank == 0) w.exitCode = fromRoot.exitCode;
    if (rank == 0 && fromRoot.job) {
        const pnb::RenderSettings& s = fromRoot.job->settings;
        const pnb::Camera& c = fromRoot.job->camera;
        w.go = 1;
        w.width = s.width;
        w.height = s.height;
        w.spp = s.spp;
        w.lightSamples = s.lightSamples;
        w.maxDepth = s.maxDepth;
        w.threads = s.threads;
        w.tileSize = s.tileSize;
        w.hasCrop = s.crop ? 1 : 0;
        if (s.crop) {
            w.x0 = s.crop->x0;
            w.y0 = s.crop->y0;
            w.x1 = s.crop->x1;
            w.y1 = s.crop->y1;
        }
        w.lightSelection = static_cast<std::int32_t>(s.lightSelection);
        w.aovs = s.aovs ? 1 : 0;
        w.integrator = s.integrator == pnb::IntegratorKind::Path ? 1 : 0;
        w.directLight = static_cast<std::int32_t>(s.directLight);
        w.seed = s.seed;
        const pnb::Vec3* v[3] = {&c.eye, &c.lookAt, &c.up};
        float* d[3] = {w.eye, w.lookAt, w.up};
        for (int i = 0; i < 3; ++i) {
            d[i][0] = v[i]->x;
            d[i][1] = v[i]->y;
            d[i][2] = v[i]->z;
        }
        w.vfov = c.vfovDegrees;
        w.aperture = c.aperture;
        w.focusDistance = c.focusDistance;
    }
    MPI_Bcast(&w, int(sizeof w), MPI_BYTE, 0, MPI_COMM_WORLD);
    if (!w.go) return {std::nullopt, w.exitCode};
    Job job;
    pnb::RenderSettings& s = job.settings;
    s.width = w.width;
    s.height = w.height;
    s.spp = w.spp;
    s.lightSamples = w.lightSamples;
    s.maxDepth = w.maxDepth;
    s.threads = w.threads;
    s.tileSize = w.tileSize;
    if (w.hasCrop) s.crop = pnb::CropWindow{w.x0, w.y0, w.x1, w.y1};
    s.lightSelection = static_cast<pnb::LightSelection>(w.lightSelection);
    s.aovs = w.aovs != 0;
    s.integrator = w.integrator ? pnb::IntegratorKind::Path : pnb::IntegratorKind::Whitted;
    s.directLight = static_cast<pnb::DirectLightSampling>(w.directLight);
    s.seed = w.seed;
    pnb::Camera& c = job.camera;
    c.eye = {w.eye[0], w.eye[1], w.eye[2]};
    c.lookAt = {w.lookAt[0], w.lookAt[1], w.lookAt[2]};
    c.up = {w.up[0], w.up[1], w.up[2]};
    c.vfovDegrees = w.vfov;
    c.aperture = w.aperture;
    c.focusDistance = w.focusDistance;
    return {job, 0};
}

std::string rankName(int rank, const std::string& host) {
    return "rank " + std::to_string(rank) + (host.empty() ? std::string() : " on " + host);
}

std::string processorName() {
    char name[MPI_MAX_PROCESSOR_NAME] = {};
    int length = 0;
    MPI_Get_processor_name(name, &length);
    return std::string(name, size_t(length > 0 ? length : 0));
}

WorkerTotals totalsOf(const pnb::RenderStats& st) {
    WorkerTotals t;
    t.cameraRays = st.cameraRays;
    t.shadowRays = st.shadowRays;
    t.reflectionRays = st.reflectionRays;
    t.invalidRays = st.invalidRays;
    t.nonFiniteSamples = st.nonFiniteSamples;
    t.tiles = 1;
    t.renderSeconds = st.renderSeconds;
    t.transmissionRays = st.transmissionRays;
    t.indirectRays = st.indirectRays;
    t.pathLengthSum = st.pathLengthSum;
    t.pathLengthMax = st.pathLengthMax;
    t.brdfRays = st.brdfRays;
    return t;
}

void WorkerTotals::add(const WorkerTotals& o) {
    cameraRays += o.cameraRays;
    shadowRays += o.shadowRays;
    reflectionRays += o.reflectionRays;
    invalidRays += o.invalidRays;
    nonFiniteSamples += o.nonFiniteSamples;
    tiles += o.tiles;
    renderSeconds += o.renderSeconds;
    transmissionRays += o.transmissionRays;
    indirectRays += o.indirectRays;
    pathLengthSum += o.pathLengthSum;
    pathLengthMax = std::max(pathLengthMax, o.pathLengthMax);
    brdfRays += o.brdfRays;
}

}  // namespace penumbra::mpi
