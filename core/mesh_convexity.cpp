#include "core/mesh_convexity.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace penumbra {

float convexSlack(const TriangleMesh& m) {
    constexpr size_t kMaxSteps = size_t(1) << 22;
    const size_t nt = m.triangleCount(), nv = m.positions.size();
    if (nt == 0 || nv == 0 || nt > kMaxSteps / nv) return kInfinity;
    // In double, so that the slack measures the mesh and not this test's rounding.
    std::vector<double> x(nv), y(nv), z(nv);
    double largest = 1.0;
    for (size_t i = 0; i < nv; ++i) {
        x[i] = m.positions[i].x;
        y[i] = m.positions[i].y;
        z[i] = m.positions[i].z;
        largest = std::max({largest, std::fabs(x[i]), std::fabs(y[i]), std::fabs(z[i])});
    }
    const double limit = std::ldexp(largest, -17);
    double slack = 0.0;
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t* idx = &m.indices[3 * t];
        const uint32_t a = idx[0], b = idx[1], c = idx[2];
        const double ux = x[b] - x[a], uy = y[b] - y[a], uz = z[b] - z[a];
        const double vx = x[c] - x[a], vy = y[c] - y[a], vz = z[c] - z[a];
        double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
        const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
        if (!(len > 0.0)) return kInfinity;  // finalize() drops such triangles: a mesh not prepared
        nx /= len;
        ny /= len;
        nz /= len;
        const double offset = nx * x[a] + ny * y[a] + nz * z[a];
        // Four running maxima: one chain of dependent comparisons was most of a load's time.
        double front[4] = {0.0, 0.0, 0.0, 0.0};
        size_t i = 0;
        for (; i + 4 <= nv; i += 4)
            for (size_t k = 0; k < 4; ++k)
                front[k] = std::max(front[k], nx * x[i + k] + ny * y[i + k] + nz * z[i + k] - offset);
        for (; i < nv; ++i) front[0] = std::max(front[0], nx * x[i] + ny * y[i] + nz * z[i] - offset);
        slack = std::max({slack, front[0], front[1], front[2], front[3]});
        if (slack > limit) return kInfinity;
    }
    return static_cast<float>(slack * (1.0 + 1e-6));
}

}  // namespace penumbra
