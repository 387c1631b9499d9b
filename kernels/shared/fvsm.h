// What the fitted virtual shadow map's kernels (kernels/fvsm.cl) and its host (host/techniques/fvsm.cpp) share.
// Valid as OpenCL C 1.2 and C++20.
#ifndef PENUMBRA_KERNELS_SHARED_FVSM_H
#define PENUMBRA_KERNELS_SHARED_FVSM_H

#include "kernels/shared/common.h"

#define FVSM_NO_LEAF 0xffffffffu  // a page-table entry no drawn tile covers
#define FVSM_MAX_LEVELS 10        // quadtree levels below the root at most (2^10 tiles a side)

#endif
