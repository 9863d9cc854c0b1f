#include "core/distribution2d.h"

#include <algorithm>

#include "core/error.h"

namespace penumbra {

Distribution1D::Distribution1D(std::span<const float> f) : func_(f.begin(), f.end()), cdf_(f.size() + 1, 0.f) {
    if (func_.empty()) throw Error(ErrorCode::InvalidArgument, "a distribution needs at least one cell");
    const size_t n = func_.size();
    // Summed in double: a 4k x 2k image's rows have thousands of cells.
    double sum = 0.0;
    for (float& v : func_) {
        if (!(std::isfinite(v) && v > 0.f)) v = 0.f;
        sum += v;
    }
    if (!(sum > 0.0)) {
        std::fill(func_.begin(), func_.end(), 1.f);
        sum = double(n);
    } else {
        integral_ = float(sum / double(n));
    }
    double acc = 0.0;
    for (size_t i = 0; i < n; ++i) {
        acc += func_[i];
        cdf_[i + 1] = float(acc / sum);
    }
    cdf_[n] = 1.f;
    // Normalise the cells to a density on [0, 1): pdf(i) = f_i / mean(f).
    const float invMean = float(double(n) / sum);
    for (float& v : func_) v *= invMean;
    // One slot per cell; the CDF is non-decreasing, so each slot's entries are a run.
    guide_.assign(n + 1, uint32_t(n + 1));
    for (size_t j = n + 1; j-- > 0;) guide_[size_t(slotOf(cdf_[j]))] = uint32_t(j);
    for (size_t k = n; k-- > 0;) guide_[k] = std::min(guide_[k], guide_[k + 1]);
}

Distribution1D::Point Distribution1D::locateIn(float u, Range r) const {
    const int n = size();
    // The last cell whose cdf start is <= u (cells of zero width are never
    // chosen): the first entry above u. Entries of earlier slots are below u
    // and those of later slots above it, so it lies among u's slot's entries
    // (r) or is the first of the next slot's.
    const auto it = std::upper_bound(cdf_.begin() + r.first, cdf_.begin() + r.last, u);
    int i = std::clamp(int(it - cdf_.begin()) - 1, 0, n - 1);
    // For u < 1 cell i has width (an empty cell adds nothing to the CDF);
    // u == 1 may round onto a trailing empty cell.
    while (i > 0 && !(cdf_[size_t(i) + 1] > cdf_[size_t(i)])) --i;
    const float lo = cdf_[size_t(i)], hi = cdf_[size_t(i) + 1];
    float t = hi > lo ? (u - lo) / (hi - lo) : 0.5f;
    t = std::clamp(t, 0.f, 1.f);
    float x = (float(i) + t) / float(n);
    x = std::min(x, std::nextafter(1.f, 0.f));
    return {x, i};
}

Distribution1D::Sample Distribution1D::sample(float u) const {
    const Point p = locate(u);
    return {p.x, func_[size_t(p.cell)], p.cell};
}

float Distribution1D::pdf(int cell) const {
    if (cell < 0 || cell >= size()) return 0.f;
    return func_[size_t(cell)];
}

namespace {

std::vector<float> rowIntegrals(const std::vector<Distribution1D>& rows) {
    std::vector<float> out;
    out.reserve(rows.size());
    for (const Distribution1D& d : rows) out.push_back(d.integral());
    return out;
}

std::vector<Distribution1D> makeRows(std::span<const float> f, int nu, int nv) {
    if (nu < 1 || nv < 1 || f.size() != size_t(nu) * size_t(nv))
        throw Error(ErrorCode::InvalidArgument, "distribution size does not match its values");
    std::vector<Distribution1D> rows;
    rows.reserve(size_t(nv));
    for (int v = 0; v < nv; ++v) rows.emplace_back(f.subspan(size_t(v) * size_t(nu), size_t(nu)));
    return rows;
}

}  // namespace

Distribution2D::Distribution2D(std::span<const float> f, int nu, int nv)
    : nu_(nu), nv_(nv), conditional_(makeRows(f, nu, nv)), marginal_(rowIntegrals(conditional_)) {}

Distribution2D::Cell Distribution2D::locate(Vec2f u) const {
    Cell c;
    locateLanes(&u.x, &u.y, 1, &c);
    return c;
}

void Distribution2D::locateLanes(const float* ux, const float* uy, int n, Cell* out) const {
    constexpr int kChunk = 16;
    for (; n > kChunk; n -= kChunk, ux += kChunk, uy += kChunk, out += kChunk) locateLanes(ux, uy, kChunk, out);
    // The marginal is small and stays in cache; a row's guide table and CDF
    // are read where u falls, one miss after the other.
    for (int l = 0; l < n; ++l) {
        const Distribution1D::Point row = marginal_.locate(uy[l]);
        out[l].uv.y = row.x;
        out[l].row = row.cell;
        conditional_[size_t(row.cell)].prefetchRange(ux[l]);
    }
    Distribution1D::Range ranges[kChunk];
    for (int l = 0; l < n; ++l) {
        const Distribution1D& d = conditional_[size_t(out[l].row)];
        ranges[l] = d.range(ux[l]);
        d.prefetchCdf(ranges[l]);
    }
    for (int l = 0; l < n; ++l) {
        const Distribution1D::Point col = conditional_[size_t(out[l].row)].locateIn(ux[l], ranges[l]);
        out[l].uv.x = col.x;
        out[l].column = col.cell;
    }
}

Distribution2D::Sample Distribution2D::sample(Vec2f u) const {
    const Cell c = locate(u);
    return {c.uv, cellPdf(c.column, c.row)};
}

float Distribution2D::cellPdf(int column, int row) const {
    return marginal_.pdf(row) * conditional_[size_t(row)].pdf(column);
}

float Distribution2D::pdf(Vec2f uv) const {
    const int iu = std::clamp(int(uv.x * float(nu_)), 0, nu_ - 1);
    const int iv = std::clamp(int(uv.y * float(nv_)), 0, nv_ - 1);
    return cellPdf(iu, iv);
}

}  // namespace penumbra
