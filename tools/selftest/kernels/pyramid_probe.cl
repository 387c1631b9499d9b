// Probes of kernels/shared/pyramid.h for tests/pyramid_test.cpp: a levels-only min-max pyramid's lookups over a disk
// and over its square.
#include "kernels/shared/pyramid.h"

// For each disk (centre x, y, radius): out[2i] pyramid_far_in_disk, out[2i + 1] the farthest depth of
// pyramid_depth_range_of over the disk's square, both with `outside` beyond the map.
__kernel void pyramid_disk_test(__global const float* map, __global const float2* pyramid,
                                __constant const PyramidLevel* levels, uint levelCount, uint width, uint height,
                                __global const float4* disks, uint count, float outside, __global float* out) {
  const uint i = get_global_id(0);
  if (i >= count) return;
  const float2 centre = disks[i].xy;
  const float radius = disks[i].z;
  out[2 * i] = pyramid_far_in_disk(map, pyramid, levels, levelCount, width, height, centre, radius, outside);
  out[2 * i + 1] =
      pyramid_depth_range_of(map, pyramid, levels, levelCount, width, height, centre - radius, centre + radius, outside)
          .y;
}
