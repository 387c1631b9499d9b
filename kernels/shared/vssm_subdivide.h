// VSSM kernel subdivision (Yang et al. 2010, sec. 5): the sub-kernels of a "non-planarity" kernel are sorted
// into fully lit (E(x) >= t and sigma^2 < Threshold, sec. 5.2 last paragraph / Alg. 2 L9-L11), normal
// (E(x) < t: accumulated into one Chebyshev group, eq. 5 / Alg. 2 L13-L17) and, at leaves, "non-planarity"
// sub-kernels shaded by PCF (sec. 5.1 option 2 / Alg. 2 L22-L26). Uniform (sec. 5.2) and adaptive
// (sec. 5.3, stack-less linear quad-tree traversal) drivers. OpenCL C only.
#ifndef PENUMBRA_KERNELS_SHARED_VSSM_SUBDIVIDE_H
#define PENUMBRA_KERNELS_SHARED_VSSM_SUBDIVIDE_H

#include "kernels/shared/chebyshev.h"
#include "kernels/shared/vssm_lookup.h"

// Algorithm 2's running sums (VSMEx, VSMEx2, VSMArea, LitArea, PCFArea, PCFBArea) plus what the blocker
// search needs: the depth shift of the normal group and the blocker depth found by the PCF leaves.
typedef struct VssmAccum {
  float m1, m2;      // sum of E(x) T and E(x^2) T over normal sub-kernels (eq. 5 numerators)
  float vsmArea;     // sum of T over normal sub-kernels
  float shift;       // sum of delta T over normal sub-kernels (the slope bias folded into their moments)
  float litArea;     // fully lit sub-kernels
  float pcfArea;     // PCF leaves
  float pcfBlocked;  // PCFBArea: sum of T * (occluding taps / taps)
  float pcfDepth;    // search only: sum of T * (sum of occluding tap depths / taps), normalised depth
  int visited;       // sub-kernels whose moments were read
} VssmAccum;

inline VssmAccum vssm_accum_zero(void) {
  VssmAccum a = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0};
  return a;
}

// Blocker search leaf: taps x taps point samples; blockers add their depth (sec. 5.2, "m points are sampled
// in w_ck and the sum of all the blocker depth samples are computed").
inline void vssm_leaf_search(const VssmMaps* m, const VssmReceiver* r, float2 lo, float2 hi, VssmAccum* acc) {
  const int taps = (int)m->p.leafTaps;
  const float2 step = (hi - lo) / (float)taps;
  float blocked = 0.0f, depthSum = 0.0f;
  for (int j = 0; j < taps; ++j)
    for (int i = 0; i < taps; ++i) {
      const float2 pos = lo + step * (float2)((float)i + 0.5f, (float)j + 0.5f);
      const float z = sc_fetch(m->depth, m->lv->width, m->lv->height, (int)pn_floor(pos.x), (int)pn_floor(pos.y));
      if (z < vssm_tap_depth(r, pos)) {
        blocked += 1.0f;
        depthSum += (z - m->p.depthNear) * m->p.depthInvRange;
      }
    }
  const float area = (hi.x - lo.x) * (hi.y - lo.y), weight = area / (float)(taps * taps);
  acc->pcfArea += area;
  acc->pcfBlocked += weight * blocked;
  acc->pcfDepth += weight * depthSum;
}

// Shading leaf: taps x taps bilinear comparisons (Alg. 2 L22-L24).
inline void vssm_leaf_shade(const VssmMaps* m, const VssmReceiver* r, float2 lo, float2 hi, VssmAccum* acc) {
  const int taps = (int)m->p.leafTaps;
  const float2 step = (hi - lo) / (float)taps;
  float lit = 0.0f;
  for (int j = 0; j < taps; ++j)
    for (int i = 0; i < taps; ++i) {
      const float2 pos = lo + step * (float2)((float)i + 0.5f, (float)j + 0.5f);
      lit += sc_compare_bilinear(m->depth, m->lv->width, m->lv->height, pos, vssm_tap_depth(r, pos));
    }
  const float area = (hi.x - lo.x) * (hi.y - lo.y);
  acc->pcfArea += area;
  acc->pcfBlocked += area * (1.0f - lit / (float)(taps * taps));
}

// One sub-kernel w_ci = [lo, hi] (Alg. 2 L6-L26). Its moments are shifted by delta, the slope bias at its
// centre, so that comparing with the receiver's t equals comparing with the bias at the sub-kernel (the PCF
// taps' rule, which keeps tilted receivers from shadowing themselves). Returns 1 when the traversal must
// descend (a "non-planarity" inner node), else 0.
inline int vssm_visit(const VssmMaps* m, const VssmReceiver* r, float2 lo, float2 hi, int leaf, int search,
                      VssmAccum* acc) {
  acc->visited++;
  const float2 e = vssm_box_moments(m, lo, hi);
  const float area = (hi.x - lo.x) * (hi.y - lo.y);
  const float delta = r->tSlope * length(0.5f * (lo + hi) - r->uv);
  const float mean = e.x + delta, meanSq = e.y + delta * (2.0f * e.x + delta), variance = e.y - e.x * e.x;
  // L9-L11: nearly planar and behind: lit. Judged with the bias of the sub-kernel's point nearest the receiver,
  // the strictest any of its taps gets, so that a large node is not declared lit on its centre's lenient bias.
  const float nearest = r->tSlope * length(fmax(fmax(lo - r->uv, r->uv - hi), (float2)(0.0f)));
  if (e.x + nearest >= r->t && variance < m->p.litVariance) {
    acc->litArea += area;
    return 0;
  }
  // L13-L17: Chebyshev holds for this sub-kernel. In the blocker search an inner node whose bound P exceeds the
  // eq. 4 guard is refined instead (P -> 1 is the limit of the non-planarity case, z_Avg -> t).
  const int guarded =
      search && !leaf && cheb_upper_bound((float2)(mean, meanSq), r->t, m->p.minVariance) > m->p.planarMaxLit;
  if (mean < r->t && !guarded) {
    acc->m1 += mean * area;
    acc->m2 += meanSq * area;
    acc->vsmArea += area;
    acc->shift += delta * area;
    return 0;
  }
  if (!leaf) return 1;  // L19-L20
  if (search)
    vssm_leaf_search(m, r, lo, hi, acc);
  else
    vssm_leaf_shade(m, r, lo, hi, acc);
  return 0;
}

// Sec. 5.2: nx x ny equal sub-kernels, each a leaf (the paper's m x m or n x n on a square kernel).
inline void vssm_uniform(const VssmMaps* m, const VssmReceiver* r, float2 lo, float2 hi, uint nx, uint ny, int search,
                         VssmAccum* acc) {
  const float2 step = (hi - lo) / (float2)((float)nx, (float)ny);
  for (uint j = 0; j < ny; ++j)
    for (uint i = 0; i < nx; ++i) {
      const float2 a = lo + step * (float2)((float)i, (float)j);
      vssm_visit(m, r, a, a + step, 1, search, acc);
    }
}

// Sec. 5.3 / Alg. 2 L3-L27: linear traversal of the full quad-tree of height H over [lo, hi] by its Child and
// Next links (Bunnell 2005), no stack: a node that needs refining goes to Child, every other to Next. Nodes at
// `maxLevel` are leaves (a disk strip's shallower tree; H for the paper's square).
inline void vssm_adaptive(const VssmMaps* m, const VssmReceiver* r, float2 lo, float2 hi, uint maxLevel, int search,
                          VssmAccum* acc) {
  uint node = 0;
  while (node < m->p.nodeCount) {
    const VssmNode n = m->nodes[node];
    const float2 size = (hi - lo) / (float)(1u << n.level);
    const float2 a = lo + size * (float2)((float)(n.cell & 0xffffu), (float)(n.cell >> 16));
    const int leaf = n.child == VSSM_NO_NODE || n.level >= maxLevel;
    const int descend = vssm_visit(m, r, a, a + size, leaf, search, acc) && !leaf;
    node = descend ? n.child : n.next;
  }
}

#endif
