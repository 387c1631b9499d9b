// What the irregular z-buffer's kernels (kernels/izb.cl) and its host (host/techniques/izb.cpp) share: the sub-pixel
// sample patterns of `--izb-samples`, the cell codes of samples that get no cell, and the scan's block shape. Valid as
// OpenCL C 1.2 and C++20.
#ifndef PENUMBRA_KERNELS_SHARED_IZB_H
#define PENUMBRA_KERNELS_SHARED_IZB_H

#include "kernels/shared/common.h"

#define IZB_NO_CELL 0xffffffffu       // background pixel: no sample
#define IZB_OUTSIDE_CELL 0xfffffffeu  // the sample's ray origin projects outside the light grid: lit, as sm's outside
#define IZB_SCAN_WG 256               // work-items of a scan block
#define IZB_SCAN_ITEMS 4              // cells per scan work-item
#define IZB_SCAN_BLOCK (IZB_SCAN_WG * IZB_SCAN_ITEMS)  // cells per scan block (1024)
#define IZB_DEPTH_MAX_SPAN 64  // cells per work-item of izb_depth_max: one atomic each, not one per cell
#define IZB_MAX_SAMPLES 32
#define IZB_CELL_TEXELS 8  // cell side in texels: the rasterizer's tile (RASTER_TILE_SIZE; the host asserts them equal)
#define IZB_CHUNK_SAMPLES (1u << 24)  // default --izb-chunk: samples binned and tested per pass, 8 bytes each
// Area lights: casters are listed and culled in clusters of this many consecutive triangles (kernels/izb.cl
// izb_soft_clusters).
#define IZB_CLUSTER 8

// Everything the sample kernels share about a frame and chunk, passed by value (only 4-byte scalars, so OpenCL C and
// C++ lay it out alike).
typedef struct {
  float cameraInverse[16];  // clip -> world of the camera's raster view, row-major
  float sceneRadius;        // Scene::bounds().radius(): the ray offset's floor
  uint width, height;       // G-buffer pixels
  int samples;              // per pixel: 1, 4, 8 or 32
  int pattern;              // first pattern entry (izb_pattern_offset)
  uint pixelBegin;          // first pixel of this chunk
  uint sampleCount;         // samples of this chunk: pixels * samples
  uint cells;               // cells of the light grid
  uint alphaTested;         // 1 when the scene has alpha-tested casters (their texels are looked up), else 0
  // Area lights (izb_soft_*): the light's points per receiver sample, N (0: the hard path), and the light as the
  // reference samples it (tools/reference/light_samples.h): its kind (IZB_LIGHT_*), centre (spot, sphere), unit
  // direction towards a sun, the disk's or cone's basis (spot, sun; a sphere's disk faces each receiver), the disk's
  // radius (spot, sphere) or the cone's 1 - cos(angular radius) (sun).
  int lightSamples, lightKind;
  float lightCentre[3], toLight[3], lightTangent[3], lightBitangent[3];
  float lightRadius, lightOneMinusCos;
  // How far a segment from a receiver sample at light depth o_z to the light strays from the sample's own position,
  // in grid texels, where it passes light depth z: at most listReach (o_z - z) / ((o_z - R) z) on a spot grid, or
  // listReach (o_z - z) on a sun grid; listed casters are dilated by it (kernels/izb.cl izb_soft_reach).
  float listReach;
  // Work-group g of the sample kernels (izb_test, izb_soft_test) takes block g spread mod groups of the sorted samples
  // (izb_spread_sample): the sorted samples are a prefix of the launch, dense where the shadows are, and a CPU runtime
  // hands each thread a contiguous run of work-groups at once (PoCL: up to 512), so with the identity one thread gets
  // nearly all the work. On CPU devices a stride coprime to the group count near groups / golden ratio, which deals
  // each run its share of the prefix (default.json at 640x360: izb_soft_test 1.6x faster on two cores); 1 elsewhere,
  // keeping neighbouring cells in neighbouring work-groups.
  uint spread;
} IzbFrame;

#if PENUMBRA_HOST
static_assert(sizeof(IzbFrame) == 172, "IzbFrame layout must match OpenCL C");
#endif

// Area lights: the kinds of light the soft path samples, as tools/reference/light_samples.cpp does.
#define IZB_LIGHT_DISK 0    // a spot light: a disk of lightRadius at lightCentre, facing along the light's axis
#define IZB_LIGHT_SPHERE 1  // a point light: the disk of lightRadius through lightCentre facing the receiver
#define IZB_LIGHT_SUN 2     // a directional light: directions uniform over the cone of angular radius alpha
#define IZB_MIN_LIGHT_GRID 4
#define IZB_MAX_LIGHT_GRID 16  // --izb-light-samples: k^2 for k in 4..16 (16 .. 256)

// The side k of --izb-light-samples N's k x k pattern, or 0 unless N = k^2 with k in 4..16.
static inline int izb_light_grid_of(int samples) {
  for (int k = IZB_MIN_LIGHT_GRID; k <= IZB_MAX_LIGHT_GRID; ++k)
    if (k * k == samples) return k;
  return 0;
}

// A 32-bit integer hash (Wellons' "lowbias32", full avalanche): the light pattern's jitter and each pixel's turn of
// it, the same on every device and on the host.
static inline uint izb_hash(uint x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

// The light pattern (host/techniques/izb_pattern.h): turned per pixel by one of IZB_ROTATIONS angles, and its bitmask
// tables over IZB_MASK_ANGLES line normals times IZB_MASK_OFFSETS line offsets across [-1, 1] (the unit disk).
#define IZB_ROTATIONS 256
#define IZB_MASK_ANGLES 256
#define IZB_MASK_OFFSETS 64
#define IZB_MASK_MARGIN \
  1e-3f  // units of the light's radius: "may" and "certainly" inside a projected edge differ by it

// The rotation of pattern key `key` (a pixel, or a pixel's sub-pixel sample).
static inline uint izb_rotation_of(uint key) { return izb_hash(key) >> 24; }

// Clusters of IZB_CLUSTER casters (izb_soft_lists' unit, the last one padded): how many `triangles` make.
static inline uint izb_cluster_count(uint triangles) { return (triangles + IZB_CLUSTER - 1) / IZB_CLUSTER; }

// The soft lists' binning (izb_soft_tiles): clusters listed first in tiles of IZB_TILE_CELLS x IZB_TILE_CELLS cells,
// from which each cell then takes its own list (izb_soft_lists) without atomics.
#define IZB_TILE_CELLS 4
static inline uint izb_tiles_of(uint cells) { return (cells + IZB_TILE_CELLS - 1) / IZB_TILE_CELLS; }
// Cells of IZB_CELL_TEXELS along a grid side of `texels`.
static inline uint izb_cells_of(uint texels) { return (texels + IZB_CELL_TEXELS - 1) / IZB_CELL_TEXELS; }

// IzbFrame::spread on a CPU device for `groups` work-groups: the odd stride nearest groups / golden ratio that is
// coprime to it, so that g -> g stride mod groups is a permutation whose runs of consecutive g reach the whole range.
static inline uint izb_spread_stride(uint groups) {
  if (groups < 3u) return 1u;
  uint stride = (uint)((float)groups * 0.618034f) | 1u;
  for (;;) {
    uint a = groups, b = stride;  // gcd(groups, stride)
    while (b != 0u) {
      const uint r = a % b;
      a = b, b = r;
    }
    if (a == 1u) return stride;
    stride += 2u;
  }
}

// Jitter `axis` (0: x, 1: y) of point j of the pattern, in [0, 1): exactly 24 bits.
static inline float izb_jitter(uint j, uint axis) {
  return (float)(izb_hash(j * 2u + axis + 0x9e3779b9u) >> 8) * (1.0f / 16777216.0f);
}

// The angle bin of a line normal (x, y) in the masks: IZB_MASK_ANGLES bins uniform in its "diamond angle" (a
// monotonic stand-in for the polar angle in [0, 4), one division instead of an arc tangent), 0 for the zero vector.
// kernels/izb.cl izb_mask_angle_bins computes the same, lane by lane.
static inline int izb_mask_angle_bin(float x, float y) {
  const float ax = x < 0.0f ? -x : x, ay = y < 0.0f ? -y : y, sum = ax + ay;
  if (!(sum > 0.0f)) return 0;
  const float p = y >= 0.0f ? (x >= 0.0f ? y / sum : 1.0f - x / sum) : (x < 0.0f ? 2.0f - y / sum : 3.0f + x / sum);
  const int bin = (int)(p * (0.25f * (float)IZB_MASK_ANGLES));
  return bin < 0 ? 0 : bin >= IZB_MASK_ANGLES ? IZB_MASK_ANGLES - 1 : bin;
}

// Words of a mask of N points.
static inline int izb_mask_words(int samples) { return (samples + 31) / 32; }

// Sub-pixel sample offsets from the pixel centre, in pixels, x then y, for 1, 4, 8 and 32 samples per pixel (the
// counts of Wyman et al. 2015's antialiased variant): the centre; the 4x rotated grid and the 8x pattern of the
// Direct3D 11 standard multisample positions; the first 32 points of the Halton (2, 3) sequence, centred.
#define IZB_PATTERN_1_OFFSET 0
#define IZB_PATTERN_4_OFFSET 1
#define IZB_PATTERN_8_OFFSET 5
#define IZB_PATTERN_32_OFFSET 13
#define IZB_PATTERN_ENTRIES 45
#define IZB_PATTERN_VALUES                                                                                         \
  {0.0f, 0.0f, /* 4 */ -0.125f, -0.375f, 0.375f, -0.125f, -0.375f, 0.125f, 0.125f, 0.375f,                        \
   /* 8 */ 0.0625f, -0.1875f, -0.0625f, 0.1875f, 0.3125f, 0.0625f, -0.1875f, -0.3125f, -0.3125f, 0.3125f, -0.4375f, \
   -0.0625f, 0.1875f, 0.4375f, 0.4375f, -0.4375f,                                                                  \
   /* 32: Halton (2, 3) points 1..32 minus 0.5 */                                                                    \
   0.0f, -0.166666667f, -0.25f, 0.166666667f, 0.25f, -0.388888889f, -0.375f, -0.0555555556f, 0.125f, 0.277777778f,   \
   -0.125f, -0.277777778f, 0.375f, 0.0555555556f, -0.4375f, 0.388888889f, 0.0625f, -0.462962963f, -0.1875f,          \
   -0.12962963f, 0.3125f, 0.203703704f, -0.3125f, -0.351851852f, 0.1875f, -0.0185185185f, -0.0625f, 0.314814815f,    \
   0.4375f, -0.240740741f, -0.46875f, 0.0925925926f, 0.03125f, 0.425925926f, -0.21875f, -0.425925926f, 0.28125f,     \
   -0.0925925926f, -0.34375f, 0.240740741f, 0.15625f, -0.314814815f, -0.09375f, 0.0185185185f, 0.40625f,             \
   0.351851852f, -0.40625f, -0.203703704f, 0.09375f, 0.12962963f, -0.15625f, 0.462962963f, 0.34375f, -0.487654321f,  \
   -0.28125f, -0.154320988f, 0.21875f, 0.179012346f, -0.03125f, -0.37654321f, 0.46875f, -0.0432098765f, -0.484375f,  \
   0.290123457f}

// Samples per pixel of --izb-samples' choice `choice` (0..3: 1, 4, 8, 32).
static inline int izb_samples_of_choice(int choice) {
  return choice <= 0 ? 1 : choice == 1 ? 4 : choice == 2 ? 8 : IZB_MAX_SAMPLES;
}

// First entry (pair) of the pattern of `samples` per pixel (1, 4, 8 or 32), -1 for other counts.
static inline int izb_pattern_offset(int samples) {
  return samples == 1 ? IZB_PATTERN_1_OFFSET
                      : samples == 4 ? IZB_PATTERN_4_OFFSET
                                     : samples == 8 ? IZB_PATTERN_8_OFFSET : samples == 32 ? IZB_PATTERN_32_OFFSET : -1;
}

#endif
