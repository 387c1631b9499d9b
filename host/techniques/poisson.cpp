#include "host/techniques/poisson.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace penumbra {
namespace {

// PCG32 (O'Neill 2014, XSH-RR output): portable, unlike the distributions of <random>.
class Pcg32 {
 public:
  explicit Pcg32(uint64_t seed) : state_(seed + kIncrement) { next(); }
  uint32_t next() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + kIncrement;
    const auto xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }
  float uniform() { return static_cast<float>(next() >> 8) * 0x1p-24f; }  // [0, 1)

 private:
  static constexpr uint64_t kIncrement = 1442695040888963407ull;
  uint64_t state_;
};

}  // namespace

std::vector<cl_float2> poissonDisk(int count, uint64_t seed, int candidates) {
  if (count < 1 || candidates < 1)
    throw std::invalid_argument(fmt::format("poissonDisk: count {} and candidates {} must be >= 1", count, candidates));
  Pcg32 rng(seed);
  auto sample = [&] {  // uniform in the unit disk: sqrt for the radius
    const float r = std::sqrt(rng.uniform()), a = 2.0f * std::numbers::pi_v<float> * rng.uniform();
    return cl_float2{{r * std::cos(a), r * std::sin(a)}};
  };
  std::vector<cl_float2> points;
  points.reserve(static_cast<size_t>(count));
  points.push_back(sample());
  while (static_cast<int>(points.size()) < count) {
    cl_float2 best{};
    float bestDistance = -1.0f;
    for (int c = 0; c < candidates; ++c) {
      const cl_float2 q = sample();
      float nearest = std::numeric_limits<float>::max();
      for (const cl_float2& p : points)
        nearest = std::min(nearest, std::hypot(q.s[0] - p.s[0], q.s[1] - p.s[1]));
      if (nearest > bestDistance) bestDistance = nearest, best = q;
    }
    points.push_back(best);
  }
  std::stable_sort(points.begin(), points.end(), [](const cl_float2& a, const cl_float2& b) {
    return std::hypot(a.s[0], a.s[1]) < std::hypot(b.s[0], b.s[1]);
  });
  return points;
}

}  // namespace penumbra
