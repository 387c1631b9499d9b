// Double-precision reference of the moments stage, written from the papers independently of the kernels:
// depth normalisation with invalid -> far, VSM, EVSM2/4, LVSM layer warps, MSM quantization transform.
#pragma once

#include <vector>

#include "host/stages/moments.h"

namespace penumbra::ref {

// Normalised depth in [0, 1]; NaN and infinities are 1 (no occluder).
double normalizeDepth(double depth, double depthNear, double depthFar);

// Same layout as computeMoments: planes x texels x momentChannels(kind) values.
std::vector<double> moments(const std::vector<float>& depth, const MomentsConfig& config);

// The reference of computeMomentsReduced: each factor x factor block's mean of the per-texel moments, texels beyond the
// map counted as an empty texel's (+inf depth). Layout as the stage's: reducedExtent(width) x reducedExtent(height).
std::vector<double> momentBlockMeans(const std::vector<float>& depth, uint32_t width, uint32_t height,
                                     const MomentsConfig& config, uint32_t factor);

// Peters & Klein 2015: the optimized 4-moment quantization and its inverse.
void msmEncode(double d, double out[4]);
void msmDecode(const double q[4], double out[4]);

// 16-bit unorm code of a moment: x clamped to [0, 1] times 65535, rounded to nearest; NaN -> 0.
int unorm16(double x);

}  // namespace penumbra::ref
