// Separable blur with clamp-to-edge: a direct weighted sum (Gaussian or box weights, radius <=
// BLUR_DIRECT_RADIUS_LIMIT) in two layouts, tiles staged through local memory (GPUs) and float16 runs (CPUs),
// and box running sums whose cost per texel does not depend on the radius (a Gaussian of large sigma is three
// of them; Wells 1986). Built per channel count: -DBLUR_CHANNELS=1|2|4 selects float, float2 or float4 texels;
// with -DSTORE_HALF the direct column pass (the last one) stores half texels (kernels/shared/storage.h).
#include "kernels/shared/blur.h"
#include "kernels/shared/moments.h"  // the fused moments encodings and ESM's log-space taps
#include "kernels/shared/storage.h"

#ifndef BLUR_CHANNELS
#define BLUR_CHANNELS 1
#endif
#define BLUR_T PN_VEC(float, BLUR_CHANNELS)
#define BlurStored PN_STORED(BLUR_CHANNELS)  // the column pass's output texel (BLUR_T, or half)

// Lines staged per row-pass work-group: the kernels' defaults, or fewer where the host's local-memory plan
// (host/stages/blur_local.h) finds the device too small for them.
#ifndef BLUR_ROW_LINES
#define BLUR_ROW_LINES BLUR_ROWS
#endif
#ifndef BLUR_RUNS_LINES
#define BLUR_RUNS_LINES BLUR_RUNS_ROWS
#endif

// One work-group: BLUR_ROW_LINES rows of BLUR_ROW_TILE outputs; each row stages BLUR_ROW_TILE + 2r texels.
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

__kernel __attribute__((reqd_work_group_size(BLUR_ROW_TILE, BLUR_ROW_LINES, 1))) void blur_rows(
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
// The moments stage fused into the row pass (-DBLUR_MOMENTS=MOMENTS_KIND_*): stages the moments of the depth
// texels (moments_encode, as kernels/moments.cl writes them) instead of reading a moment image, so the moment
// image is never written nor read back; the result equals moments then blur_rows bit for bit.
__kernel __attribute__((reqd_work_group_size(BLUR_ROW_TILE, BLUR_ROW_LINES, 1))) void blur_rows_moments(
    __global const float* depth, __global BLUR_T* out, uint width, uint height, int radius, __constant float* weights,
    __local BLUR_T* lines, MomentsParams p) {
  const int x0 = get_group_id(0) * BLUR_ROW_TILE - radius, span = BLUR_ROW_TILE + 2 * radius;
  __local BLUR_T* line = lines + get_local_id(1) * span;
  __global const float* src = depth + (size_t)blur_rows_row(height) * width;
  for (int i = get_local_id(0); i < span; i += BLUR_ROW_TILE) {
    const float4 m = moments_encode(src[clamp(x0 + i, 0, (int)width - 1)], p, BLUR_MOMENTS);
#if BLUR_CHANNELS == 4
    line[i] = m;
#elif BLUR_CHANNELS == 1
    line[i] = m.x;
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

// blur_columns where even a tile of one output row does not fit the device's local memory (large radii, 4 channels,
// devices of 32 KiB or less): an item per output texel reads its taps straight from global memory (neighbouring
// items read neighbouring texels, so the reads still coalesce); the same sums in the same order as blur_columns.
__kernel void blur_columns_global(__global const BLUR_T* in, __global BlurStored* out, uint width, uint height,
                                  int radius, __constant float* weights) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= (int)width || y >= (int)height) return;
  BLUR_T sum = 0.0f;
  for (int k = 0; k <= 2 * radius; ++k)
    sum += weights[k] * in[(size_t)clamp(y - radius + k, 0, (int)height - 1) * width + x];
  PN_STORE(BLUR_CHANNELS, out, (size_t)y * width + x, sum);
}

// ---- Runs layout (CPUs) ----------------------------------------------------------------------------------------
// PoCL runs a work-group's items one after another and vectorises across them only where the body has no inner
// loop, so the tiles kernels (one item per texel, a loop over taps) run float2 arithmetic on 512-bit units and stay
// far above their bandwidth floor. Here the vector is explicit: an item sums runs of BLUR_RUN_FLOATS consecutive
// floats of one row as one float16, sum += w[k] * (the run shifted by k texels), so every tap is one vector
// multiply-add whatever the channel count. Each lane adds its taps in the order k = 0..2r with the same
// `sum += weights[k] * x` as the tiles kernels, and the fused and unfused row passes share the summing code (one
// body for taps in global or local memory), so their results agree bit for bit. No barrier anywhere: an item only
// reads back what it staged itself.
#define BLUR_RUN_TEXELS (BLUR_RUN_FLOATS / BLUR_CHANNELS)
#if BLUR_CHANNELS == 1
#define BLUR_VSTORE_T(v, i, p) ((p)[i] = (v))
#else
#define BLUR_VSTORE_T(v, i, p) PN_CAT(vstore, BLUR_CHANNELS)((v), (i), (p))
#endif

// The first n <= BLUR_RUN_FLOATS floats at p as a run (the rest 0): the last run of a row may be partial.
inline float16 blur_runs_load_part(__global const float* p, int n) {
  float lanes[BLUR_RUN_FLOATS] = {0.0f};
  for (int i = 0; i < n; ++i) lanes[i] = p[i];
  return vload16(0, lanes);
}

// Stores the first n <= BLUR_RUN_FLOATS floats of a run: fp32 (row pass), or the column pass's storage.
inline void blur_runs_store(float16 v, __global float* p, int n) {
  if (n == BLUR_RUN_FLOATS) {
    vstore16(v, 0, p);
    return;
  }
  float lanes[BLUR_RUN_FLOATS];
  vstore16(v, 0, lanes);
  for (int i = 0; i < n; ++i) p[i] = lanes[i];
}

inline void blur_runs_store_stored(float16 v, __global PN_SCALAR* p, int n) {
#ifdef STORE_HALF
  if (n == BLUR_RUN_FLOATS) {
    vstore_half16_rte(v, 0, p);
    return;
  }
  float lanes[BLUR_RUN_FLOATS];
  vstore16(v, 0, lanes);
  for (int i = 0; i < n; ++i) vstore_half_rte(lanes[i], i, p);
#else
  blur_runs_store(v, p, n);
#endif
}

// A blur_rows_runs item: segment (x0, count texels) of row y, and its line of local memory (texels x0 - r ...).
inline int blur_runs_x0(void) { return get_global_id(0) * BLUR_RUNS_SEGMENT; }
inline __local float* blur_runs_line(__local float* lines, int radius) {
  return lines + get_local_id(1) * (BLUR_RUNS_SEGMENT + 2 * radius) * BLUR_CHANNELS;
}
#define BLUR_RUNS_STEP (BLUR_RUNS_UNROLL * BLUR_RUN_TEXELS)  // texels one blur_runs_step_* call sums together
// Texels staged for `count` outputs: whole steps (the last may be partial) and the 2r halo.
inline int blur_runs_span(int count, int radius) {
  return (count + BLUR_RUNS_STEP - 1) / BLUR_RUNS_STEP * BLUR_RUNS_STEP + 2 * radius;
}

// The row pass's sums of BLUR_RUNS_UNROLL runs from `src` (texel x - r of the first output x, in global or local
// memory), of which the first `count` texels are stored. A multiply-add waits for the previous one on the same sum
// (4 cycles): runs side by side keep the vector unit busy and share each weight's broadcast, and each sum still adds
// its taps in order. The sums are stored here rather than returned through a pointer, which kept them in memory.
#define BLUR_RUNS_STEP_DEFINE(name, space)                                                                            \
  inline void name(space const float* src, int radius, __constant float* weights, __global float* out, int count) {   \
    float16 sum[BLUR_RUNS_UNROLL];                                                                                    \
    _Pragma("unroll") for (int j = 0; j < BLUR_RUNS_UNROLL; ++j) sum[j] = 0.0f;                                       \
    for (int k = 0; k <= 2 * radius; ++k) {                                                                           \
      const float w = weights[k];                                                                                     \
      _Pragma("unroll") for (int j = 0; j < BLUR_RUNS_UNROLL; ++j) sum[j] += w * vload16(j, src + k * BLUR_CHANNELS); \
    }                                                                                                                 \
    _Pragma("unroll") for (int j = 0; j < BLUR_RUNS_UNROLL; ++j) {                                                    \
      const int n = min(BLUR_RUN_TEXELS, count - j * BLUR_RUN_TEXELS) * BLUR_CHANNELS;                                \
      if (n > 0) blur_runs_store(sum[j], out + j * BLUR_RUN_FLOATS, n);                                               \
    }                                                                                                                 \
  }
BLUR_RUNS_STEP_DEFINE(blur_runs_step_global, __global)
BLUR_RUNS_STEP_DEFINE(blur_runs_step_local, __local)

// The row pass's sums over a staged line (texel i of `line` is texel x0 - r + i of the row, clamped).
inline void blur_runs_row_output(__local const float* line, __global float* out, int count, int radius,
                                 __constant float* weights) {
  for (int t = 0; t < count; t += BLUR_RUNS_STEP)
    blur_runs_step_local(line + t * BLUR_CHANNELS, radius, weights, out + t * BLUR_CHANNELS, count - t);
}

// Work-item (segment, row): BLUR_RUNS_SEGMENT outputs of one row. Steps whose window lies inside the row read their
// taps straight from global memory; the others stage the window clamped in the item's line first (staging every
// step cost as much as the sums at small radii).
__kernel __attribute__((reqd_work_group_size(1, BLUR_RUNS_LINES, 1))) void blur_rows_runs(
    __global const float* in, __global float* out, uint width, uint height, int radius, __constant float* weights,
    __local float* lines) {
  const int x0 = blur_runs_x0(), y = get_global_id(1), w = width;
  if (y >= (int)height || x0 >= w) return;
  const int count = min(BLUR_RUNS_SEGMENT, w - x0);
  __local float* line = blur_runs_line(lines, radius);
  __global const BLUR_T* row = (__global const BLUR_T*)in + (size_t)y * width;
  __global float* dst = out + ((size_t)y * width + x0) * BLUR_CHANNELS;
  for (int t = 0; t < count; t += BLUR_RUNS_STEP) {
    const int first = x0 + t - radius, span = BLUR_RUNS_STEP + 2 * radius;
    if (first >= 0 && first + span <= w) {
      blur_runs_step_global((__global const float*)(row + first), radius, weights, dst + t * BLUR_CHANNELS, count - t);
    } else {
      for (int i = 0; i < span; ++i) BLUR_VSTORE_T(row[clamp(first + i, 0, w - 1)], i, line);
      blur_runs_step_local(line, radius, weights, dst + t * BLUR_CHANNELS, count - t);
    }
  }
}

#ifdef BLUR_MOMENTS
// Texel i of a line: the moments of one depth texel.
inline void blur_runs_stage_moments(float depth, MomentsParams p, int i, __local float* line) {
  const float4 m = moments_encode(depth, p, BLUR_MOMENTS);
#if BLUR_CHANNELS == 4
  vstore4(m, i, line);
#elif BLUR_CHANNELS == 1
  line[i] = m.x;
#else
  vstore2(m.xy, i, line);
#endif
}

// blur_rows_runs reading depth: stages the moments of the segment's window of depth texels (moments_encode, as
// blur_rows_moments; each texel encoded once, not once per tap), then the same sums from local memory. The encoding
// stays scalar on PoCL 3.1 and costs about as much as the sums at radius 6.
__kernel __attribute__((reqd_work_group_size(1, BLUR_RUNS_LINES, 1))) void blur_rows_runs_moments(
    __global const float* depth, __global float* out, uint width, uint height, int radius, __constant float* weights,
    __local float* lines, MomentsParams p) {
  const int x0 = blur_runs_x0(), y = get_global_id(1);
  if (y >= (int)height || x0 >= (int)width) return;
  const int count = min(BLUR_RUNS_SEGMENT, (int)width - x0), span = blur_runs_span(count, radius);
  __local float* line = blur_runs_line(lines, radius);
  __global const float* row = depth + (size_t)y * width;
  for (int i = 0; i < span; ++i) blur_runs_stage_moments(row[clamp(x0 - radius + i, 0, (int)width - 1)], p, i, line);
  blur_runs_row_output(line, out + ((size_t)y * width + x0) * BLUR_CHANNELS, count, radius, weights);
}
#endif

// The column pass's sums of a strip's partial run (the last n < BLUR_RUN_FLOATS floats of each row), lane by lane.
inline void blur_columns_runs_part(__global const float* in, __global PN_SCALAR* out, int rowFloats, int height, int f,
                                   int n, int y0, int y1, int radius, __constant float* weights) {
  for (int y = y0; y < y1; ++y) {
    float16 sum = 0.0f;
    for (int k = 0; k <= 2 * radius; ++k)
      sum += weights[k] * blur_runs_load_part(in + (size_t)clamp(y - radius + k, 0, height - 1) * rowFloats + f, n);
    blur_runs_store_stored(sum, out + (size_t)y * rowFloats + f, n);
  }
}

// The column pass's sums of the run at `in` in output rows y .. min(y + BLUR_RUNS_COLUMN_ROWS, y1) - 1 (rows of
// rowFloats), side by side for the same reason as the row pass's runs, stored at `out`. Clamping picks whole rows,
// so only taps whose rows leave the image pay for it.
inline void blur_columns_runs_rows(__global const float* in, __global PN_SCALAR* out, int rowFloats, int height, int y,
                                   int y1, int radius, __constant float* weights) {
  float16 sum[BLUR_RUNS_COLUMN_ROWS];
#pragma unroll
  for (int j = 0; j < BLUR_RUNS_COLUMN_ROWS; ++j) sum[j] = 0.0f;
  for (int k = 0; k <= 2 * radius; ++k) {
    const int top = y - radius + k;  // the tap's row for output row y
    const float w = weights[k];
    if (top >= 0 && top + BLUR_RUNS_COLUMN_ROWS <= height) {
      __global const float* src = in + (size_t)top * rowFloats;
#pragma unroll
      for (int j = 0; j < BLUR_RUNS_COLUMN_ROWS; ++j) sum[j] += w * vload16(0, src + (size_t)j * rowFloats);
    } else {
#pragma unroll
      for (int j = 0; j < BLUR_RUNS_COLUMN_ROWS; ++j)
        sum[j] += w * vload16(0, in + (size_t)clamp(top + j, 0, height - 1) * rowFloats);
    }
  }
#pragma unroll
  for (int j = 0; j < BLUR_RUNS_COLUMN_ROWS; ++j)
    if (y + j < y1) blur_runs_store_stored(sum[j], out + (size_t)(y + j) * rowFloats, BLUR_RUN_FLOATS);
}

// Work-item (block, strip): BLUR_RUNS_COLUMN_BLOCK floats of each of the BLUR_RUNS_COLUMN_STRIP output rows of a
// strip, taps read straight from global memory (rows y - r .. y + r, clamped). The item sweeps its block's runs for
// a few output rows, then moves down: each input row is read as a contiguous block (what the prefetcher follows) and
// the 2r rows the next outputs share are still in cache (2r + 4 block rows: 104 KiB at radius 24). Measured worse:
// an item per run walking down (a page per tap), short strips of runs side by side (each input row fetched
// (2r + rows) / rows times). Only a row's last, partial run loads lane by lane.
__kernel __attribute__((reqd_work_group_size(1, 1, 1))) void blur_columns_runs(__global const float* in,
                                                                               __global PN_SCALAR* out, uint width,
                                                                               uint height, int radius,
                                                                               __constant float* weights) {
  const int rowFloats = width * BLUR_CHANNELS, h = height, f0 = get_global_id(0) * BLUR_RUNS_COLUMN_BLOCK;
  const int f1 = min(f0 + BLUR_RUNS_COLUMN_BLOCK, rowFloats), whole = f1 - (f1 - f0) % BLUR_RUN_FLOATS;
  const int y0 = get_global_id(1) * BLUR_RUNS_COLUMN_STRIP, y1 = min(y0 + BLUR_RUNS_COLUMN_STRIP, h);
  if (f0 >= rowFloats || y0 >= h) return;
  for (int y = y0; y < y1; y += BLUR_RUNS_COLUMN_ROWS) {
    for (int f = f0; f < whole; f += BLUR_RUN_FLOATS)
      blur_columns_runs_rows(in + f, out + f, rowFloats, h, y, y1, radius, weights);
    if (whole < f1)
      blur_columns_runs_part(in, out, rowFloats, h, whole, f1 - whole, y, min(y + BLUR_RUNS_COLUMN_ROWS, y1), radius,
                             weights);
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

#if BLUR_CHANNELS == 1 && defined(BLUR_LOG_RADIUS)
// Log-space blur of ESM's depths (kernels/shared/moments.h, moments_log_mix): per output texel, the D with
// e^(c D) = sum w_k e^(c d_k) over the clamped taps, computed around the largest tap so that every exponential is at
// most 1. An item sums a run of BLUR_RUN_FLOATS consecutive outputs of a row as one float16 (the runs layout's
// reasoning: CPU compilers vectorise explicit vectors, exp and log included, not loops across items), with the radius
// fixed at build time (-DBLUR_LOG_RADIUS: the few radii ESM's kernels take), so the taps unroll.
#define BLUR_LOG_TAPS (2 * BLUR_LOG_RADIUS + 1)

inline float16 blur_log_taps(const float16* v, __constant float* weights, float c) {
  float16 m = v[0], linear = 0.0f, sum = 0.0f;
#pragma unroll
  for (int k = 1; k < BLUR_LOG_TAPS; ++k) m = fmax(m, v[k]);  // every direct tap has weight > 0
#pragma unroll
  for (int k = 0; k < BLUR_LOG_TAPS; ++k) {
    linear += weights[k] * v[k];
    sum += weights[k] * exp(c * (v[k] - m));
  }
  return c > MOMENTS_LOG_MIN_EXPONENT ? m + log(sum) / c : linear;
}

// The 16 floats of `line` (n long) from `first`, each index clamped to the line.
inline float16 blur_log_load_clamped(__global const float* line, int n, int first) {
  float lanes[BLUR_RUN_FLOATS];
  for (int i = 0; i < BLUR_RUN_FLOATS; ++i) lanes[i] = line[clamp(first + i, 0, n - 1)];
  return vload16(0, lanes);
}

// Item (run, row): outputs x0 .. x0 + 15 of row y (the last run of a row may be partial).
__kernel void blur_log_rows(__global const float* in, __global float* out, uint width, uint height,
                            __constant float* weights, float exponent) {
  const int x0 = get_global_id(0) * BLUR_RUN_FLOATS, y = get_global_id(1), w = width;
  if (x0 >= w || y >= (int)height) return;
  __global const float* line = in + (size_t)y * width;
  const bool inside = x0 - BLUR_LOG_RADIUS >= 0 && x0 + BLUR_RUN_FLOATS - 1 + BLUR_LOG_RADIUS < w;
  float16 v[BLUR_LOG_TAPS];
#pragma unroll
  for (int k = 0; k < BLUR_LOG_TAPS; ++k)
    v[k] =
        inside ? vload16(0, line + x0 - BLUR_LOG_RADIUS + k) : blur_log_load_clamped(line, w, x0 - BLUR_LOG_RADIUS + k);
  blur_runs_store(blur_log_taps(v, weights, exponent), out + (size_t)y * width + x0, min(BLUR_RUN_FLOATS, w - x0));
}

// Item (run, row) of the column pass: taps from whole rows y - r .. y + r (clamped), stored in the image's storage
// (fp32, or half with STORE_HALF).
__kernel void blur_log_columns(__global const float* in, __global PN_SCALAR* out, uint width, uint height,
                               __constant float* weights, float exponent) {
  const int x0 = get_global_id(0) * BLUR_RUN_FLOATS, y = get_global_id(1), w = width;
  if (x0 >= w || y >= (int)height) return;
  const int n = min(BLUR_RUN_FLOATS, w - x0);
  float16 v[BLUR_LOG_TAPS];
#pragma unroll
  for (int k = 0; k < BLUR_LOG_TAPS; ++k) {
    __global const float* row = in + (size_t)clamp(y - BLUR_LOG_RADIUS + k, 0, (int)height - 1) * width + x0;
    v[k] = n == BLUR_RUN_FLOATS ? vload16(0, row) : blur_runs_load_part(row, n);
  }
  blur_runs_store_stored(blur_log_taps(v, weights, exponent), out + (size_t)y * width + x0, n);
}
#endif
