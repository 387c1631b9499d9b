// Variance soft shadow mapping (Yang et al., "Variance Soft Shadow Mapping", PG 2010): the parameters, the
// quad-tree node of the adaptive kernel subdivision (sec. 5.3, Fig. 5: Child/Next links after Bunnell 2005)
// and the per-pixel path codes shared by host and kernels. Depths inside the algorithm are normalised as the
// moments stage does: t = (d - depthNear) * depthInvRange, background and NaN = 1 (no occluder).
#ifndef PENUMBRA_KERNELS_SHARED_VSSM_H
#define PENUMBRA_KERNELS_SHARED_VSSM_H

#include "kernels/shared/common.h"

// How one step (blocker search or shading) treats a "non-planarity" kernel, z_Avg >= t (sec. 5.1).
#define VSSM_SCHEME_NONE 0      // assume lit, as VSM/SAVSM do (the error the paper removes)
#define VSSM_SCHEME_UNIFORM 1   // sec. 5.2: m x m (search) or n x n (shading) equal sub-kernels
#define VSSM_SCHEME_ADAPTIVE 2  // sec. 5.3, Algorithm 2: linear quad-tree traversal of height H

// The path a pixel took (debug channel path.Z).
#define VSSM_PATH_LIT 0  // min-max HSM: every texel of the search (Alg. 1 L8) or penumbra kernel is behind the receiver
#define VSSM_PATH_UMBRA 1       // min-max HSM: every texel of the search (Alg. 1 L8) or penumbra kernel blocks
#define VSSM_PATH_PLANAR 2      // blocker depth and visibility from one Chebyshev bound each (L15, L20)
#define VSSM_PATH_SUBDIVIDED 3  // the search or the shading kernel was subdivided (L12, L18)
#define VSSM_PATH_CONTACT 4     // contact shadow: 3x3 jittered bilinear PCF (sec. 6.4)
#define VSSM_PATH_NO_BLOCKER 5  // the blocker search found no blocker: lit
#define VSSM_PATH_STACKED 6     // the penumbra kernel's blockers lie at several depths: jittered PCF (vssm.cl)
#define VSSM_PATH_TILTED 7      // the receiver's plane spans too much of the kernel's depth gap: jittered PCF (vssm.cl)

// Beyond the paper: a disk kernel as at most this many strips (--vssm-disk-strips); the strips' half-widths, as shares
// of the disk's half-width, are a table of K (K - 1) / 2 + k for strip k of K (vssmDiskStripTable).
#define VSSM_MAX_DISK_STRIPS 32
#define VSSM_MAX_LEVELS 5     // quad-tree height H: 4^5 = 1024 leaves, 1365 nodes (21 KiB of __constant)
#define VSSM_NO_NODE 0xffffu  // Child of a leaf

// One node of the full quad-tree over a filter kernel, in depth-first order: the root (level 0) is the kernel,
// a node at `level` covers the cell (x, y) of a 2^level x 2^level grid over it. `child` is the first child
// (VSSM_NO_NODE for a leaf), `next` the node that follows the node's subtree (the node count for none).
typedef struct VssmNode {
  uint cell;   // x | y << 16
  uint level;  // 0 = root
  uint child;
  uint next;
} VssmNode;

typedef struct VssmParams {
  float depthNear;       // light depth mapped to 0 (the moments stage's depthNear)
  float depthInvRange;   // 1 / (depthFar - depthNear)
  float litVariance;     // sec. 6.5 Threshold: sigma^2 below it with E(x) >= t marks a sub-kernel lit (normalised)
  float contactDepth;    // sec. 6.4 epsilon: d - z_occ below it (world units) selects contact PCF; 0 disables
  float maxRadius;       // largest search / penumbra half-width, texels
  float minVariance;     // sigma^2 floor of every Chebyshev bound (normalised depth^2)
  uint searchScheme;     // VSSM_SCHEME_* for the blocker search (Alg. 1 L12)
  uint shadeScheme;      // VSSM_SCHEME_* for the shading (Alg. 1 L18)
  uint searchDivisions;  // m: uniform search sub-kernels per side (sec. 6.2)
  uint shadeDivisions;   // n: uniform shading sub-kernels per side
  uint leafTaps;         // PCF taps per side in a "non-planarity" leaf (sec. 5.1 option 2: 2 x 2)
  uint nodeCount;        // quad-tree nodes, (4^(H+1) - 1) / 3
  uint pyramidLevels;    // levels 1.. of the min-max HSM (level 0 is the depth map)
  float planarMaxLit;    // guard of eq. 4: above this Chebyshev P the search kernel is subdivided (1: never)
  uint diskStrips;       // beyond the paper: 0 the square kernels of Yang et al., else at most this many disk strips
  float stackedSpread;   // beyond the paper: eq. 4's blocker this far past the nearest texel, over t - nearest, selects
                         // the jittered taps of a stacked-blocker search or penumbra kernel (0: never)
  uint stackedTaps;      // the fallback's jittered taps per side
  uint searchNarrowings;  // beyond the paper: narrowings of the search kernel by its nearest texel (0: L7's kernel)
  uint satReduce;         // beyond the paper: map texels per SAT texel along each side (1: the paper's, one per texel)
  uint stackedTrace;      // beyond the paper: a stacked search kernel's receiver also traced through the map (1)
  uint satX, satY;        // beyond the paper: the window of map texels the SAT covers (vssmCastersWindow): its
  uint satWidth, satHeight;  // origin and size; (0, 0) and the map's size for the whole map
  uint firstMoment;          // beyond the paper: a shading kernel's Chebyshev bound also capped by its first moment (1)
  float tiltShare;  // beyond the paper: a planar penumbra kernel over which the receiver's plane moves by more than
                    // this share of t - z_occ is filtered by the jittered taps (0: never)
  uint pad[2];
} VssmParams;

#if PENUMBRA_HOST
static_assert(sizeof(VssmNode) == 16, "VssmNode layout is shared with OpenCL C");
static_assert(sizeof(VssmParams) == 112, "VssmParams layout is shared with OpenCL C");
static_assert(offsetof(VssmParams, searchScheme) == 24 && offsetof(VssmParams, pyramidLevels) == 48);
#endif

#endif
