// Weighted per-cluster reductions without atomics: pass 1 gives every work-group a fixed chunk of
// samples, each work-item accumulates per cluster in registers, then a local-memory tree per cluster
// writes the group's partials; pass 2 (one work-group) reduces the partials the same way. The order of
// every addition depends only on the sample count, so results are bitwise reproducible.
#include "kernels/shared/reduce.h"

// Built per cluster count (-DREDUCE_CLUSTERS=k): the per-work-item accumulators are an array of exactly k,
// indexed by an unrolled select so that they stay in registers; a count fixed at REDUCE_MAX_CLUSTERS would make
// every sample update 16 accumulators whatever k is.
#ifndef REDUCE_CLUSTERS
#define REDUCE_CLUSTERS REDUCE_MAX_CLUSTERS
#endif

// Cluster of x: the number of (sorted) boundaries <= x.
inline uint reduce_cluster(float x, __global const float* boundaries, uint clusters) {
  uint k = 0;
  for (uint b = 0; b + 1 < clusters; ++b) k += x >= boundaries[b];
  return k;
}

// Tree-reduces (sum, samples) over the work-group; the result is valid in work-item 0. Ends with a barrier
// so the scratch can be reused.
inline void reduce_group(float4* sum, uint* samples, __local float4* sums, __local uint* counts) {
  const uint lid = get_local_id(0);
  sums[lid] = *sum;
  counts[lid] = *samples;
  for (uint active = REDUCE_GROUP / 2; active > 0; active /= 2) {
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid < active) sums[lid] += sums[lid + active], counts[lid] += counts[lid + active];
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  *sum = sums[0];
  *samples = counts[0];
  barrier(CLK_LOCAL_MEM_FENCE);
}

__kernel __attribute__((reqd_work_group_size(REDUCE_GROUP, 1, 1))) void reduce_lloyd_partial(
    __global const float* x, __global const float* w, __global const float* boundaries, ReduceParams p,
    __global LloydStats* partials) {
  __local float4 sums[REDUCE_GROUP];
  __local uint counts[REDUCE_GROUP];
  float4 acc[REDUCE_CLUSTERS];
  uint n[REDUCE_CLUSTERS];
  for (uint k = 0; k < REDUCE_CLUSTERS; ++k) acc[k] = 0.0f, n[k] = 0;
  const uint begin = get_group_id(0) * p.chunk, end = min(begin + p.chunk, p.count);
  for (uint i = begin + get_local_id(0); i < end; i += REDUCE_GROUP) {
    const float xi = x[i], wi = w[i];
    if (!(isfinite(xi) && isfinite(wi) && wi > 0.0f)) continue;
    const uint c = reduce_cluster(xi, boundaries, p.clusters);
    for (uint k = 0; k < REDUCE_CLUSTERS; ++k)  // unrolled select keeps acc in registers
      if (k == c) acc[k] += (float4)(wi, wi * xi, wi * xi * xi, 0.0f), n[k] += 1;
  }
  for (uint k = 0; k < REDUCE_CLUSTERS; ++k) {
    float4 s = acc[k];
    uint samples = n[k];
    reduce_group(&s, &samples, sums, counts);
    if (get_local_id(0) == 0)
      partials[get_group_id(0) * p.clusters + k] = (LloydStats){s.x, s.y, s.z, samples};
  }
}

// One work-group: sums the partials of every first-pass work-group per cluster.
__kernel __attribute__((reqd_work_group_size(REDUCE_GROUP, 1, 1))) void reduce_lloyd_final(
    __global const LloydStats* partials, ReduceParams p, __global LloydStats* out) {
  __local float4 sums[REDUCE_GROUP];
  __local uint counts[REDUCE_GROUP];
  for (uint k = 0; k < p.clusters; ++k) {
    float4 s = 0.0f;
    uint samples = 0;
    for (uint g = get_local_id(0); g < p.groups; g += REDUCE_GROUP) {
      const LloydStats q = partials[g * p.clusters + k];
      s += (float4)(q.sumW, q.sumWX, q.sumWX2, 0.0f);
      samples += q.samples;
    }
    reduce_group(&s, &samples, sums, counts);
    if (get_local_id(0) == 0) out[k] = (LloydStats){s.x, s.y, s.z, samples};
  }
}
