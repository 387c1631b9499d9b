// Exact hard shadows by an irregular z-buffer (Johnson, Lee, Burns & Mark 2005; in compute after Wyman, Hoetzlein &
// Lefohn 2015, "Frustum-traced raster shadows"). The camera's G-buffer samples (one per pixel, or 4 / 8 / 32 sub-pixel
// samples on the pixel's surface plane) are binned into a light-space grid of 8x8-texel cells, the rasterizer's tiles:
// izb_bin finds each sample's cell and counts the cells, izb_scan_* place the cells, izb_scatter sorts the samples by
// cell (a counting sort). The host then draws every caster conservatively over the grid (Rasterizer::drawTileLists,
// only the cells that hold samples), and izb_test tests each sample exactly against the triangles listed for its cell:
// the shadow ray of the Embree reference (tools/reference/tracer.cpp: the origin moved off the surface along its
// geometric normal, towards the light's centre, by SHADOW_RAY_OFFSET times max(|p|_inf, scene radius); to the light's
// point, or against a directional light's axis), with a watertight ray-triangle test and the alpha masks of
// kernels/shared/alpha.h (kernels/shared/shadow_ray.h). A ray from a sample to a spot or point light (the light grid's
// centre of projection) or along a directional light's axis projects to one point of the grid, so the triangles that
// can block it are exactly those whose projection covers the point its origin projects to. izb_resolve turns the
// blocked samples into visibility. Under an area light, izb_soft_* (below) take the place of the conservative draw and
// izb_test.
#include "kernels/shared/alpha.h"
#include "kernels/shared/izb.h"
#include "kernels/shared/light_view.h"
#include "kernels/shared/shadow_ray.h"

// The same arithmetic on every device: no fused multiply-adds in the sample positions either (shadow_ray.h sets it
// for the ray test too).
#pragma OPENCL FP_CONTRACT OFF

__constant float kIzbPattern[2 * IZB_PATTERN_ENTRIES] = IZB_PATTERN_VALUES;

// clip -> world of NDC (x, y, z), through the camera's inverse.
static float3 izb_unproject(const IzbFrame* f, float x, float y, float z) {
  const float4 c = (float4)(x, y, z, 1.0f);
  const float4 w = (float4)(dot(vload4(0, f->cameraInverse), c), dot(vload4(1, f->cameraInverse), c),
                            dot(vload4(2, f->cameraInverse), c), dot(vload4(3, f->cameraInverse), c));
  return w.xyz / w.w;
}

// Sample `s` of pixel `pixel` at world point p with geometric normal n: p itself for the centre sample; else the point
// where the camera ray through the sub-pixel offset meets the surface's plane, or p where that point is not within
// four pixel footprints of p (grazing planes).
static float3 izb_sample_point(const IzbFrame* f, uint pixel, int s, float3 p, float3 n) {
  const float2 offset = vload2(f->pattern + s, kIzbPattern);
  if (offset.x == 0.0f && offset.y == 0.0f) return p;
  const float px = (float)(pixel % f->width) + 0.5f, py = (float)(pixel / f->width) + 0.5f;
  const float sx = 2.0f / (float)f->width, sy = 2.0f / (float)f->height;
  const float3 a0 = izb_unproject(f, px * sx - 1.0f, py * sy - 1.0f, -1.0f);
  const float3 b0 = izb_unproject(f, px * sx - 1.0f, py * sy - 1.0f, 1.0f);
  const float x = (px + offset.x) * sx - 1.0f, y = (py + offset.y) * sy - 1.0f;
  const float3 a = izb_unproject(f, x, y, -1.0f), d = izb_unproject(f, x, y, 1.0f) - a;
  const float t = dot(p - a, n) / dot(d, n);
  const float3 q = a + t * d;
  // The same ray parameter's point on the centre ray: the pixel's footprint at p's depth, for the grazing test.
  const float3 d0 = b0 - a0;
  const float t0 = dot(p - a0, d0) / dot(d0, d0);
  const float spread = length(a + t0 * d - p);
  return isfinite(t) && t > 0.0f && length(q - p) <= 4.0f * spread ? q : p;
}

// The shadow ray of sample i of the chunk (tools/reference/tracer.cpp addRays with light_samples.cpp's exact rays);
// false for background.
static bool izb_ray(const IzbFrame* f, uint i, __global const float4* position, __global const uint* pixelTriangle,
                    __global const float4* normal, __global const float* positions, __global const uint* triangles,
                    __constant const LightViewGpu* lv, ShadowRay* ray, uint* pixelOut) {
  const uint pixel = f->pixelBegin + i / (uint)f->samples;
  *pixelOut = pixel;
  const float4 p4 = position[pixel];
  if (p4.w == 0.0f) return false;
  const float3 n0 = ray_geometric_normal(positions, triangles, pixelTriangle[pixel], normal[pixel].xyz);
  const float3 p = izb_sample_point(f, pixel, (int)(i % (uint)f->samples), p4.xyz, n0);
  *ray = ray_towards_light(p, n0, lv, f->sceneRadius);
  return true;
}

// ---- Binning: cell of every sample, counts per cell ------------------------------------------------------------

// cellOf[i]: the cell of sample i (IZB_NO_CELL background, IZB_OUTSIDE_CELL outside the grid, counted in outside[0]);
// cellCount must be zero on entry.
__kernel void izb_bin(__global const float4* position, __global const float4* normal,
                      __global const uint* pixelTriangle, __global const float* positions,
                      __global const uint* triangles, const IzbFrame f, __constant const LightViewGpu* lv,
                      __global uint* cellOf, __global uint* cellCount, __global uint* outside,
                      __global uint* cellDepth) {
  const uint i = get_global_id(0);
  if (i >= f.sampleCount) return;
  ShadowRay ray;
  uint pixel;
  if (!izb_ray(&f, i, position, pixelTriangle, normal, positions, triangles, lv, &ray, &pixel)) {
    cellOf[i] = IZB_NO_CELL;
    return;
  }
  const float3 t = lv_project(lv, ray.origin);
  if (!(t.x >= 0.0f && t.y >= 0.0f && t.x < (float)lv->width && t.y < (float)lv->height && t.z > 0.0f)) {
    cellOf[i] = IZB_OUTSIDE_CELL;
    atomic_inc(outside);
    return;
  }
  const uint cellsX = izb_cells_of((uint)lv->width);  // the light view's tiles
  const uint cell = ((uint)t.y / IZB_CELL_TEXELS) * cellsX + (uint)t.x / IZB_CELL_TEXELS;
  cellOf[i] = cell;
  atomic_inc(&cellCount[cell]);
  // Area lights: the cell's farthest sample's light depth (non-negative floats order as their bits).
  if (f.lightSamples > 0) atomic_max(&cellDepth[cell], as_uint(fmax(t.z, 0.0f)));
}

// depthMax: the farthest sample's light depth of the pass, the largest of the cells' (zero on entry). A work-item per
// IZB_DEPTH_MAX_SPAN cells, one atomic each: an atomic per cell holding samples, all at one address, took 0.5 ms on
// default.json at 640x360 (64 k cells).
__kernel void izb_depth_max(__global const uint* cellDepth, uint cells, __global uint* depthMax) {
  const uint first = get_global_id(0) * IZB_DEPTH_MAX_SPAN;
  if (first >= cells) return;
  uint farthest = 0u;
  for (uint c = first; c < min(first + IZB_DEPTH_MAX_SPAN, cells); ++c) farthest = max(farthest, cellDepth[c]);
  if (farthest > 0u) atomic_max(depthMax, farthest);
}

// ---- Exclusive scan of the cell counts: blocks, the blocks' sums, then the sums added ----------------------------

// Exclusive work-group scan of `value` (Hillis-Steele in local memory); *total gets the group's sum.
static uint izb_group_scan(uint value, __local uint* sums, uint* total) {
  const uint lid = get_local_id(0);
  sums[lid] = value;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint step = 1; step < IZB_SCAN_WG; step <<= 1) {
    const uint add = lid >= step ? sums[lid - step] : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    sums[lid] += add;
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  *total = sums[IZB_SCAN_WG - 1];
  const uint inclusive = sums[lid];
  barrier(CLK_LOCAL_MEM_FENCE);
  return inclusive - value;
}

// Scans IZB_SCAN_ITEMS consecutive entries of `data` per work-item, exclusively and in place, from `base` on each.
static uint izb_scan_items(__global uint* data, uint n, uint first, __local uint* sums, uint* total) {
  uint own[IZB_SCAN_ITEMS], sum = 0;
  for (int k = 0; k < IZB_SCAN_ITEMS; ++k) {
    own[k] = first + k < n ? data[first + k] : 0;
    sum += own[k];
  }
  uint running = izb_group_scan(sum, sums, total);
  for (int k = 0; k < IZB_SCAN_ITEMS; ++k)
    if (first + k < n) {
      data[first + k] = running;
      running += own[k];
    }
  return running;
}

// cellStart = exclusive scan of cellCount inside each block of IZB_SCAN_BLOCK cells; blockSums[block] = its total.
__kernel __attribute__((reqd_work_group_size(IZB_SCAN_WG, 1, 1))) void izb_scan_blocks(
    __global const uint* cellCount, __global uint* cellStart, __global uint* blockSums, uint cells) {
  __local uint sums[IZB_SCAN_WG];
  const uint first = get_global_id(0) * IZB_SCAN_ITEMS;
  for (int k = 0; k < IZB_SCAN_ITEMS; ++k)
    if (first + k < cells) cellStart[first + k] = cellCount[first + k];
  uint total;
  izb_scan_items(cellStart, cells, first, sums, &total);
  if (get_local_id(0) == 0) blockSums[get_group_id(0)] = total;
}

// The block sums scanned in place by one work-group (at most IZB_SCAN_BLOCK blocks: 2^20 cells).
__kernel __attribute__((reqd_work_group_size(IZB_SCAN_WG, 1, 1))) void izb_scan_sums(__global uint* blockSums,
                                                                                     uint blocks) {
  __local uint sums[IZB_SCAN_WG];
  uint total;
  izb_scan_items(blockSums, blocks, get_local_id(0) * IZB_SCAN_ITEMS, sums, &total);
}

__kernel void izb_scan_add(__global uint* cellStart, __global const uint* blockSums, uint cells) {
  const uint i = get_global_id(0);
  if (i < cells) cellStart[i] += blockSums[i / IZB_SCAN_BLOCK];
}

// sorted[cellStart[c] ...]: the chunk's samples of cell c (cursor zero on entry), so neighbouring work-items of
// izb_test share a cell and its triangle list.
__kernel void izb_scatter(__global const uint* cellOf, __global const uint* cellStart, __global uint* cursor,
                          __global uint* sorted, uint sampleCount) {
  const uint i = get_global_id(0);
  if (i >= sampleCount) return;
  const uint cell = cellOf[i];
  if (cell >= IZB_OUTSIDE_CELL) return;
  sorted[cellStart[cell] + atomic_inc(&cursor[cell])] = i;
}

// ---- The exact test ----------------------------------------------------------------------------------------------

// Sorted sample k of the pass (izb_scatter's order): its index i, its shadow ray towards the light's centre and its
// pixel; false past the pass's samples or for background.
static bool izb_sorted_sample(const IzbFrame* f, uint k, __global const uint* sorted, __global const uint* cellStart,
                              __global const uint* cellCount, __global const float4* position,
                              __global const float4* normal, __global const uint* pixelTriangle,
                              __global const float* positions, __global const uint* triangles,
                              __constant const LightViewGpu* lv, uint* i, ShadowRay* ray, uint* pixel) {
  if (k >= cellStart[f->cells - 1] + cellCount[f->cells - 1]) return false;
  *i = sorted[k];
  return izb_ray(f, *i, position, pixelTriangle, normal, positions, triangles, lv, ray, pixel);
}

// The sorted sample of this work-item: its work-group's block spread over the launch (IzbFrame::spread).
static uint izb_spread_sample(const IzbFrame* f) {
  const ulong block = ((ulong)get_group_id(0) * f->spread) % get_num_groups(0);
  return (uint)block * (uint)get_local_size(0) + (uint)get_local_id(0);
}

// One work-item per sorted sample: its ray against every triangle listed for its cell; occluded[pixel] counts the
// pixel's blocked samples.
__kernel void izb_test(__global const uint* sorted, __global const uint* cellOf, __global const uint* cellStart,
                       __global const uint* cellCount, __global const float4* position,
                       __global const float4* normal, __global const uint* pixelTriangle,
                       __global const float* positions, __global const uint* triangles, const IzbFrame f,
                       __constant const LightViewGpu* lv, __global const uint* tileCount,
                       __global const uint* tileOffset, __global const uint* tileEntries,
                       __global const uint* alphaIndex, __global const AlphaTriangle* alphaTriangles,
                       __global const AlphaMaterial* alphaMaterials, __global const uchar* alphaTexels,
                       __global uint* occluded) {
  uint i, pixel;
  ShadowRay ray;
  if (!izb_sorted_sample(&f, izb_spread_sample(&f), sorted, cellStart, cellCount, position, normal, pixelTriangle,
                         positions, triangles, lv, &i, &ray, &pixel))
    return;
  const uint cell = cellOf[i], begin = tileOffset[cell], end = begin + tileCount[cell];
  const RayAlpha alpha = {alphaIndex, alphaTriangles, alphaMaterials, alphaTexels, f.alphaTested};
  for (uint e = begin; e < end; ++e)
    if (ray_blocked_by(&ray, tileEntries[e], positions, triangles, &alpha)) {
      atomic_inc(&occluded[pixel]);
      return;
    }
}

// ---- Area lights: every receiver sample against N points of the light ------------------------------------------
// (after Johnson, Hunt, Mark, Burns & Junkins 2009, "Soft irregular shadow mapping"): a caster is listed in every cell
// where it can hide some point of the light from some receiver sample of the cell, and each sample's N rays to the
// light's points (the same rays `penumbra reference --izb-light-samples N` traces) are tested exactly against its
// cell's casters; the visibility is the share of (sample, light point) pairs no caster blocks: occluders fuse exactly,
// with no blocker-depth estimate and no bias.

// The disk's basis for a sphere light seen along unit `axis` (camera.cpp chooseUp, light_samples.cpp diskBasis).
static void izb_disk_basis(float3 axis, float3* tangent, float3* bitangent) {
  float3 up = (float3)(0.0f, 1.0f, 0.0f);
  if (!(length(cross(axis, up)) > 1e-3f)) up = (float3)(0.0f, 0.0f, 1.0f);
  if (!(length(cross(axis, up)) > 1e-3f)) up = (float3)(1.0f, 0.0f, 0.0f);
  *tangent = normalize(cross(axis, up));
  *bitangent = cross(axis, *tangent);
}

// Caster records, cluster by cluster in lanes (structure of arrays): field f of triangle t at float
// (16 (t / IZB_CLUSTER) + f) IZB_CLUSTER + t % IZB_CLUSTER, so that a sample tests a cluster's IZB_CLUSTER casters at
// once in float8 vectors (izb_soft_cull). Fields: its bounding ball (IZB_FIELD_BALL: the centroid m, the farthest
// vertex's distance widened by 1e-3 against rounding) for the cone test, its vertices (IZB_FIELD_A, _B, _C) and its
// plane's unit normal n (IZB_FIELD_NORMAL: zero for a degenerate triangle; the plane is n . p = n . m). The last
// cluster's slots past the triangles get a NaN ball, which no cone test passes.
#if IZB_CLUSTER != 8
#error "izb_soft_cull tests a cluster's casters in float8 lanes"
#endif
#define IZB_FIELD_BALL 0
#define IZB_FIELD_A 4
#define IZB_FIELD_B 7
#define IZB_FIELD_C 10
#define IZB_FIELD_NORMAL 13
#define IZB_FIELDS 16

// One work-item per slot of izb_cluster_count(triangleCount) IZB_CLUSTER: slot i holds triangle order[i], the
// triangles in the order of their centroids' Morton codes (host/techniques/izb.cpp), so that a cluster's are
// neighbours and its ball small.
__kernel void izb_soft_casters(__global const float* positions, __global const uint* triangles,
                               __global const uint* order, uint triangleCount, __global float* casters) {
  const uint i = get_global_id(0);
  if (i >= izb_cluster_count(triangleCount) * IZB_CLUSTER) return;
  __global float* record = casters + (size_t)(i / IZB_CLUSTER) * IZB_FIELDS * IZB_CLUSTER + i % IZB_CLUSTER;
  float values[IZB_FIELDS];
  if (i < triangleCount) {
    const uint t = order[i];
    const float3 a = ray_vertex(positions, triangles[3 * t]), b = ray_vertex(positions, triangles[3 * t + 1]);
    const float3 c = ray_vertex(positions, triangles[3 * t + 2]);
    const float3 m = (a + b + c) / 3.0f;
    const float3 n = cross(b - a, c - a);
    const float len = length(n);
    const float3 unit = len > 0.0f && isfinite(len) ? n / len : (float3)(0.0f);
    const float rho = 1.001f * sqrt(fmax(fmax(dot(a - m, a - m), dot(b - m, b - m)), dot(c - m, c - m)));
    vstore4((float4)(m, rho), 0, values);
    vstore3(a, 0, values + IZB_FIELD_A), vstore3(b, 0, values + IZB_FIELD_B), vstore3(c, 0, values + IZB_FIELD_C);
    vstore3(unit, 0, values + IZB_FIELD_NORMAL);
  } else {
    for (int k = 0; k < IZB_FIELDS; ++k) values[k] = k < 4 ? NAN : 0.0f;
  }
  for (int k = 0; k < IZB_FIELDS; ++k) record[k * IZB_CLUSTER] = values[k];
}

// Field `field` .. field + 2 of lane j of a cluster's `record` (izb_soft_casters).
static float3 izb_record_point(__global const float* record, int field, int j) {
  return (float3)(record[field * IZB_CLUSTER + j], record[(field + 1) * IZB_CLUSTER + j],
                  record[(field + 2) * IZB_CLUSTER + j]);
}

// Lane j's ball (izb_soft_casters).
static float4 izb_record_ball(__global const float* record, int j) {
  return (float4)(izb_record_point(record, IZB_FIELD_BALL, j), record[3 * IZB_CLUSTER + j]);
}

// clusters[k]: a ball holding the balls of casters k IZB_CLUSTER .. (k + 1) IZB_CLUSTER - 1 (after izb_soft_casters):
// their centroids' mean, the farthest of their balls' far sides widened by 1e-3. A cone that misses it misses them all.
// Balls that are not finite are left out (the last cluster's empty slots among them): the cone test never passes them
// (NaN compares false), so their casters are skipped as they would be alone; a cluster of none gets a NaN ball, skipped
// the same way.
__kernel void izb_soft_clusters(__global const float* casters, uint triangleCount, __global float4* clusters) {
  const uint k = get_global_id(0);
  if (k >= izb_cluster_count(triangleCount)) return;
  __global const float* record = casters + (size_t)k * IZB_FIELDS * IZB_CLUSTER;
  float3 centre = (float3)(0.0f);
  int finite = 0;
  for (int j = 0; j < IZB_CLUSTER; ++j) {
    const float4 ball = izb_record_ball(record, j);
    if (all(isfinite(ball))) centre += ball.xyz, ++finite;
  }
  centre /= (float)finite;
  float radius = finite > 0 ? 0.0f : NAN;
  for (int j = 0; j < IZB_CLUSTER; ++j) {
    const float4 ball = izb_record_ball(record, j);
    if (all(isfinite(ball))) radius = fmax(radius, length(ball.xyz - centre) + ball.w);
  }
  clusters[k] = (float4)(centre, 1.001f * radius);
}

// A caster's projection on the grid: its bounding box (texels) and nearest light depth; `unbounded` when it reaches the
// light's plane (spot grid) or is not finite, and may then hide the light anywhere.
typedef struct {
  float2 lo, hi;
  float zMin;
  int unbounded;
} IzbCaster;

static IzbCaster izb_caster(__constant const LightViewGpu* lv, float3 a, float3 b, float3 v) {
  IzbCaster c = {(float2)(INFINITY), (float2)(-INFINITY), INFINITY, 0};
  const float3 pa = lv_project(lv, a), pb = lv_project(lv, b), pv = lv_project(lv, v);
  c.lo = fmin(fmin(fmin(c.lo, pa.xy), pb.xy), pv.xy), c.hi = fmax(fmax(fmax(c.hi, pa.xy), pb.xy), pv.xy);
  c.zMin = fmin(fmin(fmin(c.zMin, pa.z), pb.z), pv.z);
  c.unbounded = (lv->kind != LIGHT_KIND_DIRECTIONAL && !(c.zMin > 0.0f)) || !isfinite(c.zMin) ||
                !(all(isfinite(c.lo)) && all(isfinite(c.hi)));
  return c;
}

// How far (texels) a segment from a receiver sample at light depth at most zCell to the light strays from the sample's
// own projection where it passes light depth z >= zMin (IzbFrame listReach): a sun's (zCell - zMin) tan(alpha); on a
// spot grid s R sqrt(1 + T^2) / z with s = (o_z - z) / (o_z - l_z), at most (zCell - z) / (zCell - R) (it grows with
// o_z when z > R), so at most listReach (zCell - zMin) / ((zCell - R) zMin). Negative: the caster lies behind every
// such sample and blocks none of its segments; infinite: no bound (the caster reaches within R of the light's plane).
static float izb_soft_reach(const IzbFrame* f, __constant const LightViewGpu* lv, float zMin, float zCell) {
  if (lv->kind == LIGHT_KIND_DIRECTIONAL) return zMin < zCell ? f->listReach * (zCell - zMin) : -1.0f;
  const float radius = f->lightRadius;  // a sphere's points lie up to R nearer the receivers than its centre
  if (!(zMin < zCell + radius)) return -1.0f;
  if (!(zMin > radius && zCell > radius)) return INFINITY;
  return f->listReach * fmax(zCell - zMin, 0.0f) / ((zCell - radius) * zMin);
}

// The caster's candidate cells (x0, x1, y0, y1 inclusive; x0 > x1 when none): its box dilated by the reach towards
// the farthest sample of the frame, within the grid. Each is then checked with its own farthest sample
// (izb_soft_lists).
static int4 izb_soft_box(const IzbFrame* f, __constant const LightViewGpu* lv, const IzbCaster* c, float zMax) {
  const uint cellsX = izb_cells_of((uint)lv->width);
  const uint cellsY = izb_cells_of((uint)lv->height);
  const int4 every = (int4)(0, (int)cellsX - 1, 0, (int)cellsY - 1);
  if (c->unbounded) return every;
  const float reach = izb_soft_reach(f, lv, c->zMin, zMax);
  if (reach < 0.0f) return (int4)(1, 0, 1, 0);
  const float2 lo = c->lo - reach, hi = c->hi + reach;
  if (!(all(isfinite(lo)) && all(isfinite(hi)))) return every;
  if (hi.x < 0.0f || hi.y < 0.0f || lo.x >= (float)lv->width || lo.y >= (float)lv->height) return (int4)(1, 0, 1, 0);
  const float2 last = (float2)((float)(cellsX - 1), (float)(cellsY - 1));
  const float2 c0 = clamp(floor(lo / (float)IZB_CELL_TEXELS), (float2)(0.0f), last);
  const float2 c1 = clamp(floor(hi / (float)IZB_CELL_TEXELS), (float2)(0.0f), last);
  return (int4)((int)c0.x, (int)c1.x, (int)c0.y, (int)c1.y);
}

// Whether cell (x, y), whose farthest sample lies at light depth zCell, needs caster c: the cell's square meets the
// caster's box dilated by the reach towards that sample.
static bool izb_soft_listed(const IzbFrame* f, __constant const LightViewGpu* lv, const IzbCaster* c, int x, int y,
                            float zCell) {
  if (c->unbounded) return true;
  const float reach = izb_soft_reach(f, lv, c->zMin, zCell);
  if (reach < 0.0f) return false;
  const float x0 = (float)(x * IZB_CELL_TEXELS), y0 = (float)(y * IZB_CELL_TEXELS);
  return c->lo.x - reach <= x0 + (float)IZB_CELL_TEXELS && c->hi.x + reach >= x0 &&
         c->lo.y - reach <= y0 + (float)IZB_CELL_TEXELS && c->hi.y + reach >= y0;
}

// The union of cluster `k`'s casters (izb_caster, from their records) with a triangle count: triangles that hide
// nothing (a repeated vertex, izb_soft_project) and the last cluster's empty slots are left out of it.
static IzbCaster izb_cluster_caster(__constant const LightViewGpu* lv, __global const float* casters, uint k,
                                    int* members) {
  IzbCaster u = {(float2)(INFINITY), (float2)(-INFINITY), INFINITY, 0};
  *members = 0;
  __global const float* record = casters + (size_t)k * IZB_FIELDS * IZB_CLUSTER;
  for (int j = 0; j < IZB_CLUSTER; ++j) {
    const float3 a = izb_record_point(record, IZB_FIELD_A, j), b = izb_record_point(record, IZB_FIELD_B, j);
    const float3 v = izb_record_point(record, IZB_FIELD_C, j);
    if (all(a == b) || all(b == v) || all(v == a)) continue;
    const IzbCaster c = izb_caster(lv, a, b, v);
    u.lo = fmin(u.lo, c.lo), u.hi = fmax(u.hi, c.hi), u.zMin = fmin(u.zMin, c.zMin), u.unbounded |= c.unbounded;
    ++*members;
  }
  return u;
}

// A cluster's union (izb_cluster_caster) as izb_soft_tiles stores it for the cells' tests: (lo, hi, zMin, unbounded,
// members, 0).
static float8 izb_box_pack(const IzbCaster* c, int members) {
  return (float8)(c->lo, c->hi, c->zMin, as_float(c->unbounded), as_float(members), 0.0f);
}
static IzbCaster izb_box_unpack(float8 b, int* members) {
  IzbCaster c = {b.s01, b.s23, b.s4, as_int(b.s5)};
  *members = as_int(b.s6);
  return c;
}

// Per cluster of IZB_CLUSTER casters: its union stored in boxes[k] (fill == 0; read back when fill == 1), and the
// cluster counted into tileCount (fill == 0) or written to tileEntries[tileStart[t] + cursor] (fill == 1) for every
// tile of IZB_TILE_CELLS^2 cells that its box, dilated by the reach towards the frame's farthest sample (izb_soft_box),
// meets. tileCount zero on entry. The cluster's box is the union of its casters' and its nearest depth theirs, so a
// cell that one of them reaches (the reach grows as the caster nears the light) lies in a tile that lists it. One
// atomic per cluster and tile, where listing per cell took one per cluster and cell.
__kernel void izb_soft_tiles(__global const float* casters, uint triangleCount, const IzbFrame f,
                             __constant const LightViewGpu* lv, __global const uint* depthMax, int fill,
                             __global float8* boxes, __global uint* tileCount, __global const uint* tileStart,
                             __global uint* tileEntries) {
  const uint k = get_global_id(0);
  if (k >= izb_cluster_count(triangleCount)) return;
  int members;
  IzbCaster c;
  if (fill) {
    c = izb_box_unpack(boxes[k], &members);
  } else {
    c = izb_cluster_caster(lv, casters, k, &members);
    boxes[k] = izb_box_pack(&c, members);
  }
  if (members == 0) return;
  const int4 box = izb_soft_box(&f, lv, &c, as_float(*depthMax));
  if (box.x > box.y || box.z > box.w) return;
  const uint tilesX = izb_tiles_of(izb_cells_of((uint)lv->width));
  for (int y = box.z / IZB_TILE_CELLS; y <= box.w / IZB_TILE_CELLS; ++y)
    for (int x = box.x / IZB_TILE_CELLS; x <= box.y / IZB_TILE_CELLS; ++x) {
      const uint tile = (uint)y * tilesX + (uint)x;
      const uint slot = atomic_inc(&tileCount[tile]);
      if (fill) tileEntries[tileStart[tile] + slot] = k;
    }
}

// Per cell: the most entries its list can hold, its tile's cluster count (izb_soft_tiles) where it holds samples and 0
// elsewhere, into bound[cell]: scanned, they place each cell's list (izb_soft_lists) without a counting pass.
__kernel void izb_soft_list_bounds(const IzbFrame f, __constant const LightViewGpu* lv, __global const uint* cellCount,
                                   __global const uint* tileCount, __global uint* bound) {
  const uint cell = get_global_id(0);
  if (cell >= f.cells) return;
  const uint cellsX = izb_cells_of((uint)lv->width);
  const uint x = cell % cellsX, y = cell / cellsX;
  bound[cell] = cellCount[cell] == 0 ? 0u : tileCount[(y / IZB_TILE_CELLS) * izb_tiles_of(cellsX) + x / IZB_TILE_CELLS];
}

// Per cell holding samples: the clusters of its tile (izb_soft_tiles) that it needs, those whose box dilated by the
// reach towards the cell's own farthest sample meets its square (izb_soft_listed), those over the cell first, each
// group in the tile's order, to entries[listStart[cell] ...] (room for its whole tile: izb_soft_list_bounds) and
// counted into listCount[cell] (0 for a cell without samples). No atomics: each work-item owns its cell's list.
__kernel void izb_soft_lists(const IzbFrame f, __constant const LightViewGpu* lv, __global const uint* cellCount,
                             __global const uint* cellDepth, __global const float8* boxes,
                             __global const uint* tileCount, __global const uint* tileStart,
                             __global const uint* tileEntries, __global uint* listCount, __global const uint* listStart,
                             __global uint* entries) {
  const uint cell = get_global_id(0);
  if (cell >= f.cells) return;
  if (cellCount[cell] == 0) {
    listCount[cell] = 0;
    return;
  }
  const uint cellsX = izb_cells_of((uint)lv->width);
  const int x = (int)(cell % cellsX), y = (int)(cell / cellsX);
  const uint tile = (uint)(y / IZB_TILE_CELLS) * izb_tiles_of(cellsX) + (uint)(x / IZB_TILE_CELLS);
  const float zCell = as_float(cellDepth[cell]);
  const uint begin = tileStart[tile], end = begin + tileCount[tile], out = listStart[cell];
  // The clusters whose own box lies over the cell first (those towards the light's centre from its samples), at the
  // front of the room, the others from its back in reverse, then moved down behind them in the tile's order: an umbra
  // sample stops once its light points are all hidden, and the casters over it hide the most of them.
  const float x0 = (float)(x * IZB_CELL_TEXELS), y0 = (float)(y * IZB_CELL_TEXELS);
  const float x1 = x0 + (float)IZB_CELL_TEXELS, y1 = y0 + (float)IZB_CELL_TEXELS;
  const uint room = end - begin;
  uint over = 0, beside = 0;
  for (uint j = begin; j < end; ++j) {
    const uint k = tileEntries[j];
    int members;
    const IzbCaster c = izb_box_unpack(boxes[k], &members);
    if (!izb_soft_listed(&f, lv, &c, x, y, zCell)) continue;
    if (!c.unbounded && c.lo.x <= x1 && c.hi.x >= x0 && c.lo.y <= y1 && c.hi.y >= y0)
      entries[out + over++] = k;
    else
      entries[out + room - 1u - beside++] = k;
  }
  const uint tail = out + room - beside;  // the others, reversed there: back into order, then down behind the first
  for (uint j = 0; j < beside / 2u; ++j) {
    const uint a = entries[tail + j];
    entries[tail + j] = entries[out + room - 1u - j], entries[out + room - 1u - j] = a;
  }
  for (uint j = 0; j < beside; ++j) entries[out + over + j] = entries[tail + j];  // downwards: no entry read is lost
  listCount[cell] = over + beside;
}

// The cone from a receiver sample around every segment it can send to the light: unit `axis` towards the light's
// centre (a sun: towards the sun), cos and sin of its half-angle, and the farthest a segment's point lies along the
// axis.
typedef struct {
  float3 axis;
  float cosHalf, sinHalf, reach;
} IzbCone;

static IzbCone izb_light_cone(const IzbFrame* f, float3 origin) {
  IzbCone cone;
  if (f->lightKind == IZB_LIGHT_SUN) {
    cone.axis = vload3(0, f->toLight);
    cone.cosHalf = 1.0f - f->lightOneMinusCos, cone.sinHalf = sqrt(fmax(0.0f, 1.0f - cone.cosHalf * cone.cosHalf));
    cone.reach = INFINITY;
    return cone;
  }
  // Every point of the disk lies in the ball of lightRadius around the centre, which subtends asin(R / D).
  const float3 d = vload3(0, f->lightCentre) - origin;
  const float distance = length(d), sine = f->lightRadius / distance;
  cone.axis = d / distance;
  cone.sinHalf = sine < 1.0f ? sine : 1.0f, cone.cosHalf = sine < 1.0f ? sqrt(1.0f - sine * sine) : 0.0f;
  cone.reach = distance + f->lightRadius;
  return cone;
}

// Whether a caster in `ball` can meet a segment from `origin` inside `cone`: the ball against the cone, in front of
// the origin and short of the light. In the plane of the axis and the ball's centre (a along the axis, p across it),
// the ball meets the cone only if its centre lies within rho of the cone's side, p cos(half) - a sin(half) <= rho
// (the side's line is nearer than its ray, so this never rejects a ball that meets it), tested squared: no square root
// or division. The side is widened by 1e-3 (|a| + rho) against rounding (p^2 = |w|^2 - a^2 cancels near the axis).
static bool izb_may_block(const IzbCone* cone, float3 origin, float4 ball) {
  const float rho = ball.w;
  const float3 w = ball.xyz - origin;
  const float a = dot(w, cone->axis);
  if (!(a + rho > 0.0f && a - rho < cone->reach)) return false;  // behind the origin, beyond the light (or NaN)
  const float side = rho + a * cone->sinHalf + 1e-3f * (fabs(a) + rho);
  if (side < 0.0f) return false;
  const float p2 = fmax(dot(w, w) - a * a, 0.0f);
  return p2 * cone->cosHalf * cone->cosHalf <= side * side;
}

// The plane the light's points lie in, seen from a receiver sample's origin o: a spot's disk (its own basis), a
// sphere's disk facing o, a sun's directions at unit distance along its axis. `scale` turns the plane's coordinates
// into the unit disk's that holds the light's points (the pattern's, host/techniques/izb_pattern.h).
typedef struct {
  float3 origin, centre, normal, tangent, bitangent;
  float height;  // spot, sphere: (centre - origin) . normal, the plane's distance from o along the normal
  float scale;
  int sun;
} IzbLightPlane;

static IzbLightPlane izb_light_plane(const IzbFrame* f, float3 origin) {
  IzbLightPlane p;
  p.origin = origin, p.centre = vload3(0, f->lightCentre), p.sun = f->lightKind == IZB_LIGHT_SUN;
  p.normal = vload3(0, f->toLight);  // a spot's disk faces along its axis; a sun's plane lies across its direction
  p.tangent = vload3(0, f->lightTangent), p.bitangent = vload3(0, f->lightBitangent);
  if (f->lightKind == IZB_LIGHT_SPHERE) {
    const float3 d = p.centre - origin;
    const float len = length(d);
    p.normal = len > 0.0f ? d / len : -vload3(0, f->toLight);
    izb_disk_basis(p.normal, &p.tangent, &p.bitangent);
  }
  p.height = p.sun ? 1.0f : dot(p.centre - origin, p.normal);
  const float tanAlpha = sqrt(f->lightOneMinusCos * (2.0f - f->lightOneMinusCos)) / (1.0f - f->lightOneMinusCos);
  p.scale = 1.0f / (p.sun ? tanAlpha : f->lightRadius);  // the unit disk holds the light's points
  return p;
}

// The cone around the segments from the plane's origin to the light points that no caster has hidden yet (the zero
// bits of `mask`): the bounding circle of their plane points (its box's centre, the farthest point), turned by cs as
// they are, lifted to a ball in the light's plane (spot, sphere) or at unit distance along the sun's axis. A caster
// outside it can only hide points already hidden, so izb_soft_test skips it and the answer stays exact.
static IzbCone izb_unhidden_cone(const IzbLightPlane* p, const uint* mask, int words,
                                 __global const float2* planePoints, float2 cs) {
  float2 lo = (float2)(INFINITY), hi = (float2)(-INFINITY);
  for (int w = 0; w < words; ++w)
    for (uint open = ~mask[w]; open != 0u; open &= open - 1u) {
      const float2 q = planePoints[32 * w + (int)(31u - clz(open & (0u - open)))];
      lo = fmin(lo, q), hi = fmax(hi, q);
    }
  const float2 mid = 0.5f * (lo + hi);
  float r2 = 0.0f;
  for (int w = 0; w < words; ++w)
    for (uint open = ~mask[w]; open != 0u; open &= open - 1u) {
      const float2 q = planePoints[32 * w + (int)(31u - clz(open & (0u - open)))] - mid;
      r2 = fmax(r2, dot(q, q));
    }
  const float2 c = (float2)(cs.x * mid.x - cs.y * mid.y, cs.y * mid.x + cs.x * mid.y);
  const float s = 1.0f / p->scale, r = s * (sqrt(r2) * 1.0001f + 1e-6f);
  const float3 target = (p->sun ? p->normal : p->centre - p->origin) + s * (c.x * p->tangent + c.y * p->bitangent);
  const float distance = length(target), sine = r / distance;
  IzbCone cone;
  cone.axis = target / distance;
  cone.sinHalf = sine < 1.0f ? sine : 1.0f, cone.cosHalf = sine < 1.0f ? sqrt(1.0f - sine * sine) : 0.0f;
  cone.reach = p->sun ? INFINITY : distance + r;
  return cone;
}

// The ray from the plane's origin to the light's point of unit-disk point `disk` (host/techniques/izb_pattern.h), as
// tools/reference/light_samples.cpp LightSampler::rayFromDisk: the disk's basis is the plane's (a sphere's faces the
// origin, izb_light_plane computes it as the reference does).
static ShadowRay izb_light_ray(const IzbFrame* f, const IzbLightPlane* p, float2 disk) {
  ShadowRay ray;
  ray.origin = p->origin;
  if (p->sun) {
    const float r2 = dot(disk, disk), x = r2 * f->lightOneMinusCos;
    const float cosTheta = 1.0f - x, sinTheta = sqrt(fmax(0.0f, x * (2.0f - x))), r = sqrt(r2);
    const float2 azimuth = r > 0.0f ? disk / r : (float2)(0.0f);
    ray.direction = cosTheta * p->normal + sinTheta * (azimuth.x * p->tangent + azimuth.y * p->bitangent);
    ray.tfar = INFINITY;
    return ray;
  }
  const float3 point = p->centre + f->lightRadius * (disk.x * p->tangent + disk.y * p->bitangent);
  ray.direction = point - p->origin;
  ray.tfar = SHADOW_RAY_SPOT_TFAR;
  return ray;
}

// An edge's line is trusted to the masks when its cross product's rounding, magnified by the light's distance over its
// radius, moves it across the unit disk by at most ~8 eps IZB_EDGE_CONDITION = 2.4e-4 (a quarter of IZB_MASK_MARGIN).
#define IZB_EDGE_CONDITION 512.0f

// Three float8 coordinates: a point or vector of each of a cluster's IZB_CLUSTER casters.
typedef struct {
  float8 x, y, z;
} IzbLanes3;

static IzbLanes3 izb_lanes_load(__global const float* record, int field) {
  const IzbLanes3 v = {vload8(field, record), vload8(field + 1, record), vload8(field + 2, record)};
  return v;
}

static IzbLanes3 izb_lanes_minus(IzbLanes3 a, float3 o) {
  const IzbLanes3 v = {a.x - o.x, a.y - o.y, a.z - o.z};
  return v;
}

static IzbLanes3 izb_lanes_sub(IzbLanes3 a, IzbLanes3 b) {
  const IzbLanes3 v = {a.x - b.x, a.y - b.y, a.z - b.z};
  return v;
}

// Component by component in dot()'s and cross()'s order, products first (no fused multiply-adds: FP_CONTRACT OFF).
static float8 izb_lanes_dot(IzbLanes3 a, IzbLanes3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static float8 izb_lanes_dot3(IzbLanes3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

static IzbLanes3 izb_lanes_cross(IzbLanes3 a, IzbLanes3 b) {
  const IzbLanes3 v = {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  return v;
}

// Bit j set where lane j of `m` (an OpenCL vector comparison: -1 true, 0 false) is true.
static uint izb_lane_bits(int8 m) {
  const int8 v = m & (int8)(1, 2, 4, 8, 16, 32, 64, 128);
  return (uint)(v.s0 | v.s1 | v.s2 | v.s3 | v.s4 | v.s5 | v.s6 | v.s7);
}

// A batch of IZB_CLUSTER casters (from one cluster or several) projected onto the light's plane, lane by lane: for
// edge i, the unit-disk points q with dot(g[i], q) >= h[i], each side's value known to within tol[i] (rounding; at
// least IZB_MASK_MARGIN |g[i]|), and its masks' first word in the tables. Bit j of the masks: `live`, caster j may
// hide a light point and needs the per-point work; `traced` (live), its points must be traced (no projection);
// `masked` (live, projected), every edge is conditioned well enough for the bitmask tables; `edge[i]`, edge i bounds
// the projection (an edge that holds the whole disk is left out; none, and the caster hides every light point).
typedef struct {
  float gx[3][IZB_CLUSTER], gy[3][IZB_CLUSTER], h[3][IZB_CLUSTER], tol[3][IZB_CLUSTER];
  int table[3][IZB_CLUSTER];  // masked: the edge's masks in the tables (izb_edge_tables)
  uint live, traced, masked, edge[3];
} IzbLanes;

// izb_mask_angle_bin, lane by lane, with its arithmetic: q = (x or y) / (|x| + |y|), one division, then
// y >= 0: x >= 0 ? q_y : 1 - q_x; y < 0: x < 0 ? 2 - q_y : 3 + q_x ((int) and convert_int8 both truncate). The clamps
// here take vector bounds: Oclgrind's int8 clamp with scalar bounds returns garbage.
static int8 izb_mask_angle_bins(float8 x, float8 y) {
  const float8 sum = fabs(x) + fabs(y);
  const int8 xPositive = x >= 0.0f, yPositive = y >= 0.0f;
  const float8 q = select(x, y, xPositive == yPositive) / sum;
  const float8 base = select(select((float8)(3.0f), (float8)(2.0f), x < 0.0f),
                             select((float8)(1.0f), (float8)(0.0f), xPositive), yPositive);
  const float8 p = base + select(-q, q, xPositive);
  const int8 bin = clamp(convert_int8(p * (0.25f * (float)IZB_MASK_ANGLES)), (int8)(0), (int8)(IZB_MASK_ANGLES - 1));
  return select(bin, (int8)(0), !(sum > 0.0f));
}

// The first word of the masks (host/techniques/izb_pattern.h) of the points that edge (g, offset = h / |g|) may hold,
// or certainly holds, lane by lane, the pattern turned by cs: its lookups are of the edge turned back; `misses`: the
// edge holds none of the unit disk.
static int8 izb_edge_tables(float8 gx, float8 gy, float8 offset, float2 cs, int words, int8* misses) {
  *misses = offset > 1.0f + IZB_MASK_MARGIN;
  const int8 a = izb_mask_angle_bins(cs.x * gx + cs.y * gy, cs.x * gy - cs.y * gx);
  // Truncation, not floor: the two differ only below 0, which the clamp takes to 0 either way.
  const int8 b = clamp(convert_int8((offset + 1.0f) * (0.5f * (float)IZB_MASK_OFFSETS)), (int8)(0),
                       (int8)(IZB_MASK_OFFSETS - 1));
  return (a * IZB_MASK_OFFSETS + b) * (2 * words);
}

// Which of cluster `record`'s casters may hide part of the light from a receiver sample whose segments to it lie in
// `cone` (bit j: lane j), all lanes at once:
// 1. Each caster's ball against the cone (izb_may_block's test).
// 2. Beside its plane: the origin and the whole light on one side of it, clear by more than rounding (its vertices
//    lie within slack = 1e-5 (|m|_inf + rho) of it): no segment between them meets it. A sphere's or disk's points lie
//    within lightRadius of its centre; a sun's directions within alpha of its axis. The receiver's own surface and
//    casters that face the light with the origin in front end here.
static uint izb_soft_cull(const IzbFrame* f, float3 o, const IzbCone* cone, __global const float* record) {
  const float8 rho = vload8(3, record);
  const IzbLanes3 m = izb_lanes_load(record, IZB_FIELD_BALL);
  const IzbLanes3 w = izb_lanes_minus(m, o);
  const float8 a = izb_lanes_dot3(w, cone->axis);
  const float8 side = rho + a * cone->sinHalf + 1e-3f * (fabs(a) + rho);
  const float8 p2 = fmax(izb_lanes_dot(w, w) - a * a, 0.0f);
  const float cos2 = cone->cosHalf * cone->cosHalf;
  // Behind the origin, beyond the light (or NaN), or outside the cone's side.
  const int8 meets = (a + rho > 0.0f) & (a - rho < cone->reach) & (side >= 0.0f) & (p2 * cos2 <= side * side);
  if (!any(meets)) return 0u;
  const IzbLanes3 n = izb_lanes_load(record, IZB_FIELD_NORMAL);
  const float8 level = izb_lanes_dot(n, m), offside = izb_lanes_dot3(n, o) - level;
  const float8 slack = 1e-5f * (fmax(fmax(fabs(m.x), fabs(m.y)), fabs(m.z)) + rho);
  int8 beside = fabs(offside) > slack;
  if (f->lightKind == IZB_LIGHT_SUN) {
    const float sinAlpha = sqrt(f->lightOneMinusCos * (2.0f - f->lightOneMinusCos));
    beside &= izb_lanes_dot3(n, vload3(0, f->toLight)) * sign(offside) > sinAlpha + 1e-5f;
  } else {
    beside &= (izb_lanes_dot3(n, vload3(0, f->lightCentre)) - level) * sign(offside) > f->lightRadius + slack;
  }
  return izb_lane_bits(meets & ~beside);
}

// The casters of a batch (`vertex`: lanes of a.x, a.y, a.z, b.x, ... c.z; `live`: the lanes that hold one) projected
// onto the light's plane (IzbLanes). With v_i the vertices minus o, a direction d meets the triangle at t > 0 exactly
// when d = alpha v_0 + beta v_1 + gamma v_2 with alpha, beta, gamma >= 0, i.e. when sign(det(v_0, v_1, v_2))
// (v_i x v_j) . d >= 0 for each edge (the triple products of a ray-triangle test): the plane through o and an edge
// cuts the light's plane in a line. The light's point of q lies along d(q) = D + s (q.x T + q.y B) (spot, sphere:
// D = centre - o, s = radius; sun: D = the axis, s = tan alpha), affine in q, so each edge is a half-plane of the
// light's plane: vertices behind o, or next to it, need no clipping. Before the light: every vertex lies nearer than
// the light's plane (checked), so the hit does too. A caster hides none when an edge leaves the whole disk out, or two
// vertices coincide (the watertight test's U and V are then opposite and W zero, so it meets no ray); its points are
// traced when a vertex lies at or beyond the light's plane, or o in its plane within rounding.
static IzbLanes izb_soft_project(const IzbLightPlane* p, const float (*vertex)[IZB_CLUSTER], uint live, float2 cs,
                                 int words) {
  IzbLanes out;
  const float3 o = p->origin;
  IzbLanes3 v[3];
  for (int i = 0; i < 3; ++i) {
    const IzbLanes3 corner = {vload8(0, vertex[3 * i]), vload8(0, vertex[3 * i + 1]), vload8(0, vertex[3 * i + 2])};
    v[i] = izb_lanes_minus(corner, o);
  }
  // Coinciding vertices (compared as given, before o is taken off).
  int8 none = (int8)(0);
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    none |= (vload8(0, vertex[3 * i]) == vload8(0, vertex[3 * j])) &
            (vload8(0, vertex[3 * i + 1]) == vload8(0, vertex[3 * j + 1])) &
            (vload8(0, vertex[3 * i + 2]) == vload8(0, vertex[3 * j + 2]));
  }
  int8 traced = (int8)(0);
  if (!p->sun)
    for (int i = 0; i < 3; ++i) traced |= !(izb_lanes_dot3(v[i], p->normal) < p->height * (1.0f - 1e-5f));
  // Products of v_i with the edges v_j - v_i, whose differences are near exact (Sterbenz), not of two long, nearly
  // parallel v_i: det(v_0, v_1, v_2) = v_0 . (e_01 x e_02) and v_i x v_j = v_i x e_ij.
  const IzbLanes3 e[3] = {izb_lanes_sub(v[1], v[0]), izb_lanes_sub(v[2], v[1]), izb_lanes_sub(v[0], v[2])};
  const IzbLanes3 minusE2 = {-e[2].x, -e[2].y, -e[2].z};
  const IzbLanes3 normal = izb_lanes_cross(e[0], minusE2);
  const float8 det = izb_lanes_dot(v[0], normal);
  traced |= !(det * det > 1e-10f * izb_lanes_dot(v[0], v[0]) * izb_lanes_dot(normal, normal));  // o in its plane
  const float8 sgn = select((float8)(-1.0f), (float8)(1.0f), det > 0.0f);
  const float s = 1.0f / p->scale;
  const float3 d = p->sun ? p->normal : p->centre - p->origin;
  const float reach = length(d) + s;  // |d(q)| over the unit disk
  int8 hidesNone = none, masked = (int8)(-1), misses = (int8)(0);
  for (int i = 0; i < 3; ++i) {
    const IzbLanes3 cr = izb_lanes_cross(v[i], e[i]);
    const IzbLanes3 mi = {sgn * cr.x, sgn * cr.y, sgn * cr.z};
    const float8 gx = s * izb_lanes_dot3(mi, p->tangent), gy = s * izb_lanes_dot3(mi, p->bitangent);
    const float8 h = -izb_lanes_dot3(mi, d), g2 = gx * gx + gy * gy;
    // Inside where dot(g, q) >= h; over the unit disk dot(g, q) spans [-|g|, |g|]. Rounding moves h by about 8 eps
    // |v_i| |e_i| reach, which a well-conditioned edge (|g| IZB_EDGE_CONDITION > |v_i| |e_i| reach) bounds by
    // 8 eps IZB_EDGE_CONDITION |g|.
    const float8 scale2 = izb_lanes_dot(v[i], v[i]) * izb_lanes_dot(e[i], e[i]) * (reach * reach);
    const int8 conditioned = g2 * (IZB_EDGE_CONDITION * IZB_EDGE_CONDITION) > scale2;
    const float8 glen = sqrt(g2);
    const float8 err = select(5e-7f * sqrt(scale2), (5e-7f * IZB_EDGE_CONDITION) * glen, conditioned);
    const int8 whole = h + glen < -err;  // the whole disk lies inside this edge
    hidesNone |= h - glen > err;
    masked &= whole | conditioned;
    out.edge[i] = izb_lane_bits(~whole);
    vstore8(gx, 0, out.gx[i]), vstore8(gy, 0, out.gy[i]), vstore8(h, 0, out.h[i]);
    vstore8(fmax(err, IZB_MASK_MARGIN * glen), 0, out.tol[i]);
    int8 edgeMisses;
    vstore8(izb_edge_tables(gx, gy, h / glen, cs, words, &edgeMisses), 0, out.table[i]);
    misses |= edgeMisses & ~whole;
  }
  // Coinciding vertices hide nothing even where traced; a projection that leaves the disk out, only when projected;
  // an edge of a masked one that misses the disk (its tables are trusted).
  masked &= ~traced;
  out.live = live & ~izb_lane_bits(none | (hidesNone & ~traced) | (masked & misses));
  out.traced = izb_lane_bits(traced) & out.live;
  out.masked = izb_lane_bits(masked) & out.live;
  return out;
}

// What izb_soft_cover reads besides the batch: the sample's light, pattern and the scene's triangles.
typedef struct {
  const IzbFrame* f;
  const IzbLightPlane* plane;
  float2 cs;
  int words;
  __global const float* positions;
  __global const uint* triangles;
  __global const float2* pattern;
  __global const float2* planePoints;
  __global const uint* masks;
  RayAlpha alpha;
} IzbCover;

// The light points the batch's live casters (triangles[j]: lane j's) hide, added to `mask` and counted in *blocked,
// until all n are. Per caster, three bitmask lookups (its edges) give the points it may hold and those it certainly
// holds; the certain ones of an opaque caster are blocked outright, the others not yet blocked are tested against the
// projection and, where rounding leaves it unsure, traced exactly (the reference's ray and test).
static void izb_soft_cover(const IzbCover* in, const IzbLanes* lanes, const uint* casterOf, uint n, uint* mask,
                           uint* blocked) {
  const int words = in->words;
  const float2 cs = in->cs;
  for (uint live = lanes->live; live != 0u && *blocked < n; live &= live - 1u) {
    const int j = (int)(31u - clz(live & (0u - live)));  // lowest live lane
    const uint t = casterOf[j], bitJ = 1u << j;
    const bool projected = !(lanes->traced & bitJ), masked = (lanes->masked & bitJ) != 0u;
    if (masked) {  // most casters a sample reaches can hide only points it has hidden already
      uint open = 0u;
      for (int w = 0; w < words; ++w) {
        uint may = ~mask[w];
        for (int c = 0; c < 3; ++c)
          if (lanes->edge[c] & bitJ) may &= in->masks[lanes->table[c][j] + w];
        open |= may;
      }
      if (open == 0u) continue;
    }
    float2 g[3];
    float h[3], tol[3];
    int edges = 0;
    __global const uint* table[3];
    for (int c = 0; c < 3; ++c) {
      if (!(lanes->edge[c] & bitJ)) continue;
      g[edges] = (float2)(lanes->gx[c][j], lanes->gy[c][j]), h[edges] = lanes->h[c][j];
      tol[edges] = lanes->tol[c][j], table[edges++] = in->masks + lanes->table[c][j];
    }
    const bool opaque = !in->alpha.alphaTested || in->alpha.index[t] == ALPHA_NO_TRIANGLE;
    for (int w = 0; w < words; ++w) {
      uint test = ~mask[w];
      if (masked) {
        uint may = ~0u, certain = ~0u;
        for (int c = 0; c < edges; ++c) may &= table[c][w], certain &= table[c][words + w];
        test &= may;
        if (opaque) {
          const uint sure = test & certain;
          mask[w] |= sure, *blocked += popcount(sure), test &= ~certain;
        }
      }
      while (test != 0u) {
        const uint bit = 31u - clz(test & (0u - test));  // lowest set bit
        test &= test - 1u;
        const uint pj = 32u * (uint)w + bit;
        if (projected) {  // the point against the projection itself: clearly outside, or clearly inside an opaque one
          const float2 hp = in->planePoints[pj];
          const float2 q = (float2)(cs.x * hp.x - cs.y * hp.y, cs.y * hp.x + cs.x * hp.y);
          bool outside = false, inside = true;
          for (int c = 0; c < edges; ++c) {
            const float side = dot(g[c], q) - h[c];
            outside |= side<-tol[c], inside &= side> tol[c];
          }
          if (outside) continue;
          if (opaque && inside) {
            mask[w] |= 1u << bit;
            ++*blocked;
            continue;
          }
        }
        const float2 pp = in->pattern[pj];
        const float2 dd = (float2)(cs.x * pp.x - cs.y * pp.y, cs.y * pp.x + cs.x * pp.y);
        const ShadowRay ray = izb_light_ray(in->f, in->plane, dd);
        if (ray_blocked_by(&ray, t, in->positions, in->triangles, &in->alpha)) {
          mask[w] |= 1u << bit;
          ++*blocked;
        }
      }
    }
  }
}

// One work-item per sorted sample. Each cluster of its cell whose ball meets the cone of its segments to the light
// has its casters culled in lanes (izb_soft_cull); the ones left are gathered, IZB_CLUSTER at a time across clusters,
// projected onto the light's plane in lanes (izb_soft_project) and cover the light's points (izb_soft_cover).
// Occluders fuse in the mask, with no blocker-depth estimate and no bias. occluded[pixel] gains the blocked rays.
// Sub-pixel sample s turns its pattern by key pixel + s * 0x632be5ab.
__kernel void izb_soft_test(__global const uint* sorted, __global const uint* cellOf, __global const uint* cellStart,
                            __global const uint* cellCount, __global const float4* position,
                            __global const float4* normal, __global const uint* pixelTriangle,
                            __global const float* positions, __global const uint* triangles, const IzbFrame f,
                            __constant const LightViewGpu* lv, __global const uint* listCount,
                            __global const uint* listStart, __global const uint* listEntries,
                            __global const float* casters, __global const float4* clusters, __global const uint* order,
                            __global const float2* pattern, __global const float2* rotations,
                            __global const float2* planePoints, __global const uint* masks,
                            __global const uint* alphaIndex, __global const AlphaTriangle* alphaTriangles,
                            __global const AlphaMaterial* alphaMaterials, __global const uchar* alphaTexels,
                            __global uint* occluded) {
  uint i, pixel;
  ShadowRay hard;
  if (!izb_sorted_sample(&f, izb_spread_sample(&f), sorted, cellStart, cellCount, position, normal, pixelTriangle,
                         positions, triangles, lv, &i, &hard, &pixel))
    return;
  const uint cell = cellOf[i], begin = listStart[cell], end = begin + listCount[cell];
  if (begin == end) return;
  const uint key = pixel + (i % (uint)f.samples) * 0x632be5abu, n = (uint)f.lightSamples;
  const IzbLightPlane plane = izb_light_plane(&f, hard.origin);
  const IzbCover in = {&f,
                       &plane,
                       rotations[izb_rotation_of(key)],
                       izb_mask_words((int)n),
                       positions,
                       triangles,
                       pattern,
                       planePoints,
                       masks,
                       {alphaIndex, alphaTriangles, alphaMaterials, alphaTexels, f.alphaTested}};
  IzbCone cone = izb_light_cone(&f, hard.origin);
  uint mask[IZB_MAX_LIGHT_GRID * IZB_MAX_LIGHT_GRID / 32];
  for (int w = 0; w < in.words; ++w) mask[w] = n - 32u * (uint)w >= 32u ? 0u : ~0u << (n - 32u * (uint)w);
  uint blocked = 0, coned = 0;
  // The batch: the culled casters' vertices (a.x, a.y, a.z, b.x, ... c.z) lane by lane and their triangles.
  float vertex[9][IZB_CLUSTER];
  uint casterOf[IZB_CLUSTER];
  int pending = 0;
  for (uint e = begin; e < end && blocked < n; ++e) {
    if (blocked != coned) cone = izb_unhidden_cone(&plane, mask, in.words, planePoints, in.cs), coned = blocked;
    const uint k = listEntries[e];
    if (!izb_may_block(&cone, hard.origin, clusters[k])) continue;
    __global const float* record = casters + (size_t)k * IZB_FIELDS * IZB_CLUSTER;
    for (uint kept = izb_soft_cull(&f, hard.origin, &cone, record); kept != 0u; kept &= kept - 1u) {
      const int j = (int)(31u - clz(kept & (0u - kept)));
      for (int c = 0; c < 9; ++c) vertex[c][pending] = record[(IZB_FIELD_A + c) * IZB_CLUSTER + j];
      casterOf[pending] = order[k * IZB_CLUSTER + (uint)j];
      if (++pending < IZB_CLUSTER) continue;
      const IzbLanes lanes = izb_soft_project(&plane, vertex, (1u << IZB_CLUSTER) - 1u, in.cs, in.words);
      izb_soft_cover(&in, &lanes, casterOf, n, mask, &blocked);
      pending = 0;
    }
  }
  if (pending > 0 && blocked < n) {              // the last, partial batch
    for (int l = pending; l < IZB_CLUSTER; ++l)  // the lanes left empty hold a point, which hides none
      for (int c = 0; c < 9; ++c) vertex[c][l] = 0.0f;
    const IzbLanes lanes = izb_soft_project(&plane, vertex, (1u << pending) - 1u, in.cs, in.words);
    izb_soft_cover(&in, &lanes, casterOf, n, mask, &blocked);
  }
  if (blocked > 0) atomic_add(&occluded[pixel], blocked);
}

// visibility = the share of the pixel's `rays` (samples, times light points for an area light) that reach the light
// (1 for background).
__kernel void izb_resolve(__global const float4* position, __global const uint* occluded, int rays, uint count,
                          __global float* visibility) {
  const uint i = get_global_id(0);
  if (i >= count) return;
  visibility[i] = position[i].w == 0.0f ? 1.0f : 1.0f - (float)occluded[i] / (float)rays;
}
