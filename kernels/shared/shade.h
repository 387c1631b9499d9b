// The scalars of the shadow-map visibility kernels (sm_visibility, pcf_visibility, pcss_visibility) as structs
// passed by value, filled once on the host (host/techniques/shadow_map.h's launchVisibility and the technique):
// ShadeFrame for what every launch has (the frame's size, the receiver bias, the receiver plane, the ID buffer),
// PcfShade and PcssShade for each filter's own. The buffers stay positional arguments. Shared by host and kernels.
#ifndef PENUMBRA_KERNELS_SHARED_SHADE_H
#define PENUMBRA_KERNELS_SHARED_SHADE_H

#include "kernels/shared/common.h"

// How the filters place their taps (pcf's and pcss's --*-pattern / --pcf-poisson-taps).
#define SHADE_PATTERN_GRID 0     // a regular grid of taps x taps texels
#define SHADE_PATTERN_POISSON 1  // a Poisson disk rotated per pixel

typedef struct ShadeFrame {
  uint width, height;  // G-buffer pixels (row 0 at the bottom)
  float biasConstant;  // ShadowBias.base: texel footprints at the receiver
  float biasSlope;     // ShadowBias.slope: times the receiver's depth slope
  float normalOffset;  // ShadowBias.normalOffset
  int receiverPlane;   // 1: the receiver-plane depth bias (sc_receiver_plane)
  int idMode;          // ID_BUFFER_* (kernels/shared/id_buffer.h): sm and pcf; 0 (off) elsewhere
} ShadeFrame;

typedef struct PcfShade {
  int radius;       // the grid's half width in taps: (2 radius + 1)^2 of them
  int adaptive;     // 1: widened to the pixel's footprint in the map, up to maxRadius
  float maxRadius;  // texels
  int poissonTaps;  // 0: the (2 radius + 1)^2 grid; else this many rotated Poisson taps
  float width;      // the kernel's half width in texels (radius, or wider under --pcf-radius auto: the taps spread)
} PcfShade;

// PcssShade.autoTaps: which tap counts follow each pixel's region (--pcss-search-taps / --pcss-filter-taps auto).
#define PCSS_AUTO_SEARCH 1
#define PCSS_AUTO_FILTER 2
// Under auto a region of half-width r texels gets density * pi r^2 taps (its disk's texels times the density), at least
// the fewest and at most the setting's most (kernels/pcss.cl pcss_tap_count). A small region needs few taps to see
// every texel it holds; a wide one is sampled at the most, so that a finer map, whose regions span more texels, never
// gets fewer taps than a coarser one. Measured on scenes/default.json and builtin:staircase
// (docs/techniques/sm-pcf-pcss.md, "Taps from the region").
#define PCSS_SEARCH_DENSITY 0.1f
#define PCSS_FILTER_DENSITY 1.0f
#define PCSS_SEARCH_FEWEST 9
#define PCSS_FILTER_FEWEST 36

typedef struct PcssShade {
  int searchTaps, filterTaps;  // taps per side of the blocker search and the filter (squared on Poisson disks); the
                               // most under auto
  float maxRadius;             // texels: the largest search and filter radius
  int pattern;                 // SHADE_PATTERN_*
  int adaptive;                // 1: the blocker search bounded by the min-max pyramid (levelCount levels above the map)
  uint levelCount;
  int autoTaps;  // PCSS_AUTO_* bits
  int umbra;     // 1: with the pyramid, a pixel whose every search tap blocks is tested for umbra before the filter
  int stackedTrace;  // 1: a search whose blockers lie at several depths also traces the pixel
                     // (kernels/shared/map_trace.h)
  int sparseTaps;    // 1: a filter whose taps are sparse compares the texel under each (sc_sparse_taps)
} PcssShade;

#if PENUMBRA_HOST
static_assert(sizeof(ShadeFrame) == 28 && offsetof(ShadeFrame, idMode) == 24, "ShadeFrame is shared with OpenCL C");
static_assert(sizeof(PcfShade) == 20 && offsetof(PcfShade, width) == 16, "PcfShade is shared with OpenCL C");
static_assert(sizeof(PcssShade) == 40 && offsetof(PcssShade, sparseTaps) == 36, "PcssShade is shared with OpenCL C");
#endif

#endif  // PENUMBRA_KERNELS_SHARED_SHADE_H
