// What the fitted virtual shadow map's kernels (kernels/fvsm.cl) and its host (host/techniques/fvsm.cpp) share.
// Valid as OpenCL C 1.2 and C++20.
#ifndef PENUMBRA_KERNELS_SHARED_FVSM_H
#define PENUMBRA_KERNELS_SHARED_FVSM_H

#include "kernels/shared/common.h"

#define FVSM_NO_LEAF 0xffffffffu  // a page-table entry no drawn tile covers
#define FVSM_MAX_LEVELS 10        // quadtree levels below the root at most (2^10 tiles a side)

// One batch of fvsm_visibility's lookups: the tiles [begin, begin + count) whose views the launch holds, the page
// table's cells per side, and the exact edges (kernels/shared/exact_edges.h): on (1) or off, whether the scene has
// alpha-tested casters, the scene's radius.
typedef struct FvsmBatch {
  uint begin, count;
  uint cells;
  uint exactEdges, alphaTested;
  float sceneRadius;
  uint triangleCount;
} FvsmBatch;

#if PENUMBRA_HOST
static_assert(sizeof(FvsmBatch) == 28, "FvsmBatch is shared with OpenCL C");
#endif

#endif
