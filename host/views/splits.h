// Parallel splits of the camera's view frustum (Zhang et al. 2006 via Lauritzen, "Parallel-Split Variance Shadow
// Maps"; Luksch, "Pixel Accurate Shadows with Shadow Mapping", sec. 7): split distances by scheme, the automatic
// count from Luksch's optimal-tiling factor (eq. 12-16), and each split's light view cropped to its frustum.
#pragma once

#include <string>
#include <vector>

#include "host/views/light_fit.h"
#include "host/views/views.h"
#include "host/scene/camera.h"
#include "host/scene/light.h"

namespace penumbra {

enum class SplitScheme { Uniform = 0, Logarithmic = 1, Practical = 2 };

// count + 1 distances C_0 = near < C_1 < ... < C_count = far along the camera's view axis (linear view depth):
//   uniform      C_i = n + (f - n) i / m                      (Luksch eq. 9, sign corrected)
//   logarithmic  C_i = n (f / n)^(i / m)                      (Luksch eq. 8, exponent corrected)
//   practical    C_i = lambda C_i^log + (1 - lambda) C_i^uni  (Luksch eq. 11, alpha = lambda)
// Convention (Zhang et al. 2006): lambda = 1 is logarithmic, lambda = 0 uniform. Throws std::invalid_argument
// unless 0 < near < far, count >= 1 and lambda in [0, 1].
std::vector<float> splitDistances(SplitScheme scheme, int count, float near, float far, float lambda);

// Luksch eq. 15: the factor by which each split's near plane is closer than its far plane so that a shadow-map
// texel projects to `rho` pixels at the near plane: f = res sigma / (rho smRes). `res` is the viewport's width in
// pixels and `sigma` the split's light-space width in units of the camera's width at its far plane (eq. 12:
// fw = 2 f tan(alpha / 2), alpha the horizontal field of view). Eq. 16: only meaningful when the result is < 1.
float optimalTilingFactor(float res, float sigma, float rho, int mapSize);

// The automatic scheme (Luksch sec. 7.2): split planes from the far plane inwards, each `factor` times the last,
// until one would lie in front of `near`; at most `maxSplits` splits, and when that cap bites the two nearest
// splits share what is left by eq. 11 with `lambda`. factor >= 1 (eq. 16 violated) uses `maxSplits` splits of
// the practical scheme. Returns the distances (as splitDistances).
std::vector<float> autoSplitDistances(float near, float far, float factor, int maxSplits, float lambda);

// Luksch eq. 10's delta_bias: every inner plane C_1 .. C_{m-1} moved by `delta` (view depth) "according to practical
// requirements of the application", each kept strictly between its moved neighbours and inside (C_0, C_m), so the
// splits stay ordered and non-empty. C_0 and C_m never move.
void biasSplitDistances(std::vector<float>& distances, float delta);

// World-space corners of the camera frustum between view depths `near` and `far` (near four first).
std::vector<glm::vec3> frustumSliceCorners(const Camera& camera, float near, float far);

// The light-space box of a frustum slice, in fitLightView's units (directional: light-eye x/y; spot: tangents),
// intersected with the visible receivers' box, with depthMax the slice's deepest point (never beyond the
// receivers'). Empty when the slice holds no receiver or (spot) reaches behind the light.
ReceiverBounds sliceBounds(const Light& light, const glm::mat4& lightEye, const std::vector<glm::vec3>& corners,
                           const ReceiverBounds& receivers);

}  // namespace penumbra
