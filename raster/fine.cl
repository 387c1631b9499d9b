// Fine rasterization, stage 4 of 4 (Laine & Karras 2011, section 4.4): every pixel centre of an 8x8 tile is tested
// against every triangle of the tile's queue with the exact edge functions, keeping the nearest (view depth,
// triangle id): nearest wins, ties go to the smaller triangle id. That order is total, so the result depends
// neither on queue order nor on the layout below (no atomics, deterministic). The winner's depth is then stored in
// the view's DepthMode; every pixel of the tile inside the scissor is written (background: +INFINITY, no id), except
// in tiles the view's tile mask leaves out. With RasterViewParams::casterTiles it also records per tile whether its
// queue holds no caster (RasterView::recordCasterTiles), and with receiverReach leaves such a tile beyond the reach
// of the casters' box as the background (RasterView::receiverReach).
// Two layouts of the same per-pixel math, chosen by RASTER_WG_FINE (raster/constants.h):
//   0 (GPUs): one work-group per tile, one work-item per pixel, the queue staged in local memory RASTER_FINE_WG
//     records at a time;
//   N > 0 (CPUs): N tiles per work-group, one work-item per tile walking its queue; per triangle only the tile
//     rows inside its candidate box are visited, 8 pixels of a row at a time in a branch-free loop that the
//     compiler vectorizes (PoCL does not vectorize across work-items that loop over a queue).
//
// View depth is interpolated perspective-correctly from the integer edge values at the sample,
//   v = sum(e_k * v_k / w_k) / sum(e_k / w_k)   (e_k >= 0 inside, so neither sum cancels),
// in float: within 16 ulp of the exact value for the snapped triangle (measured <= 5; tests/raster_support.h).
// Alpha-tested triangles (RASTER_FLAG_ALPHA, glTF MASK and BLEND): a covered sample that would win the depth test is
// first alpha-tested at the pixel centre (raster/alpha.h) and discarded below its material's cutoff, so what lies
// behind a hole wins instead; only those samples pay for the texture reads, and opaque records take the same path as
// without alpha-tested triangles.
#include "raster/alpha.h"
#include "raster/constants.h"
#include "raster/coverage.h"
#include "raster/depth.h"
#include "raster/types.h"

#ifndef RASTER_WG_FINE
#define RASTER_WG_FINE 0
#endif

// The per-sample math, as expressions that apply unchanged to scalars and to OpenCL vectors (one result, bit for bit,
// in both layouts below). View depth at samples with edge values converted to float w0, w1, w2 (>= 0 inside) from the
// record's per-vertex terms vz = viewZOverW, iw = invW (float3):
#define FINE_VIEW_Z(w0, w1, w2, vz, iw) \
  (((w0) * (vz).x + (w1) * (vz).y + (w2) * (vz).z) / ((w0) * (iw).x + (w1) * (iw).y + (w2) * (iw).z))
// Whether a fragment (view depth v, triangle id) replaces the nearest so far (best, bestId): inside the far plane
// (which also rules out NaN) and nearer, or as near with a smaller id.
#define FINE_NEARER(v, id, farViewZ, best, bestId) \
  (((v) <= (farViewZ)) & (((v) < (best)) | (((v) == (best)) & ((id) < (bestId)))))

// The pixel's stored values once every triangle has been tested.
static inline void fineStore(const RasterViewParams* p, int x, int y, float best, uint bestId, __global float* depth,
                             __global uint* triangleId) {
  const size_t pixel = (size_t)y * p->width + x;
  if (!p->skipIds) triangleId[pixel] = bestId;
  depth[pixel] = bestId == RASTER_NO_TRIANGLE ? INFINITY : rasterDepth(p, x, y, best);
}

// An empty tile wholly inside the scissor (CPU layout): its rows as 8-wide stores of the background, instead of 64
// scalar stores (pcss's 4096^2 map on scenes/default.json at 640x360, 96 % of its tiles empty: the fine stage
// 7.3-7.7 -> 5.6-6.0 ms in alternated runs; the same bits).
#if RASTER_TILE_SIZE != 8
#error "fineStoreEmptyTile and the CPU layout's row stores store a tile row as one float8"
#endif
// Whether the tile at `origin` lies wholly inside the scissor: every pixel of its rows is written.
static inline bool fineTileInside(const RasterViewParams* p, int2 origin) {
  return origin.x >= p->rectX0 && origin.x + RASTER_TILE_SIZE <= p->rectX1 && origin.y >= p->rectY0 &&
         origin.y + RASTER_TILE_SIZE <= p->rectY1;
}

static inline bool fineStoreEmptyTile(const RasterViewParams* p, int2 origin, __global float* depth,
                                      __global uint* triangleId) {
  if (!fineTileInside(p, origin)) return false;
  for (int r = 0; r < RASTER_TILE_SIZE; ++r) {
    const size_t row = (size_t)(origin.y + r) * p->width + (size_t)origin.x;
    vstore8((float8)(INFINITY), 0, depth + row);
    if (!p->skipIds) vstore8((uint8)(RASTER_NO_TRIANGLE), 0, triangleId + row);
  }
  return true;
}

// Whether the view draws tile `index` of the launched tiles (its tile-mask entry nonzero, when it has a mask).
static inline bool fineDraws(const RasterViewParams* p, int index, __global const uint* tileMask) {
  const int tx = p->tileX0 + index % p->tilesAcross, ty = p->tileY0 + index / p->tilesAcross;
  return p->tileMasked == 0 || tileMask[ty * p->tilesX + tx] != 0;
}

// RasterViewParams::receiverReach: whether the tile at `origin` lies farther than the reach from the casters' box
// (RasterCounters::casterBox widened to whole tiles, as Rasterizer::draw publishes it in RasterTargets::casterBox), or
// no caster was drawn: there a tile whose queue holds no caster is left as the background.
static inline bool fineBeyondCasters(const RasterViewParams* p, __global const RasterCounters* counters, int2 origin) {
  if (!p->casterTiles || p->receiverReach < 0) return false;
  if (counters->casterBox[2] == 0u) return true;
  const int r = p->receiverReach;
  const int x0 = rasterCasterBoxEdge(counters->casterBox[0], 0), y0 = rasterCasterBoxEdge(counters->casterBox[1], 1);
  const int x1 = rasterCasterBoxEdge(counters->casterBox[2], 2), y1 = rasterCasterBoxEdge(counters->casterBox[3], 3);
  return origin.x + RASTER_TILE_SIZE <= x0 - r || origin.x >= x1 + r || origin.y + RASTER_TILE_SIZE <= y0 - r ||
         origin.y >= y1 + r;
}

// The tile a work-group (layout 0) or work-item (layout N) works on, and its queue range cut to the capacity.
static inline int2 fineTile(const RasterViewParams* p, int index, __global const uint* tileCount,
                            __global const uint* tileOffset, uint* offset, uint* count) {
  const int tx = p->tileX0 + index % p->tilesAcross, ty = p->tileY0 + index / p->tilesAcross;
  const int tile = ty * p->tilesX + tx;
  *offset = tileOffset[tile];
  *count = *offset < p->tileCapacity ? min(tileCount[tile], p->tileCapacity - *offset) : 0;
  return (int2)(tx << RASTER_TILE_LOG2, ty << RASTER_TILE_LOG2);
}

#if RASTER_WG_FINE == 0

// Alpha-tested triangles' data (raster/alpha.h), passed on to the sample tests.
typedef struct {
  __global const AlphaTriangle* triangles;
  __global const AlphaMaterial* materials;
  __global const uchar* texels;
} FineAlpha;

// Tests pixel (x, y) against one staged triangle and keeps it when it is nearer (or as near, with a smaller id) and,
// for an alpha-tested one, passes its alpha test.
static void fineTest(__local const RasterTriangle* t, int x, int y, int sx, int sy, const RasterViewParams* p,
                     const FineAlpha* alpha, float* best, uint* bestId) {
  if (x < t->bbox[0] || x > t->bbox[2] || y < t->bbox[1] || y > t->bbox[3]) return;
  const uint flags = t->flags;
  const long e0 = rasterEdgeAt(RASTER_EDGE_A(*t, 0), RASTER_EDGE_B(*t, 0), t->x[0], t->y[0], sx, sy);
  if (!rasterEdgeAccepts(e0, flags, 0)) return;
  const long e1 = rasterEdgeAt(RASTER_EDGE_A(*t, 1), RASTER_EDGE_B(*t, 1), t->x[1], t->y[1], sx, sy);
  if (!rasterEdgeAccepts(e1, flags, 1)) return;
  const long e2 = rasterEdgeAt(RASTER_EDGE_A(*t, 2), RASTER_EDGE_B(*t, 2), t->x[2], t->y[2], sx, sy);
  if (!rasterEdgeAccepts(e2, flags, 2)) return;
  const float v = FINE_VIEW_Z((float)e0, (float)e1, (float)e2, vload3(0, t->viewZOverW), vload3(0, t->invW));
  if (!FINE_NEARER(v, t->triangleId, p->farViewZ, *best, *bestId)) return;
  if ((flags & RASTER_FLAG_ALPHA) != 0) {
    const RasterAlphaFragment f =
        rasterAlphaFragment(p, alpha->triangles, alpha->materials, flags >> RASTER_FLAG_ALPHA_SHIFT);
    if (!rasterAlphaPasses(p, &f, alpha->texels, x, y)) return;
  }
  *best = v;
  *bestId = t->triangleId;
}

__kernel __attribute__((reqd_work_group_size(RASTER_FINE_WG, 1, 1))) void fine_raster(
    __global const RasterTriangle* tris, __global const uint* tileEntries, __global const uint* tileCount,
    __global const uint* tileOffset, __global const uint* tileMask, __global const AlphaTriangle* alphaTriangles,
    __global const AlphaMaterial* alphaMaterials, __global const uchar* alphaTexels, __global float* depth,
    __global uint* triangleId, __global uint* emptyTiles, __global uint* casterFree,
    __global const RasterCounters* counters, const RasterViewParams p) {
  __local RasterTriangle staged[RASTER_FINE_WG];
  __local int casters;  // p.casterTiles: whether a queue entry of the tile is a caster
  const FineAlpha alpha = {alphaTriangles, alphaMaterials, alphaTexels};
  const int lid = get_local_id(0);
  if (!fineDraws(&p, get_group_id(0), tileMask)) return;  // the whole work-group: no barrier is reached
  uint offset, count;
  const int2 origin = fineTile(&p, get_group_id(0), tileCount, tileOffset, &offset, &count);
  if (lid == 0) casters = 0;  // ordered before the atomics and the read below by the barriers after it
  if (fineBeyondCasters(&p, counters, origin)) {  // uniform: the whole group reaches the barriers
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint k = lid; k < count; k += RASTER_FINE_WG)
      if ((tris[tileEntries[offset + k]].flags & RASTER_FLAG_NONCASTER) == 0u) atomic_or(&casters, 1);
    barrier(CLK_LOCAL_MEM_FENCE);
    if (casters == 0) count = 0;  // only receivers, out of the casters' reach: the background
  }
  const int x = origin.x + (lid & (RASTER_TILE_SIZE - 1)), y = origin.y + (lid >> RASTER_TILE_LOG2);
  const bool live = x >= p.rectX0 && x < p.rectX1 && y >= p.rectY0 && y < p.rectY1;
  const int sx = rasterSample(x), sy = rasterSample(y);
  float best = INFINITY;
  uint bestId = RASTER_NO_TRIANGLE;
  for (uint base = 0; base < count; base += RASTER_FINE_WG) {
    barrier(CLK_LOCAL_MEM_FENCE);  // the previous batch is no longer read
    if (base + lid < count) {
      staged[lid] = tris[tileEntries[offset + base + lid]];
      if (p.casterTiles && (staged[lid].flags & RASTER_FLAG_NONCASTER) == 0u) atomic_or(&casters, 1);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    const uint n = min((uint)RASTER_FINE_WG, count - base);
    if (live)
      for (uint j = 0; j < n; ++j) fineTest(&staged[j], x, y, sx, sy, &p, &alpha, &best, &bestId);
  }
  if (live) fineStore(&p, x, y, best, bestId, depth, triangleId);
  if (p.casterTiles) {  // uniform: the whole group reaches the barrier
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == 0) casterFree[(origin.y >> RASTER_TILE_LOG2) * p.tilesX + (origin.x >> RASTER_TILE_LOG2)] = casters == 0;
  }
}

#else

#if RASTER_TILE_SIZE != 8
#error "fine_raster's CPU layout holds a tile row in 8-wide vectors"
#endif
#define RASTER_FINE_PREFETCH 8  // queue entries ahead whose record is prefetched (RASTER_PREFETCH_RECORD)

// An alpha-tested triangle's fragment data for fineTestRows (null for other triangles).
typedef struct {
  const RasterViewParams* p;
  RasterAlphaFragment fragment;
  __global const uchar* texels;
} FineAlphaRows;

// Depth-tests row r of the tile: the samples `inside` the triangle (mask), with edge values w0, w1, w2; with `alpha`,
// the samples that would be kept are alpha-tested first. Always inlined, so that the opaque call (alpha a constant
// null) compiles to the test without it.
static inline __attribute__((always_inline)) void fineKeepRow(int r, int8 inside, float8 w0, float8 w1, float8 w2,
                                                              float3 viewZOverW, float3 invW, uint id, float farViewZ,
                                                              int2 origin, const FineAlphaRows* alpha, float* best,
                                                              uint* bestId) {
  const float8 v = FINE_VIEW_Z(w0, w1, w2, viewZOverW, invW);
  const float8 nearest = vload8(r, best);
  const uint8 nearestId = vload8(r, bestId);
  int8 keep = inside & FINE_NEARER(v, (uint8)id, farViewZ, nearest, nearestId);
  if (alpha != 0 && any(keep))
    keep = rasterAlphaPassesRow(alpha->p, &alpha->fragment, alpha->texels, keep, origin.x, origin.y + r);
  vstore8(select(nearest, v, keep), r, best);
  vstore8(select(nearestId, (uint8)id, keep), r, bestId);
}

// Tests the pixels of tile rows r0..r1 (origin: the tile's bottom-left pixel) against one triangle, a row of 8 pixels
// as one OpenCL vector (explicit vectors: the loop vectorizer left the running minimum in masked stores, slower).
// Per row the edge values start from the exact 64-bit value at the row's first sample and step by 256 a_k per pixel.
static inline __attribute__((always_inline)) void fineTestRows(__global const RasterTriangle* t, int2 origin, int r0,
                                                               int r1, float farViewZ, const FineAlphaRows* alpha,
                                                               float* best, uint* bestId) {
  const int x0 = t->x[0], x1 = t->x[1], x2 = t->x[2], y0 = t->y[0], y1 = t->y[1], y2 = t->y[2];
  const int a0 = y0 - y1, a1 = y1 - y2, a2 = y2 - y0, b0 = x1 - x0, b1 = x2 - x1, b2 = x0 - x2;  // coverage.h
  const long da0 = (long)a0 << RASTER_SUBPIXEL_LOG2, da1 = (long)a1 << RASTER_SUBPIXEL_LOG2;
  const long da2 = (long)a2 << RASTER_SUBPIXEL_LOG2;
  const uint flags = t->flags, id = t->triangleId;
  const long owns0 = (flags & RASTER_FLAG_OWNS_EDGE0) ? -1 : 0;  // lane masks for RASTER_EDGE_PASSES
  const long owns1 = (flags & (RASTER_FLAG_OWNS_EDGE0 << 1)) ? -1 : 0;
  const long owns2 = (flags & (RASTER_FLAG_OWNS_EDGE0 << 2)) ? -1 : 0;
  const float3 viewZOverW = vload3(0, t->viewZOverW), invW = vload3(0, t->invW);
  const int8 column = (int8)(0, 1, 2, 3, 4, 5, 6, 7);
  const int8 inBox = (column >= (int)t->bbox[0] - origin.x) & (column <= (int)t->bbox[2] - origin.x);
  const int sx = rasterSample(origin.x);
  const long8 lane = (long8)(0, 1, 2, 3, 4, 5, 6, 7);
  const long8 step0 = lane * da0, step1 = lane * da1, step2 = lane * da2;
  for (int r = r0; r <= r1; ++r) {
    const int sy = rasterSample(origin.y + r);
    const long8 e0 = rasterEdgeAt(a0, b0, x0, y0, sx, sy) + step0, e1 = rasterEdgeAt(a1, b1, x1, y1, sx, sy) + step1;
    const long8 e2 = rasterEdgeAt(a2, b2, x2, y2, sx, sy) + step2;
    const int8 inside = inBox & convert_int8(RASTER_EDGE_PASSES(e0, owns0) & RASTER_EDGE_PASSES(e1, owns1) &
                                             RASTER_EDGE_PASSES(e2, owns2));
    fineKeepRow(r, inside, convert_float8(e0), convert_float8(e1), convert_float8(e2), viewZOverW, invW, id, farViewZ,
                origin, alpha, best, bestId);
  }
}

__kernel __attribute__((reqd_work_group_size(RASTER_WG_FINE, 1, 1))) void fine_raster(
    __global const RasterTriangle* tris, __global const uint* tileEntries, __global const uint* tileCount,
    __global const uint* tileOffset, __global const uint* tileMask, __global const AlphaTriangle* alphaTriangles,
    __global const AlphaMaterial* alphaMaterials, __global const uchar* alphaTexels, __global float* depth,
    __global uint* triangleId, __global uint* emptyTiles, __global uint* casterFree,
    __global const RasterCounters* counters, const RasterViewParams p) {
  const int index = get_global_id(0);
  const int tileRows = (p.rectY1 - 1) / RASTER_TILE_SIZE - p.tileY0 + 1;
  if (index >= p.tilesAcross * tileRows) return;  // padding of the last work-group
  if (!fineDraws(&p, index, tileMask)) return;    // left untouched
  uint offset, count;
  const int2 origin = fineTile(&p, index, tileCount, tileOffset, &offset, &count);
  // RasterTargets::keepEmptyTiles: a tile with no entries that held only the background at the last draw still does
  // (pcss on scenes/default.json at 640x360, 96 % of its 4096^2 map's tiles: the fine stage 6.9 -> 5.3 ms).
  const int tile = (origin.y >> RASTER_TILE_LOG2) * p.tilesX + (origin.x >> RASTER_TILE_LOG2);
  if (count != 0 && fineBeyondCasters(&p, counters, origin)) {  // only receivers there: the background
    uint casters = 0u;
    for (uint j = 0; j < count && casters == 0u; ++j)
      casters = ~tris[tileEntries[offset + j]].flags & RASTER_FLAG_NONCASTER;
    if (casters == 0u) count = 0;
  }
  if (count == 0 && p.casterTiles) casterFree[tile] = 1u;
  if (count == 0 && p.emptyTiles && emptyTiles[tile] != 0u) return;
  if (count == 0 && fineStoreEmptyTile(&p, origin, depth, triangleId)) {
    if (p.emptyTiles) emptyTiles[tile] = 1u;
    return;
  }
  if (p.emptyTiles) emptyTiles[tile] = 0u;  // drawn, or only partly inside the scissor
  float best[RASTER_TILE_PIXELS];
  uint bestId[RASTER_TILE_PIXELS];
  for (int i = 0; i < RASTER_TILE_PIXELS; ++i) best[i] = INFINITY, bestId[i] = RASTER_NO_TRIANGLE;
  uint casters = 0u;  // RASTER_FLAG_NONCASTER where a queue entry is a caster
  for (uint j = 0; j < count; ++j) {
    if (j + RASTER_FINE_PREFETCH < count) RASTER_PREFETCH_RECORD(&tris[tileEntries[offset + j + RASTER_FINE_PREFETCH]]);
    __global const RasterTriangle* t = &tris[tileEntries[offset + j]];
    const int r0 = max((int)t->bbox[1] - origin.y, 0), r1 = min((int)t->bbox[3] - origin.y, RASTER_TILE_SIZE - 1);
    const uint flags = t->flags;
    casters |= ~flags & RASTER_FLAG_NONCASTER;
    if ((flags & RASTER_FLAG_ALPHA) == 0) {
      fineTestRows(t, origin, r0, r1, p.farViewZ, (const FineAlphaRows*)0, best, bestId);
      continue;
    }
    FineAlphaRows alpha;
    alpha.p = &p, alpha.texels = alphaTexels;
    alpha.fragment = rasterAlphaFragment(&p, alphaTriangles, alphaMaterials, flags >> RASTER_FLAG_ALPHA_SHIFT);
    fineTestRows(t, origin, r0, r1, p.farViewZ, &alpha, best, bestId);
  }
  if (p.casterTiles) casterFree[tile] = casters == 0u;
  // A tile wholly inside the scissor whose depth is the view depth itself (the light maps): 8-wide rows, the
  // background selected per lane (vssm's 4096^2 map on scenes/default.json, every tile under the ground: the fine
  // stage 12.1 -> 10.5 ms; the same bits).
  if (p.depthMode == RASTER_DEPTH_VIEW_Z && fineTileInside(&p, origin)) {
    for (int r = 0; r < RASTER_TILE_SIZE; ++r) {
      const size_t row = (size_t)(origin.y + r) * p.width + (size_t)origin.x;
      const float8 b = vload8(r, best);
      const uint8 id = vload8(r, bestId);
      vstore8(select(b, (float8)(INFINITY), id == (uint8)(RASTER_NO_TRIANGLE)), 0, depth + row);
      if (!p.skipIds) vstore8(id, 0, triangleId + row);
    }
    return;
  }
  const int live0 = max(p.rectX0 - origin.x, 0), live1 = min(p.rectX1 - origin.x, RASTER_TILE_SIZE);
  for (int r = 0; r < RASTER_TILE_SIZE; ++r) {  // the row's pixels inside the scissor: [live0, live1)
    const int y = origin.y + r;
    if (y < p.rectY0 || y >= p.rectY1) continue;
    for (int i = live0; i < live1; ++i)
      fineStore(&p, origin.x + i, y, best[r * RASTER_TILE_SIZE + i], bestId[r * RASTER_TILE_SIZE + i], depth,
                triangleId);
  }
}

#endif
