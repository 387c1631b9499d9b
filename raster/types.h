// Records shared by the rasterizer's host code and kernels (valid OpenCL C 1.2 and C++20): the set-up triangle, the
// queue counters and the per-draw parameters (an alpha-tested triangle's texture data is kernels/shared/alpha.h's). Only 4- and 8-byte scalars,
// ordered largest first, so both compilers lay them out identically; the host static_asserts sizes and offsets.
#ifndef PENUMBRA_RASTER_TYPES_H
#define PENUMBRA_RASTER_TYPES_H

#include "kernels/shared/common.h"
#include "raster/constants.h"

#if PENUMBRA_HOST
typedef int64_t raster_long;
typedef uint64_t raster_ulong;
typedef uint16_t raster_ushort;
#else
typedef long raster_long;
typedef ulong raster_ulong;
typedef ushort raster_ushort;
#endif

// One triangle after setup (clipped, snapped, oriented counter-clockwise in window space), 64 bytes: one cache line
// on CPUs, where every consumer reads records in an order unrelated to the buffer's. Edge k runs from vertex k to
// vertex j = k+1 (mod 3); its edge function over subpixel coordinates is
//   e_k(x, y) = a_k (x - x[k]) + b_k (y - y[k]),   a_k = y[k] - y[j],   b_k = x[j] - x[k]
// (raster/coverage.h), exact in 64 bits, positive inside; the vertex opposite edge k has barycentric weight
// e_k / sum(e). The vertices are stored rather than the edges' a, b, c (48 bytes): the coefficients are differences
// of them, so every consumer gets the same integers as before with a few subtractions and no rounding.
// A sample is covered when every e_k > 0, or e_k == 0 on an edge that owns it (top-left rule).
typedef struct {
  int x[3], y[3];         // snapped vertices, subpixels (|x|, |y| <= RASTER_COORD_LIMIT)
  float invW[3];          // 1 / w_clip of the vertex opposite edge k
  float viewZOverW[3];    // -z_eye / w_clip of the vertex opposite edge k (eye units)
  uint triangleId;        // index into RasterGeometry::triangles
  uint flags;  // RASTER_FLAG_VALID | RASTER_FLAG_OWNS_EDGE0 << k | RASTER_FLAG_NONCASTER | RASTER_FLAG_ALPHA | alpha
               // index << 6
  raster_ushort bbox[4];  // candidate pixels: x0, y0, x1, y1 inclusive, inside the scissor
} RasterTriangle;

#if !PENUMBRA_HOST
// Queues hold record indices in an order unrelated to the record buffer's, so on a CPU nearly every record read
// misses the caches; the CPU layouts (RASTER_WG_FINE > 0, RASTER_WG_COARSE > 0) prefetch the record a few queue
// entries ahead. One line suffices: records are 64 bytes and buffers are at least 64-byte aligned
// (CL_DEVICE_MEM_BASE_ADDR_ALIGN). Clang's builtin through an integer: CPU devices have one flat address space
// (OpenCL's prefetch() is a no-op in PoCL). Never used by the GPU layouts.
#if defined(__clang__)
#define RASTER_PREFETCH_RECORD(record) __builtin_prefetch((const void*)(size_t)(record))
#else
#define RASTER_PREFETCH_RECORD(record) ((void)0)
#endif
#endif

// Queue counters: kernels count every request, write only below the capacity; the host grows and re-runs.
typedef struct {
  raster_ulong binEntries;   // bin queue entries requested (sum over bins, from the scan)
  raster_ulong tileEntries;  // tile queue entries requested (sum over tiles, from the scan)
  uint extraTriangles;       // set-up records requested beyond one per input triangle (clipping fans)
  uint setUp;                // records that are drawn (valid) after clipping, culling and dropping
  // RasterViewParams::casterTiles: the union of the casters' records' candidate boxes (bin_count), kept so that zero
  // is empty and every update is an atomic_max: [0] RASTER_CASTER_BOX_FLIP - x0, [1] RASTER_CASTER_BOX_FLIP - y0,
  // [2] x1 + 1, [3] y1 + 1 (pixels, x1 and y1 inclusive); all 0 while no caster is drawn (rasterCasterBox).
  uint casterBox[4];
  uint pad[6];  // 64 bytes: a size clEnqueueFillBuffer takes as its pattern
} RasterCounters;

// casterBox's flipped minima: above every pixel coordinate (bbox entries are 16 bits).
#define RASTER_CASTER_BOX_FLIP 0x10000u

// Edge k of RasterCounters::casterBox decoded (`stored` its entry k) and widened to whole tiles: x0, y0 rounded down,
// x1, y1 (exclusive) up; the box is empty (all 0) where entry 2 is 0. Shared by fine.cl and Rasterizer::draw
// (RasterTargets::casterBox), so that both read the same box.
static inline int rasterCasterBoxEdge(uint stored, int k) {
  const int tileMask = ~(RASTER_TILE_SIZE - 1);
  return k < 2 ? (int)(RASTER_CASTER_BOX_FLIP - stored) & tileMask : ((int)stored + RASTER_TILE_SIZE - 1) & tileMask;
}

// Everything a draw's kernels need, passed by value. Pixel rectangles are [x0, x1) x [y0, y1).
typedef struct {
  float clip[16];     // world -> clip, column-major (the float matrix the snapping spec starts from)
  float invView[12];  // eye -> world: rotation columns 0..2, translation column 3 (x, y, z each)
  // Projection terms of the separable form (x_c = P00 x + P20 z + P30, y_c = P11 y + P21 z + P31,
  // z_c = P22 z + P32, w_c = P23 z + P33, z = z_eye), for depth conversion and pixel rays.
  float p00, p11, p20, p21, p30, p31, p22, p32, p23, p33;
  float viewZFromClip[3];              // separable: -z_eye = [0] z_c + [1] w_c + [2]
  float farViewZ;                      // fragments with -z_eye > farViewZ are discarded (the far plane)
  float viewZGeneral[4];               // general: -z_eye = [0] x_c + [1] y_c + [2] z_c + [3] w_c (row of P^-1)
  float guardX, guardY;                // guard-band planes |x_c| <= guardX w_c, |y_c| <= guardY w_c
  int width, height;                   // viewport, pixels
  int rectX0, rectY0, rectX1, rectY1;  // scissor clamped to the viewport, pixels
  int tilesX, tilesY;                  // tile grid over the viewport
  int binsX, binsY;                    // bin grid over the viewport
  int binX0, binY0, binsAcross;        // launched bins: those overlapping the scissor, row by row
  int tileX0, tileY0, tilesAcross;     // launched tiles: those overlapping the scissor, row by row
  int depthMode;                       // RASTER_DEPTH_*
  int cullBackFaces;                   // 1: drop triangles clockwise in window space
  uint triangleCount;                  // input triangles (RasterGeometry::triangles)
  uint vertexCount;                    // input vertices
  uint extraCapacity;                  // set-up records beyond triangleCount
  uint binCapacity;                    // bin queue entries
  uint tileCapacity;                   // tile queue entries
  int generalProjection;               // 1: a general projective matrix (kViewZ only): viewZGeneral, no far plane
  int tileMasked;                      // 1: only tiles whose tile-mask entry is nonzero are drawn (RasterView)
  int triangleBits;                    // 1: setup reads the per-triangle material bits (RASTER_TRI_*)
  int cullSingleSided;                 // 1: drop clockwise triangles whose bits say RASTER_TRI_SINGLE_SIDED
  int conservative;                    // 1: tile lists only (Rasterizer::drawTileLists): dilated boxes and tests, no fine
  int solidSides;                      // 1: setup reads the per-triangle RASTER_CULL_* codes (RasterView)
  int skipIds;                         // 1: fine writes depth only (RasterView::writeTriangleIds false)
  uint casterSource;                   // RASTER_CASTERS_*: setup leaves out triangles that shade no point of the box
  float casterTolerance;               // world units a box point may lie behind a left-out triangle's plane
  float casterLight[4];                // ball: centre xyz, radius; cone: unit direction towards the light, sin(angle)
  float casterBoxCentre[4];            // the box every receiver lies in (the geometry's bounds): centre xyz
  float casterBoxHalf[4];              // and half-extent xyz
  int emptyTiles;  // 1 (fine, CPU layout): emptyTiles[tile] records whether the tile holds only the background, and
                   // a tile with no entries that held only the background is not rewritten (RasterTargets)
  int casterTiles;  // 1 (with casterSource): setup keeps what casts nothing, flagged RASTER_FLAG_NONCASTER, and fine
                    // records casterFree[tile]: whether the tile's queue holds no caster
                    // (RasterView::recordCasterTiles)
  int receiverReach;  // >= 0 (with casterTiles): fine leaves a tile whose queue holds no caster and that lies farther
                      // than this many pixels from the casters' box (RasterCounters::casterBox, widened to whole tiles)
                      // as the background, undrawn (RasterView::receiverReach); -1: every tile is drawn
  uint padEnd;
} RasterViewParams;

#if PENUMBRA_HOST
#include <cstddef>
static_assert(sizeof(RasterTriangle) == 64, "RasterTriangle layout must match OpenCL C (and fill one cache line)");
static_assert(offsetof(RasterTriangle, y) == 12 && offsetof(RasterTriangle, invW) == 24);
static_assert(offsetof(RasterTriangle, triangleId) == 48 && offsetof(RasterTriangle, bbox) == 56);
static_assert(sizeof(RasterCounters) == 64 && offsetof(RasterCounters, extraTriangles) == 16);
static_assert(offsetof(RasterCounters, casterBox) == 24);
static_assert(offsetof(RasterViewParams, p00) == 112 && offsetof(RasterViewParams, viewZGeneral) == 168);
static_assert(offsetof(RasterViewParams, width) == 192 && offsetof(RasterViewParams, generalProjection) == 284);
static_assert(offsetof(RasterViewParams, tileMasked) == 288 && offsetof(RasterViewParams, cullSingleSided) == 296);
static_assert(offsetof(RasterViewParams, conservative) == 300 && offsetof(RasterViewParams, solidSides) == 304);
static_assert(offsetof(RasterViewParams, casterSource) == 312 && offsetof(RasterViewParams, casterBoxHalf) == 352);
static_assert(offsetof(RasterViewParams, emptyTiles) == 368 && offsetof(RasterViewParams, casterTiles) == 372);
static_assert(offsetof(RasterViewParams, receiverReach) == 376);
static_assert(sizeof(RasterViewParams) == 384, "RasterViewParams layout must match OpenCL C");
#endif

#endif
