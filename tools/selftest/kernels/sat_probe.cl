// Probe of the SAT box lookups (kernels/shared/sat.h) for tests/sat_test.cpp and tools/bench/sat_precision.cpp. Built
// with the table's -DSAT_MODE=... -DSAT_CHANNELS=... (satBuildOptions).
#include "kernels/shared/sat.h"

// Box sums and means of `boxes` (lo.x, lo.y, hi.x, hi.y) through the shared lookup.
__kernel void sat_test_box(__global const SAT_T* sat, SatTableDesc t, __global const float* offsetBuffer,
                           __global const float4* boxes, uint count, __global SAT_F* sums, __global SAT_F* means) {
  const uint i = get_global_id(0);
  if (i >= count) return;
  const float4 b = boxes[i];
  sums[i] = sat_box_sum(sat, t, offsetBuffer, b.xy, b.zw);
  means[i] = sat_box_mean(sat, t, offsetBuffer, b.xy, b.zw);
}
