// Poisson-disk tap patterns (host/techniques/poisson.h): inside the unit disk, well spread, deterministic.
#include "host/techniques/poisson.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace penumbra {
namespace {

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

}  // namespace
}  // namespace penumbra
