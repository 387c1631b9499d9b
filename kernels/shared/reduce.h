// Weighted per-cluster reductions for Lloyd relaxation (LVSM layer placement, Lauritzen & McCool 2008,
// sec. 4): per cluster sum w, sum w x, sum w x^2 and the sample count, shared by kernels/reduce.cl and
// its host wrapper.
#ifndef PENUMBRA_KERNELS_SHARED_REDUCE_H
#define PENUMBRA_KERNELS_SHARED_REDUCE_H

#include "kernels/shared/common.h"

#define REDUCE_GROUP 256        // work-items per work-group (both passes)
#define REDUCE_MAX_CLUSTERS 16  // clusters per reduction (registers per work-item scale with it)
#define REDUCE_MAX_GROUPS 256   // first-pass work-groups at most (the second pass reads them all)

typedef struct LloydStats {
  float sumW;    // sum of weights of the cluster's samples
  float sumWX;   // sum of w * x
  float sumWX2;  // sum of w * x^2
  uint samples;  // samples counted (finite x, finite w > 0)
} LloydStats;

typedef struct ReduceParams {
  uint count;     // samples
  uint clusters;  // 1..REDUCE_MAX_CLUSTERS; cluster of x = number of boundaries <= x
  uint chunk;     // samples per first-pass work-group
  uint groups;    // first-pass work-groups
} ReduceParams;

#if PENUMBRA_HOST
static_assert(sizeof(LloydStats) == 16 && offsetof(LloydStats, samples) == 12);
static_assert(sizeof(ReduceParams) == 16, "ReduceParams layout is shared with OpenCL C");
#endif

#endif
