#include "tools/selftest/reference/inputs.h"

#include <Imath/half.h>

#include <cmath>
#include <limits>
#include <random>

namespace penumbra::ref {

std::vector<float> fromHalf(const std::vector<cl_half>& bits) {
  std::vector<float> out;
  out.reserve(bits.size());
  for (cl_half b : bits) {
    Imath::half h;
    h.setBits(b);
    out.push_back(float(h));
  }
  return out;
}

std::vector<float> randomUnitImage(size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> image(count);
  for (float& v : image) v = unit(rng);
  return image;
}

std::vector<float> randomDepthMap(uint32_t width, uint32_t height, uint32_t seed, bool empty) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> depth(1.0f, 50.0f);
  std::vector<float> map(size_t(width) * height);
  for (float& v : map) v = empty || rng() % 5 == 0 ? INFINITY : rng() % 29 == 0 ? NAN : depth(rng);
  return map;
}

std::vector<float> momentsDepth(size_t count, uint32_t seed, float depthNear, float depthFar) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> depth(depthNear - 1.0f, depthFar + 1.0f);
  std::vector<float> out(count);
  for (float& v : out) {
    switch (rng() % 16) {
      case 0:
        v = std::numeric_limits<float>::infinity();
        break;
      case 1:
        v = std::numeric_limits<float>::quiet_NaN();
        break;
      case 2:
        v = -std::numeric_limits<float>::infinity();
        break;
      case 3:
        v = (rng() % 2 ? 1.0f : -1.0f) * 3e38f;
        break;
      default:
        v = depth(rng);
    }
  }
  return out;
}

std::vector<float> depthWithHoles(uint32_t width, uint32_t height, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(1.5f, 9.5f);
  std::vector<float> depth(size_t(width) * height);
  for (size_t i = 0; i < depth.size(); ++i) depth[i] = i % 11 == 3 ? INFINITY : i % 17 == 5 ? std::nanf("") : dist(rng);
  return depth;
}

std::vector<float> satImage(const ImageShape& shape, SatInput kind, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> out(shape.count());
  for (float& v : out) {
    v = unit(rng);
    if (kind == SatInput::Constant) v = 0.75f;
    if (kind == SatInput::HugeRange) v = (v - 0.5f) * (rng() % 4 == 0 ? 1e30f : 1.0f);
    if (kind == SatInput::NonFinite && rng() % 97 == 0) v = rng() % 2 ? NAN : (rng() % 2 ? INFINITY : -INFINITY);
  }
  return out;
}

std::vector<double> blurImage(const ImageShape& shape, BlurInput kind, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> out(shape.count());
  for (double& v : out) {
    if (kind == BlurInput::Constant)
      v = 0.625;
    else if (kind == BlurInput::HugeRange)
      v = std::pow(10.0, 20.0 + 10.0 * unit(rng));
    else
      v = float(unit(rng));  // exactly representable in fp32
  }
  return out;
}

LloydInputs lloydInputs(uint32_t count, uint32_t clusters) {
  std::mt19937 rng(count * 7 + clusters);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  LloydInputs in;
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t r = rng() % 50;
    in.x.push_back(r == 0 ? NAN : r == 1 ? INFINITY : unit(rng));
    in.w.push_back(r == 2 ? 0.0f : r == 3 ? -1.0f : r == 4 ? NAN : unit(rng) * 4.0f);
  }
  for (uint32_t k = 1; k < clusters; ++k) in.boundaries.push_back(float(k) / clusters);
  return in;
}

}  // namespace penumbra::ref
