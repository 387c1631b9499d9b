// Exact hard shadows by an irregular z-buffer (Johnson, Lee, Burns & Mark 2005; in compute after Wyman, Hoetzlein &
// Lefohn 2015, "Frustum-traced raster shadows"). The camera's G-buffer samples (one per pixel, or 4 / 8 / 32 sub-pixel
// samples on the pixel's surface plane) are binned into a light-space grid of 8x8-texel cells, the rasterizer's tiles:
// izb_bin finds each sample's cell and counts the cells, izb_scan_* place the cells, izb_scatter sorts the samples by
// cell (a counting sort). The host then draws every caster conservatively over the grid (Rasterizer::drawTileLists,
// only the cells that hold samples), and izb_test tests each sample exactly against the triangles listed for its cell:
// the shadow ray of the Embree reference (tools/reference/tracer.cpp: the origin moved off the surface along its
// geometric normal, towards the light's centre, by IZB_RAY_OFFSET times max(|p|_inf, scene radius); to the light's
// point, or against a directional light's axis), with a watertight ray-triangle test and the alpha masks of
// kernels/shared/alpha.h. A ray from a sample to a spot or point light (the light grid's centre of projection) or
// along a directional light's axis projects to one point of the grid, so the triangles that can block it are exactly
// those whose projection covers the point its origin projects to. izb_resolve turns the blocked samples into visibility.
#include "kernels/shared/alpha.h"
#include "kernels/shared/izb.h"
#include "kernels/shared/light_view.h"

// The same arithmetic on every device: no fused multiply-adds in the ray test or the sample positions.
#pragma OPENCL FP_CONTRACT OFF

__constant float kIzbPattern[2 * IZB_PATTERN_ENTRIES] = IZB_PATTERN_VALUES;

// Ray end just short of a spot or point light's point, as the reference's (geometry through the light point itself does
// not count).
#define IZB_SPOT_TFAR (1.0f - 1e-6f)

typedef struct {
  float3 origin, direction;
  float tfar;
} IzbRay;

static float3 izb_vertex(__global const float* positions, uint v) { return vload3(v, positions); }

// The geometric normal of triangle t (unnormalised), or `fallback` when it is degenerate.
static float3 izb_geometric_normal(__global const float* positions, __global const uint* triangles, uint t,
                                   float3 fallback) {
  const float3 a = izb_vertex(positions, triangles[3 * t]), b = izb_vertex(positions, triangles[3 * t + 1]);
  const float3 c = izb_vertex(positions, triangles[3 * t + 2]);
  const float3 n = cross(b - a, c - a);
  return dot(n, n) > 0.0f && all(isfinite(n)) ? n : fallback;
}

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
                    __constant const LightViewGpu* lv, IzbRay* ray, uint* pixelOut) {
  const uint pixel = f->pixelBegin + i / (uint)f->samples;
  *pixelOut = pixel;
  const float4 p4 = position[pixel];
  if (p4.w == 0.0f) return false;
  const float3 n0 = izb_geometric_normal(positions, triangles, pixelTriangle[pixel], normal[pixel].xyz);
  const float3 p = izb_sample_point(f, pixel, (int)(i % (uint)f->samples), p4.xyz, n0);
  const bool directional = lv->kind == LIGHT_KIND_DIRECTIONAL;
  const float3 centre = lv->position.xyz, toLight = -lv->axis.xyz;
  float3 towards = toLight;
  if (!directional) {
    const float3 d = centre - p;
    const float len = length(d);
    if (len > 0.0f) towards = d / len;
  }
  float3 n = normalize(n0);
  if (dot(n, towards) < 0.0f) n = -n;
  const float3 q = fabs(p);
  const float extent = fmax(fmax(fmax(q.x, q.y), q.z), f->sceneRadius);
  ray->origin = p + n * (IZB_RAY_OFFSET * fmax(extent, FLT_MIN));
  ray->direction = directional ? toLight : centre - ray->origin;
  ray->tfar = directional ? INFINITY : IZB_SPOT_TFAR;
  return true;
}

// Watertight ray-triangle intersection (Woop, Benthin & Wald, "Watertight Ray/Triangle Intersection", JCGT 2013): true
// when the ray meets the triangle at 0 < t < tfar; (u, v) are the barycentric weights of vertices 1 and 2 (Embree's).
static bool izb_intersect(const IzbRay* r, float3 v0, float3 v1, float3 v2, float* u, float* v) {
  const float3 ad = fabs(r->direction);
  const int kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
  const float dir[3] = {r->direction.x, r->direction.y, r->direction.z};
  if (dir[kz] < 0.0f) {
    const int swap = kx;
    kx = ky, ky = swap;
  }
  const float sx = dir[kx] / dir[kz], sy = dir[ky] / dir[kz], sz = 1.0f / dir[kz];
  const float3 a3 = v0 - r->origin, b3 = v1 - r->origin, c3 = v2 - r->origin;
  const float a[3] = {a3.x, a3.y, a3.z}, b[3] = {b3.x, b3.y, b3.z}, c[3] = {c3.x, c3.y, c3.z};
  const float ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
  const float bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
  const float cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];
  const float U = cx * by - cy * bx, V = ax * cy - ay * cx, W = bx * ay - by * ax;
  if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;
  const float det = U + V + W;
  if (det == 0.0f) return false;
  const float T = U * (sz * a[kz]) + V * (sz * b[kz]) + W * (sz * c[kz]);
  // 0 < T / det < tfar, with det's sign folded in.
  const float sign = det < 0.0f ? -1.0f : 1.0f, adet = fabs(det), st = sign * T;
  if (!(st > 0.0f) || !(st < r->tfar * adet)) return false;
  *u = V / det, *v = W / det;
  return true;
}

// ---- Binning: cell of every sample, counts per cell ------------------------------------------------------------

// cellOf[i]: the cell of sample i (IZB_NO_CELL background, IZB_OUTSIDE_CELL outside the grid, counted in outside[0]);
// cellCount must be zero on entry.
__kernel void izb_bin(__global const float4* position, __global const float4* normal, __global const uint* pixelTriangle,
                      __global const float* positions, __global const uint* triangles, const IzbFrame f,
                      __constant const LightViewGpu* lv, __global uint* cellOf, __global uint* cellCount,
                      __global uint* outside) {
  const uint i = get_global_id(0);
  if (i >= f.sampleCount) return;
  IzbRay ray;
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
  const uint cellsX = ((uint)lv->width + IZB_CELL_TEXELS - 1) / IZB_CELL_TEXELS;  // the light view's tiles
  const uint cell = ((uint)t.y / IZB_CELL_TEXELS) * cellsX + (uint)t.x / IZB_CELL_TEXELS;
  cellOf[i] = cell;
  atomic_inc(&cellCount[cell]);
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

// Whether triangle t blocks the ray: the intersection, then its alpha test where it has one (alphaIndex holds one
// entry, ALPHA_NO_TRIANGLE, when no triangle of the scene is alpha-tested).
static bool izb_blocks(const IzbRay* ray, uint t, __global const float* positions, __global const uint* triangles,
                       __global const uint* alphaIndex, uint alphaTested,
                       __global const AlphaTriangle* alphaTriangles, __global const AlphaMaterial* alphaMaterials,
                       __global const uchar* alphaTexels) {
  float u, v;
  if (!izb_intersect(ray, izb_vertex(positions, triangles[3 * t]), izb_vertex(positions, triangles[3 * t + 1]),
                     izb_vertex(positions, triangles[3 * t + 2]), &u, &v))
    return false;
  const uint index = alphaTested ? alphaIndex[t] : ALPHA_NO_TRIANGLE;
  if (index == ALPHA_NO_TRIANGLE) return true;
  __global const AlphaTriangle* a = &alphaTriangles[index];
  // (1 - u - v) uv0 + u uv1 + v uv2, as the reference's filter (tools/reference/alpha_filter.cpp).
  const float w = 1.0f - u - v;
  const float tu = (w * a->uv[0] + u * a->uv[2]) + v * a->uv[4], tv = (w * a->uv[1] + u * a->uv[3]) + v * a->uv[5];
  const AlphaMaterial m = alphaMaterials[a->material];
  return alphaPasses(&m, alphaTexels, tu, tv) != 0;
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
  const uint k = get_global_id(0);
  if (k >= cellStart[f.cells - 1] + cellCount[f.cells - 1]) return;
  const uint i = sorted[k];
  IzbRay ray;
  uint pixel;
  if (!izb_ray(&f, i, position, pixelTriangle, normal, positions, triangles, lv, &ray, &pixel)) return;
  const uint cell = cellOf[i], begin = tileOffset[cell], end = begin + tileCount[cell];
  for (uint e = begin; e < end; ++e)
    if (izb_blocks(&ray, tileEntries[e], positions, triangles, alphaIndex, f.alphaTested, alphaTriangles,
                   alphaMaterials, alphaTexels)) {
      atomic_inc(&occluded[pixel]);
      return;
    }
}

// visibility = the share of the pixel's samples that reach the light (1 for background).
__kernel void izb_resolve(__global const float4* position, __global const uint* occluded, int samples, uint count,
                          __global float* visibility) {
  const uint i = get_global_id(0);
  if (i >= count) return;
  visibility[i] = position[i].w == 0.0f ? 1.0f : 1.0f - (float)occluded[i] / (float)samples;
}
