#include "support/chi_square.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <vector>

namespace penumbra::test {

namespace {

constexpr double kPiD = 3.14159265358979323846;

// Regularised upper incomplete gamma Q(a, x): series below a + 1, Lentz's
// continued fraction above (the usual split: both converge fast there).
double upperGammaQ(double a, double x) {
    if (x <= 0.0) return 1.0;
    const double logPrefix = -x + a * std::log(x) - std::lgamma(a);
    if (x < a + 1.0) {
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < 10000; ++n) {
            term *= x / (a + n);
            sum += term;
            if (std::fabs(term) < std::fabs(sum) * 1e-15) break;
        }
        return 1.0 - sum * std::exp(logPrefix);
    }
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::fabs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::fabs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::fabs(delta - 1.0) < 1e-15) break;
    }
    return std::exp(logPrefix) * h;
}

}  // namespace

double chiSquareSurvival(double x, int k) { return upperGammaQ(0.5 * k, 0.5 * x); }

ChiSquareResult chiSquareDirections(const std::function<std::optional<Vec3f>(uint32_t)>& sample,
                                    const std::function<double(const Vec3f&)>& pdf, const ChiSquareOptions& o) {
    const int nT = o.thetaBins, nP = o.phiBins;
    const size_t cells = size_t(nT) * size_t(nP);
    std::vector<double> observed(cells + 1, 0.0), expected(cells + 1, 0.0);
    uint32_t got = 0;
    for (uint32_t i = 0; i < o.samples; ++i) {
        const std::optional<Vec3f> w = sample(i);
        if (!w) {
            observed[cells] += 1.0;
            continue;
        }
        ++got;
        const double theta = std::acos(std::clamp(double(w->z), -1.0, 1.0));
        double phi = std::atan2(double(w->y), double(w->x));
        if (phi < 0) phi += 2.0 * kPiD;
        const int ti = std::min(nT - 1, int(theta / kPiD * nT));
        const int pi = std::min(nP - 1, int(phi / (2.0 * kPiD) * nP));
        observed[size_t(ti) * nP + pi] += 1.0;
    }
    // Expected counts: the pdf integrated over each cell (midpoint rule in
    // theta and phi with the sin(theta) Jacobian), refined where the pdf is
    // not constant over the coarse points: light pdfs jump at the emitter's
    // outline, which a coarse rule would misplace by a whole step.
    const auto integrateCell = [&](int ti, int pi, int s, double* lo, double* hi) {
        // lo and hi: the least and largest pdf value met.
        const double dT = kPiD / (nT * s), dP = 2.0 * kPiD / (nP * s);
        double sum = 0.0;
        for (int a = 0; a < s; ++a) {
            const double theta = (ti * s + a + 0.5) * dT;
            const double st = std::sin(theta), ct = std::cos(theta);
            for (int b = 0; b < s; ++b) {
                const double phi = (pi * s + b + 0.5) * dP;
                const double v = pdf(Vec3f{float(st * std::cos(phi)), float(st * std::sin(phi)), float(ct)});
                *lo = std::min(*lo, v);
                *hi = std::max(*hi, v);
                sum += v * st;
            }
        }
        return sum * dT * dP;
    };
    // Refine a cell when the pdf varies over its coarse points or differs
    // from a neighbour's: an outline can clip a cell between coarse points.
    std::vector<double> coarse(cells), lo(cells, 1e300), hi(cells, -1e300);
    for (int ti = 0; ti < nT; ++ti)
        for (int pi = 0; pi < nP; ++pi) {
            const size_t c = size_t(ti) * nP + pi;
            coarse[c] = integrateCell(ti, pi, o.subdivisions, &lo[c], &hi[c]);
        }
    double integral = 0.0;
    for (int ti = 0; ti < nT; ++ti)
        for (int pi = 0; pi < nP; ++pi) {
            const size_t c = size_t(ti) * nP + pi;
            bool refine = lo[c] != hi[c];
            for (int dt = -1; dt <= 1 && !refine; ++dt)
                for (int dp = -1; dp <= 1 && !refine; ++dp) {
                    const int t2 = ti + dt, p2 = (pi + dp + nP) % nP;
                    if (t2 < 0 || t2 >= nT) continue;
                    const size_t n2 = size_t(t2) * nP + p2;
                    refine = lo[n2] != hi[n2] || lo[n2] != lo[c];
                }
            double mass = coarse[c];
            if (refine) {
                double l = 1e300, h = -1e300;
                mass = integrateCell(ti, pi, o.fineSubdivisions, &l, &h);
            }
            integral += mass;
            expected[c] = mass * o.samples;
        }
    // The extra cell of samples the sampler did not return takes the pdf's
    // missing mass only when there are some: a sampler that never fails is
    // held to an integral of 1 by the caller, not by a cell that would turn
    // the integration's small error into a large chi-square term.
    const bool rejections = observed[cells] > 0.0;
    expected[cells] = rejections ? std::max(0.0, 1.0 - integral) * o.samples : 0.0;

    // Pool the cells expecting fewer than 5 samples (smallest first) into one.
    std::vector<size_t> order(cells + 1);
    std::iota(order.begin(), order.end(), size_t(0));
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
    double stat = 0.0, poolO = 0.0, poolE = 0.0;
    int dof = -1;
    double worstTerm = -1.0;
    size_t worst = 0;
    double strays = 0.0;  // samples where the pdf is 0 (rounding at an outline allows a few)
    for (size_t i : order) {
        if (i == cells && !rejections) continue;
        if (expected[i] == 0.0) strays += observed[i];
        if (expected[i] == 0.0 && observed[i] > 0.0 && strays > std::max(2.0, 1e-4 * o.samples)) {
            ChiSquareResult r;
            r.pdfIntegral = integral;
            std::ostringstream m;
            m << strays << " samples where the pdf is 0, e.g. " << observed[i] << " in cell " << i << " (theta bin "
              << i / nP << ", phi bin " << i % nP << ")";
            r.message = m.str();
            return r;
        }
        if (expected[i] < 5.0) {
            poolO += observed[i];
            poolE += expected[i];
            continue;
        }
        const double term = (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
        if (term > worstTerm) {
            worstTerm = term;
            worst = i;
        }
        stat += term;
        ++dof;
    }
    if (poolE > 0.0) {
        stat += (poolO - poolE) * (poolO - poolE) / poolE;
        ++dof;
    }
    ChiSquareResult r;
    r.statistic = stat;
    r.degreesOfFreedom = std::max(dof, 1);
    r.pValue = chiSquareSurvival(stat, r.degreesOfFreedom);
    r.sampledFraction = double(got) / o.samples;
    r.pdfIntegral = integral;
    r.passed = r.pValue > o.significance;
    std::ostringstream m;
    m << "chi^2 = " << stat << " with " << r.degreesOfFreedom << " dof, p = " << r.pValue << " (significance "
      << o.significance << "), pdf integral " << integral << ", sampled fraction " << r.sampledFraction;
    if (worstTerm >= 0.0)
        m << "; largest term " << worstTerm << " in theta bin " << worst / nP << ", phi bin " << worst % nP
          << ": observed " << observed[worst] << ", expected " << expected[worst];
    r.message = m.str();
    return r;
}

}  // namespace penumbra::test
