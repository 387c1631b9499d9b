// Separable blur with clamp-to-edge: a direct weighted sum staged through local memory (Gaussian or box
// weights, radius <= BLUR_DIRECT_RADIUS_LIMIT) and box running sums whose cost per texel does not depend
// on the radius (a Gaussian of large sigma is three of them; Wells 1986). Built per channel count:
// -DBLUR_CHANNELS=1|2|4 selects float, float2 or float4 texels; with -DSTORE_HALF the direct column pass (the
// last one) stores half texels (kernels/shared/storage.h), every other pass stays fp32.
#include "kernels/shared/blur.h"
#include "kernels/shared/storage.h"

#ifndef BLUR_CHANNELS
#define BLUR_CHANNELS 1
#endif
#define BLUR_T PN_VEC(float, BLUR_CHANNELS)
typedef PN_STORED(BLUR_CHANNELS) BlurStored;  // the column pass's output texel (BLUR_T, or half)

// One work-group: BLUR_ROWS rows of BLUR_ROW_TILE outputs; each row stages BLUR_ROW_TILE + 2r texels.
// Rows past the image are clamped (not skipped) so that every work-item reaches the barrier.
inline int blur_rows_row(uint height) { return min((int)get_global_id(1), (int)height - 1); }

// The weighted sum of a staged row (after the barrier).
inline void blur_rows_output(__local const BLUR_T* lines, __global BLUR_T* out, uint width, uint height, int radius,
                             __constant float* weights) {
  const int lx = get_local_id(0), x = get_group_id(0) * BLUR_ROW_TILE + lx;
  if (x >= (int)width || get_global_id(1) >= height) return;
  __local const BLUR_T* line = lines + get_local_id(1) * (BLUR_ROW_TILE + 2 * radius);
  BLUR_T sum = 0.0f;
  for (int k = 0; k <= 2 * radius; ++k) sum += weights[k] * line[lx + k];
  out[(size_t)blur_rows_row(height) * width + x] = sum;
}

__kernel __attribute__((reqd_work_group_size(BLUR_ROW_TILE, BLUR_ROWS, 1))) void blur_rows(
    __global const BLUR_T* in, __global BLUR_T* out, uint width, uint height, int radius, __constant float* weights,
    __local BLUR_T* lines) {
  const int x0 = get_group_id(0) * BLUR_ROW_TILE - radius, span = BLUR_ROW_TILE + 2 * radius;
  __local BLUR_T* line = lines + get_local_id(1) * span;
  __global const BLUR_T* src = in + (size_t)blur_rows_row(height) * width;
  for (int i = get_local_id(0); i < span; i += BLUR_ROW_TILE) line[i] = src[clamp(x0 + i, 0, (int)width - 1)];
  barrier(CLK_LOCAL_MEM_FENCE);
  blur_rows_output(lines, out, width, height, radius, weights);
}

#ifdef BLUR_MOMENTS
#include "kernels/shared/moments.h"
// The moments stage fused into the row pass (-DBLUR_MOMENTS=MOMENTS_KIND_*): stages the moments of the depth
// texels (moments_encode, as kernels/moments.cl writes them) instead of reading a moment image, so the moment
// image is never written nor read back; the result equals moments then blur_rows bit for bit.
__kernel __attribute__((reqd_work_group_size(BLUR_ROW_TILE, BLUR_ROWS, 1))) void blur_rows_moments(
    __global const float* depth, __global BLUR_T* out, uint width, uint height, int radius, __constant float* weights,
    __local BLUR_T* lines, MomentsParams p) {
  const int x0 = get_group_id(0) * BLUR_ROW_TILE - radius, span = BLUR_ROW_TILE + 2 * radius;
  __local BLUR_T* line = lines + get_local_id(1) * span;
  __global const float* src = depth + (size_t)blur_rows_row(height) * width;
  for (int i = get_local_id(0); i < span; i += BLUR_ROW_TILE) {
    const float4 m = moments_encode(src[clamp(x0 + i, 0, (int)width - 1)], p, BLUR_MOMENTS);
#if BLUR_CHANNELS == 4
    line[i] = m;
#else
    line[i] = m.xy;
#endif
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  blur_rows_output(lines, out, width, height, radius, weights);
}
#endif

// One work-group: BLUR_COLUMN_TILE columns of `tileRows` outputs, staged as (tileRows + 2r) rows.
__kernel __attribute__((reqd_work_group_size(BLUR_COLUMN_TILE, BLUR_ROWS, 1))) void blur_columns(
    __global const BLUR_T* in, __global BlurStored* out, uint width, uint height, int radius, __constant float* weights,
    int tileRows, __local BLUR_T* block) {
  const int lx = get_local_id(0), ly = get_local_id(1);
  const int x = get_group_id(0) * BLUR_COLUMN_TILE + lx, y0 = get_group_id(1) * tileRows;
  const int xc = min(x, (int)width - 1), span = tileRows + 2 * radius;
  for (int i = ly; i < span; i += BLUR_ROWS)
    block[i * BLUR_COLUMN_TILE + lx] = in[(size_t)clamp(y0 - radius + i, 0, (int)height - 1) * width + xc];
  barrier(CLK_LOCAL_MEM_FENCE);
  if (x >= (int)width) return;
  for (int r = ly; r < tileRows && y0 + r < (int)height; r += BLUR_ROWS) {
    BLUR_T sum = 0.0f;
    for (int k = 0; k <= 2 * radius; ++k) sum += weights[k] * block[(r + k) * BLUR_COLUMN_TILE + lx];
    PN_STORE(BLUR_CHANNELS, out, (size_t)(y0 + r) * width + x, sum);
  }
}

// Sum of src[clamp(c + k)] for k in [-r, r] over a line of n texels with stride `stride`: clamped taps
// are counted, not fetched, so the cost is at most min(2r + 1, n) reads.
inline BLUR_T blur_window_sum(__global const BLUR_T* src, int n, size_t stride, int c, int r) {
  const int lo = c - r, hi = c + r;
  BLUR_T sum = (float)max(0, -lo) * src[0] + (float)max(0, hi - (n - 1)) * src[(size_t)(n - 1) * stride];
  for (int i = max(lo, 0); i <= min(hi, n - 1); ++i) sum += src[(size_t)i * stride];
  return sum;
}

// Box filter along a line by a running sum over `count` outputs starting at `begin`; restarting per
// segment bounds the fp32 drift of adding and subtracting.
inline void blur_box_line(__global const BLUR_T* src, __global BLUR_T* dst, int n, size_t stride, int radius, int begin,
                          int count) {
  const float norm = 1.0f / (float)(2 * radius + 1);
  BLUR_T sum = blur_window_sum(src, n, stride, begin, radius);
  for (int c = begin;;) {
    dst[(size_t)c * stride] = sum * norm;
    if (++c >= begin + count) break;
    sum += src[(size_t)min(c + radius, n - 1) * stride] - src[(size_t)max(c - radius - 1, 0) * stride];
  }
}

// Work-item (segment, row): box filter of row segments.
__kernel void blur_box_rows(__global const BLUR_T* in, __global BLUR_T* out, uint width, uint height, int radius,
                            int segment) {
  const int begin = get_global_id(0) * segment, y = get_global_id(1);
  if (y >= (int)height || begin >= (int)width) return;
  const size_t row = (size_t)y * width;
  blur_box_line(in + row, out + row, width, 1, radius, begin, min(segment, (int)width - begin));
}

// Work-item (column, segment): box filter of column segments (neighbouring work-items read neighbouring
// addresses).
__kernel void blur_box_columns(__global const BLUR_T* in, __global BLUR_T* out, uint width, uint height, int radius,
                               int segment) {
  const int x = get_global_id(0), begin = get_global_id(1) * segment;
  if (x >= (int)width || begin >= (int)height) return;
  blur_box_line(in + x, out + x, height, width, radius, begin, min(segment, (int)height - begin));
}
