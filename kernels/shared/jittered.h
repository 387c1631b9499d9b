// The jittered technique's shading constants and counter layout, shared by host/techniques/jittered.cpp and
// kernels/jittered.cl (valid OpenCL C and C++).
#ifndef PENUMBRA_KERNELS_SHARED_JITTERED_H
#define PENUMBRA_KERNELS_SHARED_JITTERED_H

#include "kernels/shared/common.h"

// Accumulation modes (Luksch sec. 6.2-6.3), the --confidence choices in this order.
#define JITTER_SIMPLE 0
#define JITTER_ADAPTED 1
#define JITTER_OPTIMAL 2

// Counters a pass raises per pixel (bit k counts into counters[k]): receivers it tested, pixels whose visibility
// it changed (a more confident lookup with the other result; simple: turned to shadow), pixels still below the
// confidence they need after it, pixels a later pass can still change (appended to the next pass's work list).
#define JITTER_COUNT_COVERED 1u
#define JITTER_COUNT_CHANGED 2u
#define JITTER_COUNT_UNCONFIDENT 4u
#define JITTER_COUNT_ACTIVE 8u
#define JITTER_ACTIVE 3
// counters[4..7]: the texel box (min x, min y, max x, max y) of the lookups still unconfident after the pass, so
// the next pass draws only that part of its map (a scissor).
#define JITTER_COUNTERS 8
#define JITTER_BOX_MIN_X 4
// Texels around an unconfident lookup the next pass must draw (its scissor box and tile mask): the next jitter moves
// a lookup by less than one, the ID buffer or the agreement test reads one further, one for rounding.
#define JITTER_DRAW_MARGIN 3

// Work-group size of the jittered kernels (their local tile lists).
#define JITTER_GROUP 64

// The kept confidence of a pixel settled by its lookups' neighbourhoods (optimal with agreement): final, above any
// confidence of eq. 4-6. The neighbourhood: the texels within this radius (max norm) of the lookup's.
#define JITTER_SETTLED 2.0f
#define JITTER_AGREEMENT_RADIUS 1
#define JITTER_NEIGHBOURS ((2 * JITTER_AGREEMENT_RADIUS + 1) * (2 * JITTER_AGREEMENT_RADIUS + 1))

typedef struct JitterShade {
  int mode;          // JITTER_*
  float threshold;   // simple: the confidence a lookup needs to add shadow
  int agreement;     // optimal: consecutive agreeing passes that settle a pixel (0: off)
  float precision;   // optimal: eq. 5's required precision (--jitter-precision)
  int tilesX, tilesY;  // the next pass's tile mask (0: the kernels mark nothing)
  int tileSize;        // pixels per side of a mask tile (RASTER_TILE_SIZE)
  // Exact edges (kernels/shared/exact_edges.h): pass 0 settles a pixel whose texels disagree by its shadow ray (1) or
  // not (0); whether the scene has alpha-tested casters; the scene's radius.
  int exactEdges;
  uint alphaTested;
  float sceneRadius;
  uint triangleCount;
} JitterShade;

// What changes from pass to pass: its number, its work list and, for jittered_pass, its texel transform from pass 0's
// map (host/techniques/jittered.cpp's texelTransform) and that map's size and far plane.
typedef struct JitterPass {
  pn_float4 jitter;        // (s cos, s sin, shift x, shift y)
  int mapWidth, mapHeight;
  float mapFar;            // the reduced map's far plane: farther receivers are not in it
  int pass;                // 0 the first pass
  uint count;              // pixels on the work list
  int idMode;              // ID_BUFFER_* (kernels/shared/id_buffer.h)
  int pad[2];
} JitterPass;

// One receiver's state across a frame's passes, in one 64-byte line so that a later pass, which reads its listed
// pixels scattered over the frame, touches one line per pixel: pass 0's lookup (later passes move it with their
// jitter instead of projecting again), eq. 5's slack, and what the accumulation keeps.
typedef struct JitterPixel {
  float u, v;      // pass 0's continuous texel position of the lookup
  float depth;     // the biased receiver depth there (as sc_hard_lit compares it)
  float valid;     // 1: pass 0 made the lookup (a covered receiver in front of the light)
  float gu, gv;    // the receiver plane's depth gradient per texel
  float idU, idV;  // the ID buffer lookup's texel position
  float slack;     // eq. 5's 1 - optConf in pass 0's texels (optimal; background 1), else 0
  float kept;      // the kept result's confidence: -1 none yet, JITTER_SETTLED settled
  float lit;       // the kept result (the pixel's visibility)
  uint streak;     // consecutive passes whose lookup's neighbourhood agreed with the kept result
  float pass;      // the pass (1-based) that set the kept result; 0 none (the passes-used AOV)
  float unused[3];
} JitterPixel;

#if PENUMBRA_HOST
static_assert(sizeof(JitterShade) == 44 && offsetof(JitterShade, tileSize) == 24, "JitterShade as in OpenCL C");
static_assert(sizeof(JitterPass) == 48 && offsetof(JitterPass, mapWidth) == 16 && offsetof(JitterPass, idMode) == 36,
              "JitterPass as in OpenCL C");
static_assert(sizeof(JitterPixel) == 64, "JitterPixel is one cache line, laid out as in OpenCL C");
#endif

#endif
