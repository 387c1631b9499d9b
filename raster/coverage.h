// Coverage tests shared by the bin, coarse and fine kernels (OpenCL C only): exact 64-bit edge functions on
// snapped subpixel coordinates with the top-left fill rule, and the conservative "can this triangle cover any
// sample of a pixel rectangle" test (the maximum of a linear edge function over a rectangle of samples is at
// one of its corners, so one evaluation per edge decides it exactly).
#ifndef PENUMBRA_RASTER_COVERAGE_H
#define PENUMBRA_RASTER_COVERAGE_H

#include "raster/constants.h"
#include "raster/types.h"

// Subpixel coordinate of the centre of pixel column/row `pixel` (< 2^21 for pixels < 8192).
static inline int rasterSample(int pixel) { return (pixel << RASTER_SUBPIXEL_LOG2) + RASTER_SAMPLE_OFFSET; }

// e_k at a sample (x, y) from edge k's coefficients a, b and its first vertex (vx, vy) (raster/types.h): the
// differences are below 2^30, |a|, |b| <= 2^30, so each product is below 2^60 and the sum exact. 32 x 32 -> 64-bit
// products (one wide multiply on GPUs).
static inline long rasterEdgeAt(int a, int b, int vx, int vy, int x, int y) {
  return (long)a * (long)(x - vx) + (long)b * (long)(y - vy);
}

// Edge k's coefficients a_k, b_k and first vertex of a record `t` in any address space (raster/types.h).
#define RASTER_EDGE_NEXT(k) ((k) == 2 ? 0 : (k) + 1)
#define RASTER_EDGE_A(t, k) ((t).y[k] - (t).y[RASTER_EDGE_NEXT(k)])
#define RASTER_EDGE_B(t, k) ((t).x[RASTER_EDGE_NEXT(k)] - (t).x[k])

// Whether an edge accepts samples with edge value e: inside, or on the edge when it owns its samples (owns: 1 or 0;
// for OpenCL vectors e and owns are vectors or scalars of -1 or 0, the result a mask of -1 or 0). Bitwise operators,
// so that the same expression serves the scalar kernels and the fine stage's vectorized rows.
#define RASTER_EDGE_PASSES(e, owns) (((e) > 0) | (((e) == 0) & (owns)))

// Whether edge k accepts a sample with edge value e.
static inline bool rasterEdgeAccepts(long e, uint flags, int k) {
  return RASTER_EDGE_PASSES(e, (flags & (RASTER_FLAG_OWNS_EDGE0 << k)) != 0);
}

// Whether some sample of pixels [x0, x1] x [y0, y1] (inclusive, non-empty) passes edge k.
static inline bool rasterEdgeReaches(int a, int b, int vx, int vy, uint flags, int k, int x0, int y0, int x1, int y1) {
  int x = rasterSample(a > 0 ? x1 : x0), y = rasterSample(b > 0 ? y1 : y0);
  return rasterEdgeAccepts(rasterEdgeAt(a, b, vx, vy, x, y), flags, k);
}

// Conservative draws: whether some point of the area of pixels [x0, x1] x [y0, y1], dilated by
// RASTER_CONSERVATIVE_DILATION subpixels, passes edge k inclusively (the edge's maximum over the dilated rectangle is
// at one of its corners).
static inline bool rasterEdgeTouches(int a, int b, int vx, int vy, int x0, int y0, int x1, int y1) {
  int x = a > 0 ? ((x1 + 1) << RASTER_SUBPIXEL_LOG2) + RASTER_CONSERVATIVE_DILATION
                : (x0 << RASTER_SUBPIXEL_LOG2) - RASTER_CONSERVATIVE_DILATION;
  int y = b > 0 ? ((y1 + 1) << RASTER_SUBPIXEL_LOG2) + RASTER_CONSERVATIVE_DILATION
                : (y0 << RASTER_SUBPIXEL_LOG2) - RASTER_CONSERVATIVE_DILATION;
  return rasterEdgeAt(a, b, vx, vy, x, y) >= 0;
}

// The rectangle test for a triangle record in any address space: the rectangle is first cut to the triangle's
// candidate box; every edge must reach the rest: some pixel centre of it, or (conservative draws, `conservative`
// nonzero) some point of its dilated area. Not exact (the three half-planes may each reach a different point), only
// conservative, which is all binning needs.
#define RASTER_RECT_OVERLAPS(t, conservative, rx0, ry0, rx1, ry1, result)                                       \
  do {                                                                                                          \
    int ox0_ = max((int)(t).bbox[0], (rx0)), oy0_ = max((int)(t).bbox[1], (ry0));                               \
    int ox1_ = min((int)(t).bbox[2], (rx1)), oy1_ = min((int)(t).bbox[3], (ry1));                               \
    (result) = ox0_ <= ox1_ && oy0_ <= oy1_;                                                                    \
    for (int k_ = 0; k_ < 3 && (result); ++k_)                                                                  \
      (result) = (conservative) ? rasterEdgeTouches(RASTER_EDGE_A(t, k_), RASTER_EDGE_B(t, k_), (t).x[k_],      \
                                                    (t).y[k_], ox0_, oy0_, ox1_, oy1_)                          \
                                : rasterEdgeReaches(RASTER_EDGE_A(t, k_), RASTER_EDGE_B(t, k_), (t).x[k_],      \
                                                    (t).y[k_], (t).flags, k_, ox0_, oy0_, ox1_, oy1_);          \
  } while (0)

#endif
