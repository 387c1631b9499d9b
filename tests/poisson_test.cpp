// Poisson-disk tap patterns (host/techniques/poisson.h): inside the unit disk, well spread, deterministic.
#include "host/techniques/poisson.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace penumbra {
namespace poisson_test {

TEST(Poisson, PointsLieInTheDiskWellSpreadAndDeterministic) {
  for (int count : {1, 2, 7, 16, 32, 64}) {
    const std::vector<cl_float2> disk = poissonDisk(count);
    ASSERT_EQ(disk.size(), static_cast<size_t>(count));
    float nearest = INFINITY;
    for (size_t i = 0; i < disk.size(); ++i) {
      EXPECT_LE(std::hypot(disk[i].s[0], disk[i].s[1]), 1.0f);
      for (size_t j = 0; j < i; ++j) {
        nearest = std::min(nearest, std::hypot(disk[i].s[0] - disk[j].s[0], disk[i].s[1] - disk[j].s[1]));
      }
    }
    // Best-candidate sampling keeps points at least ~0.6 of the hexagonal-packing spacing apart
    // (sqrt(2 pi / (sqrt(3) N)) for N points in a disk of area pi); uniform random points would not.
    if (count > 1) {
      EXPECT_GT(nearest, 0.6f * std::sqrt(2.0f * 3.14159f / (std::sqrt(3.0f) * count))) << count;
    }
    const std::vector<cl_float2> again = poissonDisk(count);
    for (size_t i = 0; i < disk.size(); ++i) {
      EXPECT_EQ(disk[i].s[0], again[i].s[0]);
      EXPECT_EQ(disk[i].s[1], again[i].s[1]);
    }
  }
  EXPECT_THROW(poissonDisk(0), std::invalid_argument);
}

// The grid's nearest-neighbour search changes nothing: the exhaustive search's patterns bit for bit, at counts pcf
// and pcss use and odd ones between (up to 32^2: the exhaustive search of 64^2 alone takes seconds).
TEST(Poisson, GridSearchGivesTheExhaustiveSearchsPatterns) {
  for (int count : {1, 2, 3, 17, 64, 100, 257, 1024}) {
    for (uint64_t seed : {1u, 2u, 99u}) {
      const std::vector<cl_float2> grid = poissonDisk(count, seed);
      const std::vector<cl_float2> exhaustive = poissonDisk(count, seed, 64, NeighbourSearch::Exhaustive);
      ASSERT_EQ(grid.size(), exhaustive.size());
      for (size_t i = 0; i < grid.size(); ++i) {
        ASSERT_EQ(grid[i].s[0], exhaustive[i].s[0]) << count << " points, seed " << seed << ", point " << i;
        ASSERT_EQ(grid[i].s[1], exhaustive[i].s[1]) << count << " points, seed " << seed << ", point " << i;
      }
    }
  }
}

// The progressive pattern is the same points in the order they were placed: each prefix of 144 points (pcss's auto
// filter at its most) is the pattern of that many, so a pixel that takes the first k taps gets a spread-out set.
TEST(Poisson, EveryPrefixOfTheProgressivePatternIsThePatternOfItsSize) {
  const std::vector<cl_float2> all = progressivePoissonDisk(144, 1);
  ASSERT_EQ(all.size(), 144u);
  for (int count : {1, 9, 16, 36, 64, 100, 144}) {
    std::vector<cl_float2> prefix(all.begin(), all.begin() + count);
    std::stable_sort(prefix.begin(), prefix.end(), [](const cl_float2& a, const cl_float2& b) {
      return std::hypot(a.s[0], a.s[1]) < std::hypot(b.s[0], b.s[1]);
    });
    const std::vector<cl_float2> sorted = poissonDisk(count, 1);
    for (int i = 0; i < count; ++i) {
      ASSERT_EQ(prefix[i].s[0], sorted[i].s[0]) << count << " points, point " << i;
      ASSERT_EQ(prefix[i].s[1], sorted[i].s[1]) << count << " points, point " << i;
    }
  }
}

}  // namespace poisson_test
}  // namespace penumbra
