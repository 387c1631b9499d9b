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
#define IZB_MAX_SAMPLES 32
#define IZB_CELL_TEXELS 8  // cell side in texels: the rasterizer's tile (RASTER_TILE_SIZE; the host asserts them equal)
#define IZB_CHUNK_SAMPLES (1u << 24)  // default --izb-chunk: samples binned and tested per pass, 8 bytes each
// Shadow-ray origins leave the surface by IZB_RAY_OFFSET * max(|p|_inf, scene radius), the reference tracer's
// ShadowTracer::kRayOffset (tools/reference/tracer.h; a test holds them equal).
#define IZB_RAY_OFFSET 1e-4f

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
} IzbFrame;

#if PENUMBRA_HOST
static_assert(sizeof(IzbFrame) == 100, "IzbFrame layout must match OpenCL C");
#endif

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
