// Fitted virtual shadow maps (Giegl & Wimmer, "Fitted Virtual Shadow Maps", GI 2007; Luksch sec. 8): a virtual map
// of tile * 2^L texels a side, of which only the quadtree tiles the receivers need are drawn, each a tile x tile map
// of its own (host/techniques/fvsm.cpp). fvsm_request measures what every covered pixel needs: its screen steps to
// on-plane neighbours in the base map's texels (the root tile's, sc_footprint, as Luksch's optimal confidence and
// pssm's resolution error), the level l at which one step spans at least one texel of the quality xi (step * 2^l >=
// xi), per cell of the finest level's grid as a histogram, from which the host rejects outliers and builds the
// quadtree. fvsm_visibility looks every pixel up through the page table (the finest grid's cells -> the drawn tile
// covering them) and runs sm's hard test in that tile, its bias in that tile's texel footprint; with exact edges, a
// pixel whose texels disagree is decided by its shadow ray against their triangles (kernels/shared/exact_edges.h).
#define SHADOW_NORMAL_OFFSET_SCALED 0  // the whole normal offset at every angle (kernels/shared/shadow_common.h)
#include "kernels/shared/exact_edges.h"
#include "kernels/shared/fvsm.h"
#include "kernels/shared/shade.h"
#include "kernels/shared/shadow_common.h"

// The cell of the finest grid (cells x cells over the base map) holding base texel t, or -1 outside the base map.
inline int fvsm_cell(__constant const LightViewGpu* base, float3 t, uint cells) {
  if (!(t.z > 0.0f && t.x >= 0.0f && t.y >= 0.0f && t.x < (float)base->width && t.y < (float)base->height)) return -1;
  const uint cx = min((uint)(t.x * (float)cells / (float)base->width), cells - 1);
  const uint cy = min((uint)(t.y * (float)cells / (float)base->height), cells - 1);
  return (int)(cy * cells + cx);
}

// Pixel i's world position and its cell in the finest grid; -1 for background, pixels past the G-buffer and pixels
// outside the base map.
inline int fvsm_pixel(__global const float4* position, uint i, uint count, __constant const LightViewGpu* base,
                      uint cells, float4* p) {
  if (i >= count) return -1;
  *p = position[i];
  return p->w == 0.0f ? -1 : fvsm_cell(base, lv_project(base, p->xyz), cells);
}

// histogram[cell * (maxLevel + 1) + level] counts the covered pixels of the cell that need that level (0 for those
// without an on-plane neighbour, whose need is unknown). Zero on entry.
__kernel void fvsm_request(__global const float4* position, __global const float4* normal, uint width, uint height,
                           __constant const LightViewGpu* base, uint cells, int maxLevel, float quality,
                           __global uint* histogram) {
  const uint i = get_global_id(0);
  float4 p;
  const int cell = fvsm_pixel(position, i, width * height, base, cells, &p);
  if (cell < 0) return;
  const Footprint f = sc_footprint(position, base, width, height, i, p.xyz, normal[i].xyz);
  const float lx = length(f.dx.xy), ly = length(f.dy.xy);
  const float step = lx > 0.0f && ly > 0.0f ? min(lx, ly) : max(lx, ly);
  int level = 0;
  if (step > 0.0f && isfinite(step)) level = clamp((int)ceil(log2(quality / step)), 0, maxLevel);
  atomic_inc(&histogram[(uint)cell * (uint)(maxLevel + 1) + (uint)level]);
}

// sm's hard test of every covered pixel whose page-table tile is one of this batch's (leaves begin .. begin + count
// - 1, their views in `views`); the tiles' depths lie one after the other in `atlas`, tile * tile texels each, and
// their triangle ids so in `atlasIds` (read with exact edges only). pixelTriangle is the G-buffer's triangle per pixel,
// positions .. alphaTexels the scene's (raster::SceneBuffers). level[i] gets the tile's quadtree level (the debug
// channel). Other pixels are left as they are (1: lit).
__kernel void fvsm_visibility(__global const float4* position, __global const float4* normal,
                              __global const float* atlas, __global const uint* atlasIds,
                              __constant const LightViewGpu* base, ShadeFrame f, __constant const LightViewGpu* views,
                              __global const uint* page, __global const int* leafLevels, FvsmBatch b,
                              __global const uint* pixelTriangle, __global const float* positions,
                              __global const uint* triangles, __global const uint* alphaIndex,
                              __global const AlphaTriangle* alphaTriangles,
                              __global const AlphaMaterial* alphaMaterials, __global const uchar* alphaTexels,
                              __global float* visibility, __global float* level) {
  const uint width = f.width, height = f.height, begin = b.begin, count = b.count, cells = b.cells;
  const uint i = get_global_id(0);
  float4 p;
  const int cell = fvsm_pixel(position, i, width * height, base, cells, &p);
  if (cell < 0) return;
  const uint leaf = page[cell];
  if (leaf == FVSM_NO_LEAF || leaf < begin || leaf - begin >= count) return;
  __constant const LightViewGpu* lv = views + (leaf - begin);
  const ShadowBias bias = {f.biasConstant, f.biasSlope, f.normalOffset};
  const float3 n = normal[i].xyz;
  ReceiverPlane rp;
  const Receiver r = sc_hard_receiver(f.receiverPlane, position, lv, width, height, i, p.xyz, n, bias, &rp);
  float lit = 1.0f;
  if (r.valid) {
    const size_t first = (size_t)leaf * (size_t)lv->width * (size_t)lv->height;
    lit = sc_hard_lit(atlas + first, lv, r, rp, f.biasConstant * r.texel);
    if (b.exactEdges) {
      const EdgeScene s = {positions,
                           triangles,
                           b.triangleCount,
                           {alphaIndex, alphaTriangles, alphaMaterials, alphaTexels, b.alphaTested},
                           b.sceneRadius};
      const float exact =
          edge_exact_lit(atlas + first, atlasIds + first, lv, p.xyz, pixelTriangle[i], n, rp,
                         rp.valid ? f.biasConstant * r.texel : r.bias, lit, convert_int2(floor(r.uv)), false, &s);
      if (exact >= 0.0f) lit = exact;
    }
  }
  visibility[i] = lit;
  level[i] = (float)leafLevels[leaf];
}
