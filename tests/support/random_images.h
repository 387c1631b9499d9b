// Random inputs for the stage tests: images of values in [0, 1), and light depth maps with background (+INF) and
// NaN texels mixed in, as a rasterized shadow map can hold them.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace penumbra::test {

// `count` floats uniform in [0, 1); the same seed gives the same image.
inline std::vector<float> randomUnitImage(size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> image(count);
  for (float& v : image) v = unit(rng);
  return image;
}

// width x height depths: 1 texel in 5 background, 1 in 29 NaN, the rest uniform in [1, 50]; every texel
// background when `empty`. The same seed gives the same map.
inline std::vector<float> randomDepthMap(uint32_t width, uint32_t height, uint32_t seed, bool empty = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> depth(1.0f, 50.0f);
  std::vector<float> map(size_t(width) * height);
  for (float& v : map) v = empty || rng() % 5 == 0 ? INFINITY : rng() % 29 == 0 ? NAN : depth(rng);
  return map;
}

}  // namespace penumbra::test
