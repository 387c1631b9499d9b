// Tiling constants of the separable blur (kernels/blur.cl), shared with its host wrapper, which sizes
// the ND-ranges and __local arguments from them.
#ifndef PENUMBRA_KERNELS_SHARED_BLUR_H
#define PENUMBRA_KERNELS_SHARED_BLUR_H

#include "kernels/shared/common.h"

#define BLUR_ROW_TILE 64              // outputs per work-group row in blur_rows (work-group x size)
#define BLUR_ROWS 4                   // rows per work-group (work-group y size) in blur_rows and blur_columns
#define BLUR_COLUMN_TILE 32           // columns per work-group in blur_columns (work-group x size)
#define BLUR_MAX_DIRECT_RADIUS 32     // Auto: larger footprints use running sums (cost independent of radius)
#define BLUR_DIRECT_RADIUS_LIMIT 128  // direct taps beyond this are refused (local memory, 2r+1 weights)
#define BLUR_SEGMENT 128              // texels per work-item in the running-sum kernels (at least 2r+1)

#endif
