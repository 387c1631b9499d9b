// Summed-area tables. Tiled scan after Nehab et al. 2011 ("GPU-efficient recursive filtering and
// summed-area tables", alg. SAT): (1) per 32x32 tile, row and column sums and the tile total; (2) one
// launch scanning those across tiles into carries (plus one work-group for the 2-D prefix of totals);
// (3) per tile, the in-tile 2-D scan with the carries added: the image is read twice and written once,
// no inter-group synchronisation. Line scans suit CPUs; Hensley et al. 2005 recursive doubling is the
// O(n log n) baseline.
#include "kernels/shared/sat.h"

inline float4 sat_widen(SAT_F v) {
#if SAT_CHANNELS == 1
  return (float4)(v, 0.0f, 0.0f, 0.0f);
#elif SAT_CHANNELS == 2
  return (float4)(v, 0.0f, 0.0f);
#else
  return v;
#endif
}

// Per-work-group sums and finite counts of the image (for the fp32 zero-mean offset); chunked so the
// result does not depend on scheduling.
__kernel __attribute__((reqd_work_group_size(SAT_REDUCE_GROUP, 1, 1))) void sat_mean_partial(
    __global const SAT_F* in, uint count, uint chunk, __global float4* partials) {
  __local float4 sums[SAT_REDUCE_GROUP], counts[SAT_REDUCE_GROUP];
  const uint lid = get_local_id(0), begin = get_group_id(0) * chunk, end = min(begin + chunk, count);
  float4 sum = 0.0f, n = 0.0f;
  for (uint i = begin + lid; i < end; i += SAT_REDUCE_GROUP) {
    const SAT_F x = in[i];
    sum += sat_widen(select((SAT_F)0.0f, x, isfinite(x)));
    n += sat_widen(select((SAT_F)0.0f, (SAT_F)1.0f, isfinite(x)));
  }
  sums[lid] = sum;
  counts[lid] = n;
  for (uint active = SAT_REDUCE_GROUP / 2; active > 0; active /= 2) {
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid < active) sums[lid] += sums[lid + active], counts[lid] += counts[lid + active];
  }
  if (lid == 0) partials[2 * get_group_id(0)] = sums[0], partials[2 * get_group_id(0) + 1] = counts[0];
}

// One work-group: offset = sum / count of finite texels per channel (0 where none).
__kernel __attribute__((reqd_work_group_size(SAT_REDUCE_GROUP, 1, 1))) void sat_mean_final(
    __global const float4* partials, uint groups, __global float4* offset) {
  __local float4 sums[SAT_REDUCE_GROUP], counts[SAT_REDUCE_GROUP];
  const uint lid = get_local_id(0);
  float4 sum = 0.0f, n = 0.0f;
  for (uint g = lid; g < groups; g += SAT_REDUCE_GROUP) sum += partials[2 * g], n += partials[2 * g + 1];
  sums[lid] = sum;
  counts[lid] = n;
  for (uint active = SAT_REDUCE_GROUP / 2; active > 0; active /= 2) {
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid < active) sums[lid] += sums[lid + active], counts[lid] += counts[lid + active];
  }
  if (lid == 0) offset[0] = select((float4)0.0f, sums[0] / counts[0], counts[0] > 0.0f);
}

// Loads the tile at group (tx, ty) into `tile` in storage form (offset or quantized); texels outside the
// image are 0. Work-item (lx, ly) loads rows ly, ly + 8, ...
inline void sat_load_tile(__global const SAT_F* in, SatTableDesc t, SAT_F offset,
                          __local SAT_T (*tile)[SAT_TILE + 1]) {
  const uint lx = get_local_id(0), x = get_group_id(0) * SAT_TILE + lx, y0 = get_group_id(1) * SAT_TILE;
  for (uint r = get_local_id(1); r < SAT_TILE; r += SAT_GROUP_Y) {
    const uint y = y0 + r;
    tile[r][lx] = (x < t.width && y < t.height) ? SAT_LOAD(in[(size_t)y * t.width + x], offset, t.scale) : (SAT_T)0;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
}

// Pass 1: rowSums[y][tx] = sum of row y inside tile tx, colSums[ty][x] likewise for columns,
// totals[ty][tx] = the whole tile.
__kernel __attribute__((reqd_work_group_size(SAT_TILE, SAT_GROUP_Y, 1))) void sat_tile_sums(
    __global const SAT_F* in, SatTableDesc t, __global const float* offsetBuffer, __global SAT_T* rowSums,
    __global SAT_T* colSums, __global SAT_T* totals) {
  __local SAT_T tile[SAT_TILE][SAT_TILE + 1];
  __local SAT_T rowTotals[SAT_TILE];
  sat_load_tile(in, t, sat_offset(offsetBuffer), tile);
  const uint lx = get_local_id(0), ly = get_local_id(1), tx = get_group_id(0), ty = get_group_id(1);
  SAT_T sum = 0;
  if (ly == 0) {  // column lx
    for (int r = 0; r < SAT_TILE; ++r) sum += tile[r][lx];
    const uint x = tx * SAT_TILE + lx;
    if (x < t.width) colSums[(size_t)ty * t.width + x] = sum;
  } else if (ly == 1) {  // row lx
    for (int c = 0; c < SAT_TILE; ++c) sum += tile[lx][c];
    rowTotals[lx] = sum;
    const uint y = ty * SAT_TILE + lx;
    if (y < t.height) rowSums[(size_t)y * t.tilesX + tx] = sum;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (ly == 0 && lx == 0) {
    SAT_T total = 0;
    for (int r = 0; r < SAT_TILE; ++r) total += rowTotals[r];
    totals[ty * t.tilesX + tx] = total;
  }
}

// In-place exclusive scan of `n` values spaced `stride` apart.
inline void sat_exclusive_scan(__global SAT_T* p, uint n, size_t stride) {
  SAT_T running = 0;
  for (uint i = 0; i < n; ++i) {
    const SAT_T v = p[i * stride];
    p[i * stride] = running;
    running += v;
  }
}

// Pass 2: work-items [0, height) scan rowSums along x, [height, height + width) colSums along y; the
// last work-group turns totals into corners[ty][tx] = sum of all tiles above and to the left (rows, then
// columns). Every work-item reaches the one barrier: PoCL mis-compiles a barrier after an early return.
__kernel __attribute__((reqd_work_group_size(SAT_CARRY_GROUP, 1, 1))) void sat_carry(
    SatTableDesc t, __global SAT_T* rowSums, __global SAT_T* colSums, __global SAT_T* totals) {
  const uint i = get_global_id(0), lid = get_local_id(0);
  const bool corners = get_group_id(0) + 1 == get_num_groups(0);
  if (!corners && i < t.height) sat_exclusive_scan(rowSums + (size_t)i * t.tilesX, t.tilesX, 1);
  else if (!corners && i < t.height + t.width) sat_exclusive_scan(colSums + (i - t.height), t.tilesY, t.width);
  else if (corners)
    for (uint ty = lid; ty < t.tilesY; ty += SAT_CARRY_GROUP) sat_exclusive_scan(totals + ty * t.tilesX, t.tilesX, 1);
  barrier(CLK_GLOBAL_MEM_FENCE);
  if (corners)
    for (uint tx = lid; tx < t.tilesX; tx += SAT_CARRY_GROUP) sat_exclusive_scan(totals + tx, t.tilesY, t.tilesX);
}

// Inclusive scan of the 32x32 tile along rows (`alongRows`) or columns. Work-item (lx, ly) scans
// SAT_TILE / 8 consecutive elements of line lx, then adds the totals of the preceding segments.
inline void sat_scan_tile(__local SAT_T (*tile)[SAT_TILE + 1], __local SAT_T (*segments)[SAT_TILE],
                          bool alongRows) {
  const int line = get_local_id(0), seg = get_local_id(1), per = SAT_TILE / SAT_GROUP_Y;
  SAT_T running = 0;
  for (int k = seg * per; k < (seg + 1) * per; ++k) {
    __local SAT_T* e = alongRows ? &tile[line][k] : &tile[k][line];
    running += *e;
    *e = running;
  }
  segments[seg][line] = running;
  barrier(CLK_LOCAL_MEM_FENCE);
  SAT_T carry = 0;
  for (int s = 0; s < seg; ++s) carry += segments[s][line];
  for (int k = seg * per; k < (seg + 1) * per; ++k) {
    if (alongRows) tile[line][k] += carry;
    else tile[k][line] += carry;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
}

// Pass 3: reload the tile, seed its first column with the row carries, its first row with the column
// carries and its corner with the 2-D carry, scan rows then columns, write.
__kernel __attribute__((reqd_work_group_size(SAT_TILE, SAT_GROUP_Y, 1))) void sat_tile_scan(
    __global const SAT_F* in, SatTableDesc t, __global const float* offsetBuffer, __global const SAT_T* rowCarry,
    __global const SAT_T* colCarry, __global const SAT_T* corners, __global SAT_T* out) {
  __local SAT_T tile[SAT_TILE][SAT_TILE + 1];
  __local SAT_T segments[SAT_GROUP_Y][SAT_TILE];
  sat_load_tile(in, t, sat_offset(offsetBuffer), tile);
  const uint lx = get_local_id(0), ly = get_local_id(1), tx = get_group_id(0), ty = get_group_id(1);
  const uint x = tx * SAT_TILE + lx, y = ty * SAT_TILE + lx;
  if (ly == 0 && y < t.height) tile[lx][0] += rowCarry[(size_t)y * t.tilesX + tx];
  barrier(CLK_LOCAL_MEM_FENCE);
  if (ly == 0 && x < t.width) tile[0][lx] += colCarry[(size_t)ty * t.width + x];
  if (ly == 0 && lx == 0) tile[0][0] += corners[ty * t.tilesX + tx];
  barrier(CLK_LOCAL_MEM_FENCE);
  sat_scan_tile(tile, segments, true);
  sat_scan_tile(tile, segments, false);
  for (uint r = ly; r < SAT_TILE; r += SAT_GROUP_Y) {
    const uint yy = ty * SAT_TILE + r;
    if (x < t.width && yy < t.height) out[(size_t)yy * t.width + x] = tile[r][lx];
  }
}

// Line scans for CPU devices: a serial scan per row, then per column in place. Neighbouring work-items
// take neighbouring columns, which the CPU compilers vectorize; twice the traffic of the tiled scan,
// but no barriers, which CPU implementations turn into loops over the work-group.
#define SAT_ROW_CHUNK (16 / SAT_CHANNELS)  // texels of 16 floats
#if SAT_MODE == SAT_MODE_FIXED32
#define SAT_ROW_CONVERT(v, lanes) vstore16(as_uint16(convert_int16_sat_rte(v)), 0, (__private uint*)(lanes))
#elif SAT_MODE == SAT_MODE_FIXED64
#define SAT_ROW_CONVERT(v, lanes) vstore16(as_ulong16(convert_long16_sat_rte(v)), 0, (__private ulong*)(lanes))
#endif
__kernel void sat_lines_rows(__global const SAT_F* in, SatTableDesc t, __global const float* offsetBuffer,
                             __global SAT_T* out) {
  const uint y = get_global_id(0);
  if (y >= t.height) return;
  const SAT_F offset = sat_offset(offsetBuffer);
  const size_t row = (size_t)y * t.width;
  SAT_T running = 0;
  uint x = 0;
#if SAT_MODE == SAT_MODE_FIXED32 || SAT_MODE == SAT_MODE_FIXED64
  // Fixed point: 16 floats converted at once (SAT_LOAD's conversion, lane by lane the same), then the serial sum.
  for (; x + SAT_ROW_CHUNK <= t.width; x += SAT_ROW_CHUNK) {
    SAT_T lanes[SAT_ROW_CHUNK];
    SAT_ROW_CONVERT(vload16(0, (__global const float*)(in + row + x)) * t.scale, lanes);
    for (int c = 0; c < SAT_ROW_CHUNK; ++c) out[row + x + c] = running += lanes[c];
  }
#endif
  for (; x < t.width; ++x) out[row + x] = running += SAT_LOAD(in[row + x], offset, t.scale);
}

// One work-item per SAT_LINE_BLOCK neighbouring columns: each row step touches one contiguous run,
// which the compiler turns into vector loads within the work-item.
__kernel void sat_lines_columns(SatTableDesc t, __global SAT_T* table) {
  const uint x0 = get_global_id(0) * SAT_LINE_BLOCK;
  if (x0 >= t.width) return;
  const uint n = min((uint)SAT_LINE_BLOCK, t.width - x0);
  SAT_T running[SAT_LINE_BLOCK];
  for (int c = 0; c < SAT_LINE_BLOCK; ++c) running[c] = 0;
  for (uint y = 0; y < t.height; ++y) {
    __global SAT_T* row = table + (size_t)y * t.width + x0;
    if (n == SAT_LINE_BLOCK) {
      for (int c = 0; c < SAT_LINE_BLOCK; ++c) row[c] = running[c] += row[c];
    } else {
      for (uint c = 0; c < n; ++c) row[c] = running[c] += row[c];
    }
  }
}

// Hensley et al. 2005: the image in storage form, then log2 passes per axis of out[i] = in[i] + in[i - step].
__kernel void sat_hensley_load(__global const SAT_F* in, SatTableDesc t, __global const float* offsetBuffer,
                               __global SAT_T* out) {
  const uint i = get_global_id(0);
  if (i < t.width * t.height) out[i] = SAT_LOAD(in[i], sat_offset(offsetBuffer), t.scale);
}

__kernel void sat_hensley_rows(__global const SAT_T* in, __global SAT_T* out, SatTableDesc t, uint step) {
  const uint x = get_global_id(0), y = get_global_id(1);
  if (x >= t.width || y >= t.height) return;
  const size_t i = (size_t)y * t.width + x;
  out[i] = x >= step ? in[i] + in[i - step] : in[i];
}

__kernel void sat_hensley_columns(__global const SAT_T* in, __global SAT_T* out, SatTableDesc t, uint step) {
  const uint x = get_global_id(0), y = get_global_id(1);
  if (x >= t.width || y >= t.height) return;
  const size_t i = (size_t)y * t.width + x;
  out[i] = y >= step ? in[i] + in[i - (size_t)step * t.width] : in[i];
}
