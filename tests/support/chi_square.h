// Chi-square goodness-of-fit test of a direction sampler against its pdf, as
// pbrt-v4 and Mitsuba test theirs: sampled directions are binned on a
// (theta, phi) grid about +z, each cell's expected count is the pdf integrated
// numerically over the cell, cells with few expected samples are pooled, and
// the statistic's p-value must exceed the significance level.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "core/math.h"

namespace penumbra::test {

struct ChiSquareOptions {
    uint32_t samples = 200000;
    int thetaBins = 20;       // over [0, pi]
    int phiBins = 40;         // over [0, 2 pi)
    int subdivisions = 8;       // midpoint-rule steps per cell and axis for the expected counts
    int fineSubdivisions = 128; // the same where the pdf varies over the cell
    double significance = 0.01;
};

struct ChiSquareResult {
    bool passed = false;
    double statistic = 0.0;
    int degreesOfFreedom = 0;
    double pValue = 0.0;
    double sampledFraction = 0.0;  // samples that returned a direction
    double pdfIntegral = 0.0;      // integral of the pdf over the sphere
    std::string message;           // a readable summary for the assertion
};

/// sample(i) draws the i-th direction (unit; nullopt when the sampler gives
/// none, e.g. below the surface: those go to one extra cell, whose expected
/// count is the pdf mass the grid does not account for). A few samples where
/// the pdf is 0 (rounding at an outline) are tolerated: 2 or 1e-4 of them. pdf(w) is the
/// solid-angle density of w. Rotate the problem so no lobe sits on the pole.
ChiSquareResult chiSquareDirections(const std::function<std::optional<Vec3f>(uint32_t)>& sample,
                                    const std::function<double(const Vec3f&)>& pdf,
                                    const ChiSquareOptions& options = {});

/// 1 - CDF of the chi-square distribution with k degrees of freedom at x.
double chiSquareSurvival(double x, int k);

}  // namespace penumbra::test
