// Split distances (uniform, logarithmic, practical, automatic) and each split's light-space crop box.
#include "host/views/splits.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace penumbra {

std::vector<float> splitDistances(SplitScheme scheme, int count, float near, float far, float lambda) {
  if (!(near > 0.0f && far > near) || count < 1 || !(lambda >= 0.0f && lambda <= 1.0f))
    throw std::invalid_argument(
        fmt::format("split distances: need 0 < near < far, count >= 1, lambda in [0, 1] (got {}, {}, {}, {})", near,
                    far, count, lambda));
  const double n = near, f = far, m = count;
  const double weight = scheme == SplitScheme::Uniform ? 0.0 : scheme == SplitScheme::Logarithmic ? 1.0 : lambda;
  std::vector<float> c(static_cast<size_t>(count) + 1);
  for (int i = 0; i <= count; ++i) {
    const double logarithmic = n * std::pow(f / n, i / m), uniform = n + (f - n) * (i / m);
    c[static_cast<size_t>(i)] = static_cast<float>(weight * logarithmic + (1.0 - weight) * uniform);
  }
  c.front() = near, c.back() = far;  // exact ends, whatever the rounding
  return c;
}

float optimalTilingFactor(float res, float sigma, float rho, int mapSize) {
  return res * sigma / (rho * static_cast<float>(mapSize));
}

std::vector<float> autoSplitDistances(float near, float far, float factor, int maxSplits, float lambda) {
  if (!(near > 0.0f && far > near) || maxSplits < 1)
    throw std::invalid_argument(fmt::format("auto splits: need 0 < near < far and maxSplits >= 1"));
  if (!(factor > 0.0f && factor < 1.0f))  // eq. 16 does not hold: no split count reaches the target
    return splitDistances(SplitScheme::Practical, maxSplits, near, far, lambda);
  const double needed = std::ceil(std::log(double(near) / far) / std::log(double(factor)) - 1e-9);
  const int count = std::max(1, static_cast<int>(std::min<double>(needed, 1 << 20)));
  const int m = std::min(count, maxSplits);
  std::vector<float> c(static_cast<size_t>(m) + 1);
  c.front() = near, c.back() = far;
  // Planes by the factor from the far end (sec. 7.2); if capped, the nearest two splits come from eq. 11.
  const int byFactor = count <= maxSplits ? m - 1 : m - 2;
  for (int k = 1; k <= byFactor; ++k) c[static_cast<size_t>(m - k)] = far * std::pow(factor, static_cast<float>(k));
  if (count > maxSplits && m >= 2) c[1] = splitDistances(SplitScheme::Practical, 2, near, c[2], lambda)[1];
  return c;
}

void biasSplitDistances(std::vector<float>& distances, float delta) {
  const size_t m = distances.size();
  if (m < 3 || delta == 0.0f) return;
  const float near = distances.front(), far = distances.back();
  const float gap = (far - near) * 1e-4f / static_cast<float>(m);  // the least depth a split keeps
  for (size_t i = 1; i + 1 < m; ++i) {
    const float lo = distances[i - 1] + gap, hi = far - gap * static_cast<float>(m - 1 - i);
    distances[i] = std::clamp(distances[i] + delta, lo, std::max(lo, hi));
  }
}

std::vector<glm::vec3> frustumSliceCorners(const Camera& camera, float near, float far) {
  const glm::mat4 toWorld = glm::inverse(camera.view());
  std::vector<glm::vec3> corners;
  for (float d : {near, far}) {
    const glm::vec2 half = camera.halfExtentAt(d);  // grows with d for a pinhole; constant for ortho (a box)
    for (int i = 0; i < 4; ++i)
      corners.push_back(glm::vec3(toWorld * glm::vec4(i & 1 ? half.x : -half.x, i & 2 ? half.y : -half.y, -d, 1.0f)));
  }
  return corners;
}

ReceiverBounds sliceBounds(const Light& light, const glm::mat4& lightEye, const std::vector<glm::vec3>& corners,
                           const ReceiverBounds& receivers) {
  if (receivers.empty) return receivers;
  glm::vec2 lo(INFINITY), hi(-INFINITY);
  float deepest = -INFINITY;
  for (const glm::vec3& c : corners) {
    const glm::vec3 e = glm::vec3(lightEye * glm::vec4(c, 1.0f));
    const float depth = -e.z;
    glm::vec2 xy(e);
    if (light.type == LightType::Spot) {
      if (!(depth > 0.0f)) return receivers;  // the slice reaches behind the spot: keep every visible receiver
      xy /= depth;                            // tangents, the unit a perspective map's texels are uniform in
    }
    lo = glm::min(lo, xy), hi = glm::max(hi, xy), deepest = std::max(deepest, depth);
  }
  ReceiverBounds b = receivers;
  b.lo = glm::max(lo, receivers.lo), b.hi = glm::min(hi, receivers.hi);
  b.depthMax = std::min(deepest, receivers.depthMax);
  b.empty = !(b.lo.x <= b.hi.x && b.lo.y <= b.hi.y);
  return b;
}

}  // namespace penumbra
