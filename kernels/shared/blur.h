// Tiling constants of the separable blur (kernels/blur.cl), shared with its host wrapper, which sizes
// the ND-ranges and __local arguments from them. Two layouts of the direct plan: tiles (GPUs) and runs (CPUs).
#ifndef PENUMBRA_KERNELS_SHARED_BLUR_H
#define PENUMBRA_KERNELS_SHARED_BLUR_H

#include "kernels/shared/common.h"

#define BLUR_ROW_TILE 64              // outputs per work-group row in blur_rows (work-group x size)
#define BLUR_ROWS 4                   // work-group y size of blur_columns, and of blur_rows where local memory allows
#define BLUR_COLUMN_TILE 32           // columns per work-group in blur_columns (work-group x size)
#define BLUR_MAX_DIRECT_RADIUS 32     // Auto: larger footprints use running sums (cost independent of radius)
#define BLUR_DIRECT_RADIUS_LIMIT 128  // direct taps beyond this are refused (local memory, 2r+1 weights)
#define BLUR_SEGMENT 128              // texels per work-item in the running-sum kernels (at least 2r+1)

// Runs layout of the direct plan (CPUs, *_runs kernels): a work-item sums whole runs of BLUR_RUN_FLOATS
// consecutive floats (16 texels of 1 channel, 8 of 2, 4 of 4) as one float16, one tap at a time.
#define BLUR_RUN_FLOATS 16        // floats per run: one float16, an AVX-512 register
#define BLUR_RUNS_SEGMENT 512     // texels of one row per blur_rows_runs item (a multiple of 16 * BLUR_RUNS_UNROLL)
#define BLUR_RUNS_UNROLL 4        // runs summed side by side by a blur_rows_runs item
#define BLUR_RUNS_ROWS 4          // rows per blur_rows_runs work-group (y size, one line each) where local memory allows
#define BLUR_RUNS_COLUMN_ROWS 4   // output rows summed side by side by a blur_columns_runs item
#define BLUR_RUNS_COLUMN_STRIP 128  // output rows per blur_columns_runs work-item (a multiple of the above)
#define BLUR_RUNS_COLUMN_BLOCK 512  // floats of each row per blur_columns_runs work-item (a multiple of runs)
// Running-sum plans on the runs layout take each box of at most this radius as direct taps of equal weight: on
// PoCL a direct pass costs ~0.17 ms a tap at 2048^2 float2 against ~12 ms for a running-sum pass (a serial chain
// per line), so direct boxes win up to ~70 taps; 24 keeps a margin.
#define BLUR_RUNS_MAX_BOX_RADIUS 24

#endif
