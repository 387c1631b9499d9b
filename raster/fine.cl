// Fine rasterization, stage 4 of 4 (Laine & Karras 2011, section 4.4): one work-group per 8x8 tile, one work-item
// per pixel. The group stages its tile queue in local memory, RASTER_FINE_WG records at a time; each work-item
// tests its pixel centre against every staged triangle with the exact edge functions and keeps the nearest
// (view depth, triangle id) in registers: nearest wins, ties go to the smaller triangle id. That order is total,
// so the result does not depend on queue order (no atomics, deterministic). The winner's depth is then stored in
// the view's DepthMode; every pixel of the tile inside the scissor is written (background: +INFINITY, no id).
//
// View depth is interpolated perspective-correctly from the integer edge values at the sample,
//   v = sum(e_k * v_k / w_k) / sum(e_k / w_k)   (e_k >= 0 inside, so neither sum cancels),
// in float: within 16 ulp of the exact value for the snapped triangle (measured <= 5; tests/raster_support.h).
#include "raster/constants.h"
#include "raster/coverage.h"
#include "raster/depth.h"
#include "raster/types.h"

// Tests pixel (x, y) against one staged triangle and keeps it when it is nearer (or as near, with a smaller id).
static void fineTest(__local const RasterTriangle* t, int x, int y, int sx, int sy, float farViewZ, float* best,
                     uint* bestId) {
  if (x < t->bbox[0] || x > t->bbox[2] || y < t->bbox[1] || y > t->bbox[3]) return;
  const uint flags = t->flags;
  const long e0 = rasterEdgeAt(t->a[0], t->b[0], t->c[0], sx, sy);
  if (!rasterEdgeAccepts(e0, flags, 0)) return;
  const long e1 = rasterEdgeAt(t->a[1], t->b[1], t->c[1], sx, sy);
  if (!rasterEdgeAccepts(e1, flags, 1)) return;
  const long e2 = rasterEdgeAt(t->a[2], t->b[2], t->c[2], sx, sy);
  if (!rasterEdgeAccepts(e2, flags, 2)) return;
  const float w0 = (float)e0, w1 = (float)e1, w2 = (float)e2;
  const float num = w0 * t->viewZOverW[0] + w1 * t->viewZOverW[1] + w2 * t->viewZOverW[2];
  const float den = w0 * t->invW[0] + w1 * t->invW[1] + w2 * t->invW[2];
  const float v = num / den;
  if (!(v <= farViewZ)) return;  // beyond the far plane (and never NaN)
  const uint id = t->triangleId;
  if (v < *best || (v == *best && id < *bestId)) {
    *best = v;
    *bestId = id;
  }
}

__kernel __attribute__((reqd_work_group_size(RASTER_FINE_WG, 1, 1))) void fine_raster(
    __global const RasterTriangle* tris, __global const uint* tileEntries, __global const uint* tileCount,
    __global const uint* tileOffset, __global float* depth, __global uint* triangleId, const RasterViewParams p) {
  __local RasterTriangle staged[RASTER_FINE_WG];
  const int group = get_group_id(0), lid = get_local_id(0);
  const int tx = p.tileX0 + group % p.tilesAcross, ty = p.tileY0 + group / p.tilesAcross;
  const int x = (tx << RASTER_TILE_LOG2) + (lid & (RASTER_TILE_SIZE - 1));
  const int y = (ty << RASTER_TILE_LOG2) + (lid >> RASTER_TILE_LOG2);
  const bool live = x >= p.rectX0 && x < p.rectX1 && y >= p.rectY0 && y < p.rectY1;
  const int tile = ty * p.tilesX + tx;
  const uint offset = tileOffset[tile];
  const uint count = offset < p.tileCapacity ? min(tileCount[tile], p.tileCapacity - offset) : 0;
  const int sx = rasterSample(x), sy = rasterSample(y);
  float best = INFINITY;
  uint bestId = RASTER_NO_TRIANGLE;
  for (uint base = 0; base < count; base += RASTER_FINE_WG) {
    barrier(CLK_LOCAL_MEM_FENCE);  // the previous batch is no longer read
    if (base + lid < count) staged[lid] = tris[tileEntries[offset + base + lid]];
    barrier(CLK_LOCAL_MEM_FENCE);
    const uint n = min((uint)RASTER_FINE_WG, count - base);
    if (live)
      for (uint j = 0; j < n; ++j) fineTest(&staged[j], x, y, sx, sy, p.farViewZ, &best, &bestId);
  }
  if (live) {
    const size_t pixel = (size_t)y * p.width + x;
    triangleId[pixel] = bestId;
    depth[pixel] = bestId == RASTER_NO_TRIANGLE ? INFINITY : rasterDepth(&p, x, y, best);
  }
}
