// Piecewise-constant distributions in 1D and 2D, sampled by inverting their
// CDFs (continuous, so a sample lands anywhere inside its cell). The 2D one
// picks a row by its marginal, then a column by that row's conditional; the
// environment light uses it over its lat-long image.
//
// The inversion searches only the few CDF entries a guide table leaves
// (Chen and Asau's cutpoints): a binary search over a whole row of a 1k map
// missed the cache at almost every step. It finds the cell the search over
// the whole CDF finds, bit for bit.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.h"

namespace penumbra {

/// A step function f on [0, 1) with n equal cells, as a density.
class Distribution1D {
public:
    /// f: the cell values (>= 0; non-finite and negative values count as 0).
    /// An all-zero f samples uniformly (integral() stays 0).
    explicit Distribution1D(std::span<const float> f);

    struct Point {
        float x;  // in [0, 1)
        int cell;
    };
    struct Sample {
        float x;    // in [0, 1)
        float pdf;  // density at x with respect to dx on [0, 1)
        int cell;
    };
    /// Inverts the CDF at u in [0, 1): where sample(u) lands, without reading
    /// the density (a caller that keeps its own per-cell data saves a load).
    Point locate(float u) const { return locateIn(u, range(u)); }
    /// locate() in three steps, for callers that overlap the memory reads of
    /// many u (Distribution2D::locateLanes): the guide entries of u's slot
    /// bound the CDF entries to search; locateIn searches them.
    struct Range {
        uint32_t first, last;
    };
    void prefetchRange(float u) const { __builtin_prefetch(guide_.data() + slotOf(u)); }
    Range range(float u) const {
        const size_t k = size_t(slotOf(u));
        return {guide_[k], guide_[k + 1]};
    }
    void prefetchCdf(Range r) const { __builtin_prefetch(cdf_.data() + r.first); }
    Point locateIn(float u, Range r) const;
    /// Inverts the CDF at u in [0, 1).
    Sample sample(float u) const;
    /// Density of cell i (0 outside).
    float pdf(int cell) const;
    int size() const { return int(func_.size()); }
    /// Integral of f over [0, 1): the mean of the cells.
    float integral() const { return integral_; }

private:
    /// The guide slot of u: monotone in u, so the CDF entries in slot k
    /// bound the search for every u in it.
    int slotOf(float u) const {
        const float s = u * float(size());
        return s > 0.f ? int(std::min(s, float(size() - 1))) : 0;
    }

    std::vector<float> func_;  // cleaned f, or all ones when f integrates to 0
    std::vector<float> cdf_;   // size n + 1, cdf_[0] = 0, cdf_[n] = 1
    // guide_[k]: the first CDF entry whose slot is k or later (n + 1 slots, one past the last).
    std::vector<uint32_t> guide_;
    float integral_ = 0.f;
};

/// A step function f on [0, 1)^2 with nu x nv cells (row-major, v = row).
class Distribution2D {
public:
    /// f: nu * nv values, f[v * nu + u]; nu, nv >= 1.
    Distribution2D(std::span<const float> f, int nu, int nv);

    struct Cell {
        Vec2f uv;         // in [0, 1)^2
        int column, row;  // the cell uv lies in: f[row * nu + column]
    };
    struct Sample {
        Vec2f uv;   // in [0, 1)^2
        float pdf;  // density with respect to du dv
    };
    /// Where sample(u) lands, and its cell, without reading the density.
    Cell locate(Vec2f u) const;
    /// out[l] = locate({ux[l], uy[l]}) for l < n, the same values. The
    /// points' reads are issued together (prefetched), step by step: in a
    /// large map each step is a cache miss, which one point at a time would
    /// wait for in turn.
    void locateLanes(const float* ux, const float* uy, int n, Cell* out) const;
    Sample sample(Vec2f u) const;
    /// Density of cell (column, row): the pdf sample() gives in it.
    float cellPdf(int column, int row) const;
    /// Density at uv (clamped into the unit square).
    float pdf(Vec2f uv) const;
    int width() const { return nu_; }
    int height() const { return nv_; }

private:
    int nu_, nv_;
    std::vector<Distribution1D> conditional_;  // one per row
    Distribution1D marginal_;                  // over rows
};

}  // namespace penumbra
