// Multiple importance sampling weights (Veach & Guibas 1995).
#pragma once

namespace penumbra {

/// Power heuristic (beta = 2) weight of a sample drawn with pdf fPdf from a
/// strategy taking nf samples, against one taking ng samples with pdf gPdf
/// (all pdfs per unit solid angle). 0 when fPdf is 0; 1 when gPdf is 0.
inline float powerHeuristic(float nf, float fPdf, float ng, float gPdf) {
    const float f = nf * fPdf, g = ng * gPdf;
    if (!(f > 0.f)) return 0.f;
    if (!(g > 0.f)) return 1.f;
    // Ratio form: no overflow of f^2 for the huge pdfs of tiny lights.
    const float r = g / f;
    return 1.f / (1.f + r * r);
}

}  // namespace penumbra
