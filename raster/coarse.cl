// Coarse rasterization, stage 3 of 4 (Laine & Karras 2011, section 4.3): one work-group per 128x128-pixel bin,
// whose RASTER_COARSE_WG work-items walk the bin queue triangle by triangle and enter each triangle into the
// queues of the 8x8 tiles whose samples it may cover. Work is proportional to the entries made, not to
// tiles x triangles, so a bin crowded with small triangles stays cheap. Two passes keep memory bounded without
// allocation: coarse_count counts entries per tile in local memory (local atomics) and writes each tile's count
// and the bin's total (bin_scan then places bins in the tile queue); coarse_fill scans the counts inside the bin
// and writes the entries below tileCapacity. Afterwards work-item i owns tile i of the bin. The order inside a
// tile queue depends on local atomics, which the fine stage's total depth order makes irrelevant.
#include "raster/constants.h"
#include "raster/coverage.h"
#include "raster/types.h"

typedef struct {
  int bin;             // index in the bin grid
  int tileX0, tileY0;  // the bin's first tile
  int tile;            // this work-item's tile in the tile grid, -1 outside the viewport
  uint begin, count;   // the bin's queue range, cut to the capacity
} CoarseBin;

// Bin `item` of the launched bins; its tiles start at (tileX0, tileY0) in the tile grid. tile is left -1.
static CoarseBin coarseBinOf(const RasterViewParams* p, int item, __global const uint* binCount,
                             __global const uint* binOffset) {
  CoarseBin b;
  const int bx = p->binX0 + item % p->binsAcross, by = p->binY0 + item / p->binsAcross;
  b.bin = by * p->binsX + bx;
  b.tileX0 = bx << RASTER_BIN_LOG2, b.tileY0 = by << RASTER_BIN_LOG2;
  b.tile = -1;
  const uint offset = binOffset[b.bin];
  b.begin = offset;
  b.count = offset < p->binCapacity ? min(binCount[b.bin], p->binCapacity - offset) : 0;
  return b;
}

// Tile index in the grid of local tile i of bin b, -1 outside the viewport.
static int coarseTileOf(const RasterViewParams* p, const CoarseBin* b, int i) {
  const int tx = b->tileX0 + (i & (RASTER_BIN_TILES - 1)), ty = b->tileY0 + (i >> RASTER_BIN_LOG2);
  return tx < p->tilesX && ty < p->tilesY ? ty * p->tilesX + tx : -1;
}

// The work-group's bin (a group per bin), with this work-item's tile.
static CoarseBin coarseBin(const RasterViewParams* p, __global const uint* binCount, __global const uint* binOffset) {
  CoarseBin b = coarseBinOf(p, get_group_id(0), binCount, binOffset);
  b.tile = coarseTileOf(p, &b, get_local_id(0));
  return b;
}

#define RASTER_COARSE_PREFETCH 4  // bin queue entries ahead whose record the CPU layout prefetches (types.h)

// Calls BODY(localTile) for every tile of bin `b` whose samples the record `t` may cover and that the view draws
// (its tile-mask entry nonzero, when the view has a mask). The candidate box lies inside the scissor, so cutting
// each tile to the box keeps the test inside the scissor too.
#define COARSE_FOR_EACH_TILE(t, b, p, mask, BODY)                                                        \
  do {                                                                                                   \
    const int tx0_ = max((int)(t).bbox[0] >> RASTER_TILE_LOG2, (b).tileX0);                              \
    const int ty0_ = max((int)(t).bbox[1] >> RASTER_TILE_LOG2, (b).tileY0);                              \
    const int tx1_ = min((int)(t).bbox[2] >> RASTER_TILE_LOG2, (b).tileX0 + RASTER_BIN_TILES - 1);       \
    const int ty1_ = min((int)(t).bbox[3] >> RASTER_TILE_LOG2, (b).tileY0 + RASTER_BIN_TILES - 1);       \
    for (int ty_ = ty0_; ty_ <= ty1_; ++ty_)                                                             \
      for (int tx_ = tx0_; tx_ <= tx1_; ++tx_) {                                                         \
        if ((p).tileMasked != 0 && (mask)[ty_ * (p).tilesX + tx_] == 0) continue;                        \
        const int px_ = tx_ << RASTER_TILE_LOG2, py_ = ty_ << RASTER_TILE_LOG2;                          \
        bool hit_;                                                                                       \
        RASTER_RECT_OVERLAPS(t, (p).conservative, px_, py_, px_ + RASTER_TILE_SIZE - 1, py_ + RASTER_TILE_SIZE - 1, \
                             hit_);                                                                      \
        if (hit_) BODY(((ty_ - (b).tileY0) << RASTER_BIN_LOG2) + (tx_ - (b).tileX0));                    \
      }                                                                                                  \
  } while (0)

// Inclusive work-group scan of `value` (Hillis-Steele in local memory); every work-item must call it.
static ulong coarseScan(ulong value, __local ulong* sums) {
  const uint lid = get_local_id(0);
  barrier(CLK_LOCAL_MEM_FENCE);
  sums[lid] = value;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint step = 1; step < RASTER_COARSE_WG; step <<= 1) {
    ulong add = lid >= step ? sums[lid - step] : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    sums[lid] += add;
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  return sums[lid];
}

#ifndef RASTER_WG_COARSE
#define RASTER_WG_COARSE 0
#endif

#if RASTER_WG_COARSE == 0
// Writes tileCount[tile] for the bin's tiles inside the viewport and binTileTotal[bin] (saturated to 2^32 - 1).
__kernel __attribute__((reqd_work_group_size(RASTER_COARSE_WG, 1, 1))) void coarse_count(
    __global const RasterTriangle* tris, __global const uint* binEntries, __global const uint* binCount,
    __global const uint* binOffset, __global const uint* tileMask, __global uint* tileCount, __global uint* binTileTotal, const RasterViewParams p) {
  __local uint hits[RASTER_COARSE_WG];
  __local ulong sums[RASTER_COARSE_WG];
  const CoarseBin b = coarseBin(&p, binCount, binOffset);
  const uint lid = get_local_id(0);
  hits[lid] = 0;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint j = lid; j < b.count; j += RASTER_COARSE_WG) {
    const RasterTriangle t = tris[binEntries[b.begin + j]];
#define COARSE_COUNT_ONE(localTile) atomic_inc(&hits[localTile])
    COARSE_FOR_EACH_TILE(t, b, p, tileMask, COARSE_COUNT_ONE);
#undef COARSE_COUNT_ONE
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  const uint own = hits[lid];
  if (b.tile >= 0) tileCount[b.tile] = own;
  const ulong total = coarseScan(own, sums);
  if (lid == RASTER_COARSE_WG - 1) binTileTotal[b.bin] = total < RASTER_SATURATED ? (uint)total : RASTER_SATURATED;
}

// Writes tileOffset[tile] = binTileBase[bin] + the entries of the bin's tiles before it, and the tile's entries
// (indices of set-up records; conservative draws: their triangle ids) at tileEntries[tileOffset ...], below
// tileCapacity.
__kernel __attribute__((reqd_work_group_size(RASTER_COARSE_WG, 1, 1))) void coarse_fill(
    __global const RasterTriangle* tris, __global const uint* binEntries, __global const uint* binCount,
    __global const uint* binOffset, __global const uint* tileMask, __global const uint* tileCount,
    __global const uint* binTileBase,
    __global uint* tileOffset, __global uint* tileEntries, const RasterViewParams p) {
  __local uint base[RASTER_COARSE_WG], cursor[RASTER_COARSE_WG];
  __local ulong sums[RASTER_COARSE_WG];
  const CoarseBin b = coarseBin(&p, binCount, binOffset);
  const uint lid = get_local_id(0);
  const uint own = b.tile >= 0 ? tileCount[b.tile] : 0;
  const ulong before = coarseScan(own, sums) - own + binTileBase[b.bin];
  const uint offset = before < RASTER_SATURATED ? (uint)before : RASTER_SATURATED;
  if (b.tile >= 0) tileOffset[b.tile] = offset;
  base[lid] = offset;
  cursor[lid] = 0;
  barrier(CLK_LOCAL_MEM_FENCE);
  const uint capacity = p.tileCapacity;
  for (uint j = lid; j < b.count; j += RASTER_COARSE_WG) {
    const uint index = binEntries[b.begin + j];
    const RasterTriangle t = tris[index];
#define COARSE_FILL_ONE(localTile)                                                  \
  do {                                                                              \
    const uint slot_ = atomic_inc(&cursor[localTile]), at_ = base[localTile];       \
    if (at_ < capacity && slot_ < capacity - at_) tileEntries[at_ + slot_] = entry; \
  } while (0)
    const uint entry = p.conservative ? t.triangleId : index;
    COARSE_FOR_EACH_TILE(t, b, p, tileMask, COARSE_FILL_ONE);
#undef COARSE_FILL_ONE
  }
}

#else
// ---- CPU layout (RASTER_WG_COARSE > 0, raster/constants.h): one work-item per bin ------------------------------
// A work-item walks its whole bin queue in order (bin_fill left it close to record order) and counts into private
// arrays: no local atomics, and every tile queue comes out in bin queue order. coarse_count also notes per bin
// queue entry the one tile it hits (most triangles of dense meshes hit one tile of a bin) in binTiles, so that
// coarse_fill re-reads and re-tests the record only for entries that hit several tiles.
#define COARSE_NO_TILE 0xfffeu        // binTiles: the entry hits no tile of the bin
#define COARSE_SEVERAL_TILES 0xffffu  // binTiles: the entry hits several tiles (test again)

#if RASTER_BIN_TILES != 16
#error "coarseRowHits holds a bin's tile row in 16-wide vectors"
#endif
#define COARSE_LANES (int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15)  // a bin row's tiles, left to right

// RASTER_RECT_OVERLAPS for the 16 tiles of bin row `ty` (tile grid) at once, as a lane mask (-1: the record may cover a
// sample of that tile), lanes outside [tx0, tx1] (the record's candidate tiles) 0: the same rectangles (each tile cut
// to the candidate box) and the same corner of each edge, in 64-bit lanes, so the tiles hit are exactly the scalar
// test's. The scalar loop's branches mispredict where boxes span several tiles (scenes/default.json's 4096^2 light map:
// 819 k tile tests for 329 k entries); a row at a time took coarse_count + coarse_fill there from 7.5 to 3.2 ms
// (docs/performance.md). Boxes one tile wide (most triangles of dense meshes), draws with a tile mask and conservative
// tests keep the scalar loop (COARSE_FOR_EACH_TILE): for one tile the row's 16 lanes cost more.
static inline int16 coarseRowHits(const RasterTriangle* t, int tileX0, int ty, int tx0, int tx1) {
  const int16 tx = tileX0 + COARSE_LANES;
  const int16 px = tx << RASTER_TILE_LOG2;
  const int16 ox0 = max((int16)((int)t->bbox[0]), px), ox1 = min((int16)((int)t->bbox[2]), px + (RASTER_TILE_SIZE - 1));
  const int py = ty << RASTER_TILE_LOG2;
  const int oy0 = max((int)t->bbox[1], py), oy1 = min((int)t->bbox[3], py + RASTER_TILE_SIZE - 1);
  int16 hit = (tx >= tx0) & (tx <= tx1);
  for (int k = 0; k < 3; ++k) {
    const int a = RASTER_EDGE_A(*t, k), b = RASTER_EDGE_B(*t, k);
    const int16 x = ((a > 0 ? ox1 : ox0) << RASTER_SUBPIXEL_LOG2) + RASTER_SAMPLE_OFFSET;
    const long ey = (long)b * (long)(rasterSample(b > 0 ? oy1 : oy0) - t->y[k]);
    const long16 e = (long16)((long)a) * convert_long16(x - t->x[k]) + ey;
    const long owns = (t->flags & (RASTER_FLAG_OWNS_EDGE0 << k)) ? -1 : 0;
    hit &= convert_int16(RASTER_EDGE_PASSES(e, owns));
  }
  return hit;
}

// The sum of a vector's lanes.
static inline int coarseSum16(int16 v) {
  const int8 a = v.lo + v.hi;
  const int4 b = a.lo + a.hi;
  const int2 c = b.lo + b.hi;
  return c.x + c.y;
}

// Whether a record whose candidate columns are [tx0, tx1] is tested a bin row at a time (coarseRowHits): boxes more
// than a tile wide, in draws with neither a tile mask nor conservative tests. coarse_count and coarse_fill ask alike.
static inline bool coarseByRows(const RasterViewParams* p, int tx0, int tx1) {
  return p->tileMasked == 0 && p->conservative == 0 && tx1 > tx0;
}

// The candidate tiles of record `t` inside bin `b`: columns [*tx0, *tx1], rows [*ty0, *ty1] of the tile grid.
static inline void coarseCandidates(const RasterTriangle* t, const CoarseBin* b, int* tx0, int* ty0, int* tx1,
                                    int* ty1) {
  *tx0 = max((int)t->bbox[0] >> RASTER_TILE_LOG2, b->tileX0);
  *ty0 = max((int)t->bbox[1] >> RASTER_TILE_LOG2, b->tileY0);
  *tx1 = min((int)t->bbox[2] >> RASTER_TILE_LOG2, b->tileX0 + RASTER_BIN_TILES - 1);
  *ty1 = min((int)t->bbox[3] >> RASTER_TILE_LOG2, b->tileY0 + RASTER_BIN_TILES - 1);
}

// The same results as the layout above, over `bins` launched bins; binTiles[binCapacity] receives each entry's tile code.
__kernel __attribute__((reqd_work_group_size(RASTER_WG_COARSE, 1, 1))) void coarse_count(
    __global const RasterTriangle* tris, __global const uint* binEntries, __global const uint* binCount,
    __global const uint* binOffset, __global const uint* tileMask, __global uint* tileCount, __global uint* binTileTotal, __global ushort* binTiles,
    const RasterViewParams p, uint bins) {
  if (get_global_id(0) >= bins) return;
  const CoarseBin b = coarseBinOf(&p, get_global_id(0), binCount, binOffset);
  uint hits[RASTER_BIN_TILE_COUNT];
  for (int i = 0; i < RASTER_BIN_TILE_COUNT; ++i) hits[i] = 0;
  for (uint j = 0; j < b.count; ++j) {
    if (j + RASTER_COARSE_PREFETCH < b.count)
      RASTER_PREFETCH_RECORD(&tris[binEntries[b.begin + j + RASTER_COARSE_PREFETCH]]);
    const RasterTriangle t = tris[binEntries[b.begin + j]];
    uint code = COARSE_NO_TILE;
    int tx0, ty0, tx1, ty1;
    coarseCandidates(&t, &b, &tx0, &ty0, &tx1, &ty1);
    if (coarseByRows(&p, tx0, tx1)) {
      int n = 0;
      for (int ty = ty0; ty <= ty1; ++ty) {
        const int16 hit = coarseRowHits(&t, b.tileX0, ty, tx0, tx1);
        const int row = (ty - b.tileY0) << RASTER_BIN_LOG2, rowHits = -coarseSum16(hit);
        if (rowHits == 0) continue;
        vstore16(vload16(0, hits + row) - as_uint16(hit), 0, hits + row);  // a hit lane is -1
        if (n == 0 && rowHits == 1) code = (uint)(row + coarseSum16(hit & COARSE_LANES));
        n += rowHits;
      }
      if (n > 1) code = COARSE_SEVERAL_TILES;
    } else {
#define COARSE_COUNT_ONE(localTile)                                              \
  do {                                                                           \
    ++hits[localTile];                                                           \
    code = code == COARSE_NO_TILE ? (uint)(localTile) : COARSE_SEVERAL_TILES;    \
  } while (0)
      COARSE_FOR_EACH_TILE(t, b, p, tileMask, COARSE_COUNT_ONE);
#undef COARSE_COUNT_ONE
    }
    binTiles[b.begin + j] = (ushort)code;
  }
  ulong total = 0;
  for (int i = 0; i < RASTER_BIN_TILE_COUNT; ++i) {
    const int tile = coarseTileOf(&p, &b, i);
    if (tile >= 0) tileCount[tile] = hits[i];
    total += hits[i];
  }
  binTileTotal[b.bin] = total < RASTER_SATURATED ? (uint)total : RASTER_SATURATED;
}

// The same results as the layout above, over `bins` launched bins, from the tile codes coarse_count left in binTiles.
__kernel __attribute__((reqd_work_group_size(RASTER_WG_COARSE, 1, 1))) void coarse_fill(
    __global const RasterTriangle* tris, __global const uint* binEntries, __global const uint* binCount,
    __global const uint* binOffset, __global const uint* tileMask, __global const uint* tileCount,
    __global const uint* binTileBase,
    __global uint* tileOffset, __global uint* tileEntries, __global const ushort* binTiles, const RasterViewParams p,
    uint bins) {
  if (get_global_id(0) >= bins) return;
  const CoarseBin b = coarseBinOf(&p, get_global_id(0), binCount, binOffset);
  uint base[RASTER_BIN_TILE_COUNT], cursor[RASTER_BIN_TILE_COUNT];
  ulong before = binTileBase[b.bin];
  for (int i = 0; i < RASTER_BIN_TILE_COUNT; ++i) {
    const int tile = coarseTileOf(&p, &b, i);
    const uint offset = before < RASTER_SATURATED ? (uint)before : RASTER_SATURATED;
    if (tile >= 0) tileOffset[tile] = offset, before += tileCount[tile];
    base[i] = offset, cursor[i] = 0;
  }
  const uint capacity = p.tileCapacity;
#define COARSE_FILL_ONE(localTile)                                                  \
  do {                                                                              \
    const uint slot_ = cursor[localTile]++, at_ = base[localTile];                  \
    if (at_ < capacity && slot_ < capacity - at_) tileEntries[at_ + slot_] = entry; \
  } while (0)
  for (uint j = 0; j < b.count; ++j) {
    const uint ahead = j + RASTER_COARSE_PREFETCH;
    if (ahead < b.count && binTiles[b.begin + ahead] == COARSE_SEVERAL_TILES)
      RASTER_PREFETCH_RECORD(&tris[binEntries[b.begin + ahead]]);
    const uint index = binEntries[b.begin + j], code = binTiles[b.begin + j];
    const uint entry = p.conservative ? tris[index].triangleId : index;
    if (code < RASTER_BIN_TILE_COUNT) {
      COARSE_FILL_ONE(code);
    } else if (code == COARSE_SEVERAL_TILES) {
      const RasterTriangle t = tris[index];
      int tx0, ty0, tx1, ty1;
      coarseCandidates(&t, &b, &tx0, &ty0, &tx1, &ty1);
      if (coarseByRows(&p, tx0, tx1)) {
        for (int ty = ty0; ty <= ty1; ++ty) {
          // The row's hit lanes as bits, visited lowest first.
          uint bits = (uint)coarseSum16(coarseRowHits(&t, b.tileX0, ty, tx0, tx1) & ((int16)(1) << COARSE_LANES));
          for (; bits != 0; bits &= bits - 1)
            COARSE_FILL_ONE(((ty - b.tileY0) << RASTER_BIN_LOG2) + 31 - (int)clz(bits & (0u - bits)));
        }
      } else {
        COARSE_FOR_EACH_TILE(t, b, p, tileMask, COARSE_FILL_ONE);
      }
    }
  }
#undef COARSE_FILL_ONE
}
#endif
