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

// The points placed so far, bucketed in a uniform grid over [-1, 1]^2 so that a candidate's nearest neighbour is
// found among the cells around it (rings outwards until no farther cell can hold a nearer point) instead of among
// every point: 4,096 points (pcss's 64^2 taps) take milliseconds instead of seconds. The nearest distance found is
// the exhaustive search's exactly (the same hypot of the same pair), so the patterns do not depend on the grid.
class PointGrid {
 public:
  explicit PointGrid(int count)
      : side_(std::max(1, static_cast<int>(std::ceil(std::sqrt(count))))), cells_(side_ * side_) {}

  void add(const cl_float2& p) { cells_[index(cell(p.s[0]), cell(p.s[1]))].push_back(p); }

  float nearest(const cl_float2& q) const {
    const int cx = cell(q.s[0]), cy = cell(q.s[1]);
    const float size = 2.0f / static_cast<float>(side_);
    float best = std::numeric_limits<float>::max();
    for (int ring = 0; ring < side_; ++ring) {
      // A cell `ring` cells away is at least ring - 1 whole cells from q (q may lie at its own cell's edge).
      if (best < static_cast<float>(ring - 1) * size * (1.0f - 1e-5f)) break;
      for (int y = cy - ring; y <= cy + ring; ++y)
        for (int x = cx - ring; x <= cx + ring; ++x) {
          if (std::max(std::abs(x - cx), std::abs(y - cy)) != ring || x < 0 || y < 0 || x >= side_ || y >= side_)
            continue;
          for (const cl_float2& p : cells_[index(x, y)])
            best = std::min(best, std::hypot(q.s[0] - p.s[0], q.s[1] - p.s[1]));
        }
    }
    return best;
  }

 private:
  int cell(float v) const {
    return std::clamp(static_cast<int>((v + 1.0f) * 0.5f * static_cast<float>(side_)), 0, side_ - 1);
  }
  size_t index(int x, int y) const { return static_cast<size_t>(y) * side_ + x; }

  int side_;
  std::vector<std::vector<cl_float2>> cells_;
};

// Mitchell's best candidates in the order they are placed.
std::vector<cl_float2> bestCandidates(int count, uint64_t seed, int candidates, NeighbourSearch search) {
  if (count < 1 || candidates < 1)
    throw std::invalid_argument(fmt::format("poissonDisk: count {} and candidates {} must be >= 1", count, candidates));
  Pcg32 rng(seed);
  auto sample = [&] {  // uniform in the unit disk: sqrt for the radius
    const float r = std::sqrt(rng.uniform()), a = 2.0f * std::numbers::pi_v<float> * rng.uniform();
    return cl_float2{{r * std::cos(a), r * std::sin(a)}};
  };
  std::vector<cl_float2> points;
  points.reserve(static_cast<size_t>(count));
  PointGrid grid(count);
  points.push_back(sample());
  grid.add(points.back());
  while (static_cast<int>(points.size()) < count) {
    cl_float2 best{};
    float bestDistance = -1.0f;
    for (int c = 0; c < candidates; ++c) {
      const cl_float2 q = sample();
      float nearest = std::numeric_limits<float>::max();
      if (search == NeighbourSearch::Grid) {
        nearest = grid.nearest(q);
      } else {
        for (const cl_float2& p : points) nearest = std::min(nearest, std::hypot(q.s[0] - p.s[0], q.s[1] - p.s[1]));
      }
      if (nearest > bestDistance) bestDistance = nearest, best = q;
    }
    points.push_back(best);
    grid.add(best);
  }
  return points;
}

}  // namespace

std::vector<cl_float2> poissonDisk(int count, uint64_t seed, int candidates, NeighbourSearch search) {
  std::vector<cl_float2> points = bestCandidates(count, seed, candidates, search);
  std::stable_sort(points.begin(), points.end(), [](const cl_float2& a, const cl_float2& b) {
    return std::hypot(a.s[0], a.s[1]) < std::hypot(b.s[0], b.s[1]);
  });
  return points;
}

std::vector<cl_float2> progressivePoissonDisk(int count, uint64_t seed) {
  return bestCandidates(count, seed, kPoissonCandidates, NeighbourSearch::Grid);
}

}  // namespace penumbra
