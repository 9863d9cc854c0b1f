// Multiple importance sampling weights (Veach & Guibas 1995).
#pragma once

namespace penumbra {

/// Power heuristic (beta = 2) weight of a sample drawn with pdf fPdf from a
/// strategy taking nf samples, against one taking ng samples with pdf gPdf
/// (all pdfs per unit solid angle). 0 when fPdf is 0; 1 when gPdf is 0.
/// Without branches, so that a loop over lanes vectorises it (the ratio
/// is worked out where it is not used, too: no trap, a select drops it).
inline float powerHeuristic(float nf, float fPdf, float ng, float gPdf) {
    const float f = nf * fPdf, g = ng * gPdf;
    // Ratio form: no overflow of f^2 for the huge pdfs of tiny lights.
    const float r = g / f;
    const float w = 1.f / (1.f + r * r);
    return !(f > 0.f) ? 0.f : !(g > 0.f) ? 1.f : w;
}

}  // namespace penumbra
