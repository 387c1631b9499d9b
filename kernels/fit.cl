// Bounds reductions for fitting the light's frustum and the filters to the scene (host/views/light_fit.cpp): the
// light-space box of the receivers the camera sees (G-buffer positions), the depth range of a rasterized map, the
// histogram of the map sizes the camera's pixels need, the histogram of the penumbra widths its shadows have, and the
// histogram of the widths of the casters' features a drawn map holds. Two
// passes without global atomics: every work-group reduces its share in local memory and writes one partial; the
// host reduces the few partials. Min, max and counts only, so the result does not depend on the order.

#include "kernels/shared/shadow_common.h"

#define FIT_GROUP 256
#define FIT_SIZE_BINS 128      // log2 of the needed map size in [0, 16), FIT_SIZE_BINS_PER_OCTAVE bins an octave
#define FIT_SIZE_BINS_PER_OCTAVE 8
#define FIT_PENUMBRA_BINS 128  // log2 of a penumbra half-width in texels in [-8, 8), FIT_SIZE_BINS_PER_OCTAVE an octave
#define FIT_PENUMBRA_LOG2_MIN (-8)

// The G-buffer passes' loop: blocks of FIT_GROUP consecutive samples dealt to the work-groups in turn, so that each
// group's share spreads over the whole frame while a block stays contiguous. A pixel's cost follows the frame's content
// (a covered pixel projects, a shadowed one reads the map), and a chunk of consecutive rows per group left one thread
// of a CPU device with all the shadows (PoCL deals each thread a run of groups).
#define FIT_FOR_SAMPLES(k, count) \
  for (uint k = get_group_id(0) * FIT_GROUP + get_local_id(0); k < (count); k += get_num_groups(0) * FIT_GROUP)

// Sample k of a width x height frame measured on a grid of `stride` (every stride-th column of every stride-th row,
// from (0, 0)): its pixel index. `columns` = ceil(width / stride).
inline uint fit_sample_pixel(uint k, uint width, uint stride, uint columns) {
  return (k / columns) * stride * width + (k % columns) * stride;
}

// Min (lo) and max (hi) over the work-group; valid in every work-item afterwards.
inline void fit_group_minmax(float4* lo, float4* hi, __local float4* los, __local float4* his) {
  const uint lid = get_local_id(0);
  los[lid] = *lo;
  his[lid] = *hi;
  for (uint active = FIT_GROUP / 2; active > 0; active /= 2) {
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid < active) {
      los[lid] = fmin(los[lid], los[lid + active]);
      his[lid] = fmax(his[lid], his[lid + active]);
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  *lo = los[0];
  *hi = his[0];
}

// A work-group's local histogram of `n` bins zeroed, with the barrier before its counts.
inline void fit_bins_clear(__local uint* bins, uint n) {
  for (uint b = get_local_id(0); b < n; b += FIT_GROUP) bins[b] = 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
}

// Once the group has counted: its histogram into partial[group * n + b].
inline void fit_bins_store(__local const uint* bins, uint n, __global uint* partial) {
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint b = get_local_id(0); b < n; b += FIT_GROUP) partial[get_group_id(0) * n + b] = bins[b];
}

// Light-eye box of the covered G-buffer pixels (position.w != 0). With `perspective`, x and y are the
// tangents x/d and y/d at light depth d = -z_eye (what a perspective map's texels are uniform in); points
// at or behind the light (d <= 0) cannot be in a spot light's map and are skipped. Per group:
// partial[2g] = (min x, min y, min d, 0), partial[2g+1] = (max x, max y, max d, 0); empty = (+inf, -inf).
__kernel __attribute__((reqd_work_group_size(FIT_GROUP, 1, 1))) void fit_receivers_partial(
    __global const float4* position, uint count, float4 row0, float4 row1, float4 row2, int perspective,
    __global float4* partial) {
  __local float4 los[FIT_GROUP], his[FIT_GROUP];
  float4 lo = (float4)(INFINITY, INFINITY, INFINITY, 0.0f), hi = (float4)(-INFINITY, -INFINITY, -INFINITY, 0.0f);
  FIT_FOR_SAMPLES(i, count) {
    float4 p = position[i];
    if (p.w == 0.0f) continue;
    p.w = 1.0f;
    float d = -dot(row2, p);
    float2 xy = (float2)(dot(row0, p), dot(row1, p));
    if (perspective) {
      if (!(d > 0.0f)) continue;
      xy /= d;
    }
    float4 e = (float4)(xy, d, 0.0f);
    if (!all(isfinite(e.xyz))) continue;
    lo = fmin(lo, e);
    hi = fmax(hi, e);
  }
  fit_group_minmax(&lo, &hi, los, his);
  if (get_local_id(0) == 0) {
    partial[2 * get_group_id(0)] = lo;
    partial[2 * get_group_id(0) + 1] = hi;
  }
}

// Finite depth range of a rasterized map (background is +INFINITY). Per group: partial[g] = (min, max).
// FIT_CONTIGUOUS (CPUs, DeviceInfo::cpuLayouts): each work-item reduces one contiguous slice of the group's chunk,
// branch-free (a non-finite depth becomes NaN, which fmin and fmax pass over), so that it streams and vectorizes:
// PoCL runs a group's work-items one after another, and the strided walk GPUs coalesce took 12.8 ms for a 3840^2 map
// here, 5.7 times its copy floor. Otherwise consecutive work-items read consecutive depths.
#ifndef FIT_CONTIGUOUS
#define FIT_CONTIGUOUS 0
#endif
__kernel __attribute__((reqd_work_group_size(FIT_GROUP, 1, 1))) void fit_depth_partial(__global const float* depth,
                                                                                        uint count, uint chunk,
                                                                                        __global float2* partial) {
  __local float4 los[FIT_GROUP], his[FIT_GROUP];
  float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
  const uint begin = get_group_id(0) * chunk, end = min(begin + chunk, count);
#if FIT_CONTIGUOUS
  const uint slice = (chunk + FIT_GROUP - 1) / FIT_GROUP, first = min(begin + (uint)get_local_id(0) * slice, end);
  const uint last = min(first + slice, end);
  float8 l = (float8)(INFINITY), h = (float8)(-INFINITY);
  uint i = first;
  for (; i + 8 <= last; i += 8) {  // 8 depths at a time: vload8 takes any alignment
    const float8 d = vload8(0, depth + i);
    const float8 finite = select((float8)(NAN), d, isfinite(d));
    l = fmin(l, finite);
    h = fmax(h, finite);
  }
  for (; i < last; ++i) {
    const float d = depth[i];
    const float finite = isfinite(d) ? d : NAN;
    l.s0 = fmin(l.s0, finite);
    h.s0 = fmax(h.s0, finite);
  }
  const float4 l4 = fmin(l.lo, l.hi), h4 = fmax(h.lo, h.hi);
  const float2 l2 = fmin(l4.lo, l4.hi), h2 = fmax(h4.lo, h4.hi);
  lo.x = fmin(l2.x, l2.y), hi.x = fmax(h2.x, h2.y);
#else
  for (uint i = begin + get_local_id(0); i < end; i += FIT_GROUP) {
    float d = depth[i];
    if (!isfinite(d)) continue;
    lo.x = fmin(lo.x, d);
    hi.x = fmax(hi.x, d);
  }
#endif
  fit_group_minmax(&lo, &hi, los, his);
  if (get_local_id(0) == 0) partial[get_group_id(0)] = (float2)(lo.x, hi.x);
}

// Caster detail: the widths of the features a drawn map holds, in texels. Along each row and column of the map, a
// feature is a run of texels entered by a step towards the light and left by a step away from it, each step a depth
// jump of more than FIT_DETAIL_JUMP texel widths at the nearer side (background, +INFINITY, and NaN texels lie
// infinitely deep): a leg, a wire, a bar between alpha holes. A slanted surface steps one way only and holds no run.
// Work-item l < height walks row l; the others FIT_DETAIL_COLUMNS columns side by side, one row of them per step as
// one vector (a column at a time read one cache line per texel: a 512^2 probe's columns took 0.9 ms on PoCL), the
// last columns of a width that is no multiple of it one by one. Per group: partial[g * FIT_DETAIL_BINS + b] = runs of
// width b + 1 texels (the last bin: FIT_DETAIL_BINS or wider).
#define FIT_DETAIL_BINS 64
#define FIT_DETAIL_JUMP 8.0f
#define FIT_DETAIL_COLUMNS 8

// The depth jump that counts between texels of light depths a and b: FIT_DETAIL_JUMP texels at the nearer one
// (lv_texel_world, for scalars and vectors alike).
#define FIT_DETAIL_STEP(lv, a, b) \
  (FIT_DETAIL_JUMP * ((lv)->kind == LIGHT_KIND_SPOT ? (lv)->texelScale * fmin(a, b) : (lv)->texelScale))

// Texel k of the line: NaN read as background.
#define FIT_DETAIL_AT(depth, first, step, k) fit_detail_depth((depth)[(first) + (size_t)(k) * (step)])
inline float fit_detail_depth(float d) { return isnan(d) ? INFINITY : d; }

// Step k of a line (texel k - 1 to k): a run starts, or one that started ends.
inline void fit_detail_step(float d, float prev, int k, int* start, __constant const LightViewGpu* lv,
                            __local uint* bins) {
  const float jump = FIT_DETAIL_STEP(lv, d, prev);
  if (d < prev - jump) {
    *start = k;
  } else if (*start >= 0 && d > prev + jump) {
    atomic_inc(&bins[min(k - *start, FIT_DETAIL_BINS) - 1]);
    *start = -1;
  }
}

// A line of n texels from `first`, `step` apart. On a row (step 1) 8 steps are first tested at once, and only those
// holding a jump either way are walked (a row of a probe has a few).
inline void fit_detail_line(__global const float* depth, size_t first, size_t step, int n,
                            __constant const LightViewGpu* lv, __local uint* bins) {
  int start = -1;
  for (int k0 = 1; k0 < n; k0 += 8) {
    if (step == 1 && k0 + 8 <= n) {
      __global const float* at = depth + first + (size_t)k0;
      float8 d = vload8(0, at), prev = vload8(0, at - 1);
      d = select(d, (float8)(INFINITY), isnan(d)), prev = select(prev, (float8)(INFINITY), isnan(prev));
      const float8 jump = FIT_DETAIL_STEP(lv, d, prev);
      if (!any((d < prev - jump) | (d > prev + jump))) continue;  // no run starts or ends here
    }
    for (int k = k0; k < min(k0 + 8, n); ++k)
      fit_detail_step(FIT_DETAIL_AT(depth, first, step, k), FIT_DETAIL_AT(depth, first, step, k - 1), k, &start, lv,
                      bins);
  }
}

#if FIT_DETAIL_COLUMNS != 8
#error "fit_detail_columns walks its columns as float8"
#endif
// Columns x0 .. x0 + 7, every lane as fit_detail_line walks one.
inline void fit_detail_columns(__global const float* depth, int x0, int width, int height,
                               __constant const LightViewGpu* lv, __local uint* bins) {
  int8 start = (int8)(-1);
  float8 prev = vload8(0, depth + x0);
  prev = select(prev, (float8)(INFINITY), isnan(prev));
  for (int k = 1; k < height; ++k) {
    float8 d = vload8(0, depth + (size_t)k * width + x0);
    d = select(d, (float8)(INFINITY), isnan(d));
    const float8 jump = FIT_DETAIL_STEP(lv, d, prev);
    const int8 enter = d < prev - jump;
    const int8 leave = ~enter & (start >= 0) & (d > prev + jump);
    if (any(leave)) {
      const int8 width8 = min((int8)(k)-start, (int8)(FIT_DETAIL_BINS)) - 1;
      const int mask[8] = {leave.s0, leave.s1, leave.s2, leave.s3, leave.s4, leave.s5, leave.s6, leave.s7};
      const int bin[8] = {width8.s0, width8.s1, width8.s2, width8.s3, width8.s4, width8.s5, width8.s6, width8.s7};
      for (int lane = 0; lane < FIT_DETAIL_COLUMNS; ++lane)
        if (mask[lane] != 0) atomic_inc(&bins[bin[lane]]);
    }
    start = select(select(start, (int8)(k), enter), (int8)(-1), leave);
    prev = d;
  }
}

__kernel __attribute__((reqd_work_group_size(FIT_GROUP, 1, 1))) void fit_detail_partial(
    __global const float* depth, int width, int height, __constant const LightViewGpu* lv, __global uint* partial) {
  __local uint bins[FIT_DETAIL_BINS];
  fit_bins_clear(bins, FIT_DETAIL_BINS);
  const int line = (int)get_global_id(0), whole = width / FIT_DETAIL_COLUMNS;
  if (line < height) {
    fit_detail_line(depth, (size_t)line * width, 1, width, lv, bins);
  } else if (line < height + whole) {
    fit_detail_columns(depth, (line - height) * FIT_DETAIL_COLUMNS, width, height, lv, bins);
  } else if (line == height + whole) {
    for (int x = whole * FIT_DETAIL_COLUMNS; x < width; ++x)
      fit_detail_line(depth, (size_t)x, (size_t)width, height, lv, bins);
  }
  fit_bins_store(bins, FIT_DETAIL_BINS, partial);
}

// Histogram of the map size each covered pixel needs (Luksch sec. 7, eq. 5, as pssm's resolutionError): the
// pixel's screen steps to on-plane neighbours, projected into the first of `viewCount` views whose map holds the
// pixel, measured in that map's texels (sc_footprint); the shorter step s says one texel per pixel takes a map
// width / s texels wide. Bin floor(log2(width / s) * FIT_SIZE_BINS_PER_OCTAVE), clamped to the histogram; pixels with
// no on-plane neighbour, behind the light or outside every map are not counted. Only the pixels on a grid of `stride`
// (every stride-th column of every stride-th row, from (0, 0)) are measured, each against its own neighbours. Per
// group: partial[g * FIT_SIZE_BINS + b] = count of bin b.
__kernel __attribute__((reqd_work_group_size(FIT_GROUP, 1, 1))) void fit_size_partial(
    __global const float4* position, __global const float4* normal, uint width, uint height, uint stride,
    __constant const LightViewGpu* views, uint viewCount, __global uint* partial) {
  __local uint bins[FIT_SIZE_BINS];
  fit_bins_clear(bins, FIT_SIZE_BINS);
  const uint columns = (width + stride - 1) / stride, count = columns * ((height + stride - 1) / stride);
  FIT_FOR_SAMPLES(k, count) {
    const uint i = fit_sample_pixel(k, width, stride, columns);
    float4 p = position[i];
    if (p.w == 0.0f) continue;
    int view = -1;
    for (uint v = 0; v < viewCount && view < 0; ++v) {
      float3 t = lv_project(views + v, p.xyz);
      if (t.z > 0.0f && t.x >= 0.0f && t.y >= 0.0f && t.x <= views[v].width && t.y <= views[v].height) view = (int)v;
    }
    if (view < 0) continue;
    Footprint f = sc_footprint(position, views + view, width, height, i, p.xyz, normal[i].xyz);
    float lx = length(f.dx.xy), ly = length(f.dy.xy);
    float step = lx > 0.0f && ly > 0.0f ? min(lx, ly) : max(lx, ly);
    float need = (float)views[view].width / step;
    if (!(step > 0.0f) || !isfinite(need)) continue;
    int bin = (int)floor(log2(need) * FIT_SIZE_BINS_PER_OCTAVE);
    atomic_inc(&bins[clamp(bin, 0, FIT_SIZE_BINS - 1)]);
  }
  fit_bins_store(bins, FIT_SIZE_BINS, partial);
}

// Histogram of the penumbrae at the camera's pixels: what the fixed-kernel filters choose their width from
// (`--blur-radius auto`, `--pcf-radius auto`) and savsm its occluder distance. Every covered pixel facing the light is
// set up as sm's receiver (sc_receiver, the same biases); where the nearest texel's occluder lies in front of it (the
// pixel is in the hard shadow of the light's centre), that occluder and the receiver give, with `measure`
// FIT_PENUMBRA_HALF_WIDTH, the penumbra's half-width in texels at the receiver by similar triangles
// (lv_penumbra_texels: Fernando 2005, PCSS's eq. 1 with the one blocker the map holds there), or with
// FIT_PENUMBRA_DISTANCE the occluder's distance in front of the receiver (light depth) over `unit`. Bin
// floor((log2(value) - FIT_PENUMBRA_LOG2_MIN) * FIT_SIZE_BINS_PER_OCTAVE), clamped to the histogram (0, an occluder
// touching its receiver, in bin 0); background, back-facing pixels (shadowed by their own surface), pixels outside the
// map or behind the light, and lit pixels are not counted. Only the pixels on a grid of `stride` are measured
// (fit_sample_pixel). Per group: partial[g * FIT_PENUMBRA_BINS + b] = count of b.
#define FIT_PENUMBRA_HALF_WIDTH 0
#define FIT_PENUMBRA_DISTANCE 1
__kernel __attribute__((reqd_work_group_size(FIT_GROUP, 1, 1))) void fit_penumbra_partial(
    __global const float4* position, __global const float4* normal, uint width, uint height, uint stride,
    __global const float* map, __constant const LightViewGpu* lv, float biasConstant, float biasSlope,
    float normalOffset, int measure, float unit, __global uint* partial) {
  __local uint bins[FIT_PENUMBRA_BINS];
  fit_bins_clear(bins, FIT_PENUMBRA_BINS);
  const uint columns = (width + stride - 1) / stride, count = columns * ((height + stride - 1) / stride);
  const ShadowBias bias = {biasConstant, biasSlope, normalOffset};
  FIT_FOR_SAMPLES(k, count) {
    const uint i = fit_sample_pixel(k, width, stride, columns);
    float4 p = position[i];
    float3 n = normal[i].xyz;
    if (p.w == 0.0f || !(dot(n, lv_to_light(lv, p.xyz)) > 0.0f)) continue;
    Receiver r = sc_receiver(lv, p.xyz, n, bias);
    float2 texel = floor(r.uv);
    if (!r.valid || !(texel.x >= 0.0f && texel.y >= 0.0f && texel.x < (float)lv->width && texel.y < (float)lv->height))
      continue;
    float occluder = sc_fetch(map, lv->width, lv->height, (int)texel.x, (int)texel.y);
    if (!(occluder < r.depth - r.bias)) continue;  // lit, or no caster drawn there (+INFINITY)
    float h = measure == FIT_PENUMBRA_DISTANCE ? (r.depth - occluder) / unit
                                               : lv_penumbra_texels(lv, r.depth, fmax(occluder, lv->zNear));
    int bin = h > 0.0f ? (int)floor((log2(h) - (float)FIT_PENUMBRA_LOG2_MIN) * FIT_SIZE_BINS_PER_OCTAVE) : 0;
    atomic_inc(&bins[clamp(bin, 0, FIT_PENUMBRA_BINS - 1)]);
  }
  fit_bins_store(bins, FIT_PENUMBRA_BINS, partial);
}
