// Variance soft shadow mapping (Yang, Dong, Feng, Seidel, Kautz, "Variance Soft Shadow Mapping", PG 2010),
// Algorithm 1 per pixel: blocker-search kernel from the light size (L7), lit/umbra early-out from the min-max
// HSM (L8-L10), average blocker depth from the SAT moments by eq. 4 (L15) or kernel subdivision (L12-L13),
// penumbra kernel by similar triangles (L16), contact PCF (sec. 6.4), visibility by the Chebyshev bound (L20)
// or subdivision (L18). Built with -DSAT_MODE=... -DSAT_CHANNELS=2 for the SAT's storage.
#include "kernels/shared/chebyshev.h"
#include "kernels/shared/map_trace.h"
#include "kernels/shared/moments.h"
#include "kernels/shared/shade.h"
#include "kernels/shared/vssm_subdivide.h"

// Sec. 4.2, eq. 4 with z_unocc = t: z_occ = (z_Avg - P t) / (1 - P) with P = sigma^2 / (sigma^2 + (t - mu)^2)
// (eq. 1). Rearranged to the identical mu - sigma^2 / (t - mu), which needs no division by 1 - P as P -> 1;
// callers clamp it into [zmin, t]. Requires mu < t.
inline float vssm_occluder(float2 e, float t, float minVariance) {
  return e.x - cheb_variance(e, minVariance) / (t - e.x);
}

// Beyond the paper: a disk light's kernels as disks. Yang et al.'s kernels are squares (one SAT box each), but a
// disk light reaches a receiver through a disk, and the square's corners are most of VSSM's error against PCSS's
// Poisson disk (docs/techniques/vssm.md). The disk of half-width w is K horizontal strips of equal height, each one
// SAT box whose half-width gives it the disk's area over its rows (so the strips cover pi w^2, as the disk does);
// K = min(diskStrips, ceil(2 w / satReduce)): at most one strip per row of the SAT's texels (blocks), one area-matched
// box for a kernel under one.
// diskStrips = 0 keeps the paper's square. Moments are the strips' area-weighted means; a "non-planarity" kernel
// subdivides every strip into the same accumulator (Algorithm 2's sums are sums over areas).
inline uint vssm_strip_count(const VssmMaps* m, float w) {
  return m->p.diskStrips == 0u ? 0u : clamp((uint)ceil(2.0f * w / (float)m->p.satReduce), 1u, m->p.diskStrips);
}

// Kernel [c - w, c + w]: the square itself (strips 0) or strip k of `strips`, whose half-width is the integral of the
// half chord sqrt(w^2 - y^2) over its rows divided by their height: w times a share that depends on k and the strip
// count alone, looked up (m->strips, made in double precision: host/techniques/vssm_maps.h vssmDiskStripTable).
inline void vssm_kernel_box(const VssmMaps* m, float2 c, float w, uint k, uint strips, float2* lo, float2* hi) {
  if (strips == 0u) {
    *lo = c - w, *hi = c + w;
    return;
  }
  const float h = 2.0f * w / (float)strips, ya = -w + h * (float)k, yb = ya + h;
  const float halfWidth = w * m->strips[strips * (strips - 1u) / 2u + k];
  *lo = (float2)(c.x - halfWidth, c.y + ya), *hi = (float2)(c.x + halfWidth, c.y + yb);
}

inline float2 vssm_kernel_moments(const VssmMaps* m, float2 c, float w) {
  const uint strips = vssm_strip_count(m, w);
  float2 sum = (float2)(0.0f), lo, hi;
  float area = 0.0f;
  for (uint k = 0; k < max(strips, 1u); ++k) {
    vssm_kernel_box(m, c, w, k, strips, &lo, &hi);
    const float a = (hi.x - lo.x) * (hi.y - lo.y);
    sum += vssm_box_moments(m, lo, hi) * a, area += a;
  }
  return sum / area;
}

// The strips share the square's subdivision budget: uniform, each strip is d wide and ceil(d / K) high; adaptive,
// each strip's tree is floor(log2(K) / 2) levels shallower (K strips of 4^-l the leaves each), at least one level.
// Beyond the paper, the budget follows the kernel's size in texels: no sub-kernel narrower than leafTaps texels (its
// leaf PCF would take more than a tap a texel, and the map holds nothing finer): uniform at most ceil(2w / leafTaps)
// a side, adaptive at most floor(log2(2w / leafTaps)) levels (at least one). A kernel of 2 w >= d leafTaps texels
// (uniform) or 2^H leafTaps (adaptive) is subdivided as the paper's.
inline void vssm_kernel_subdivide(const VssmMaps* m, const VssmReceiver* r, float2 c, float w, int search,
                                  VssmAccum* acc) {
  const uint scheme = search ? m->p.searchScheme : m->p.shadeScheme;
  const uint strips = vssm_strip_count(m, w), k = max(strips, 1u);
  const float side = 2.0f * w / (float)m->p.leafTaps;  // the kernel's width in leaf-PCF footprints
  const uint d = (uint)clamp(ceil(side), 1.0f, (float)(search ? m->p.searchDivisions : m->p.shadeDivisions));
  uint height = 0u, shallower = 0u, resolved = 1u;
  for (uint n = 1u; n < m->p.nodeCount; n = 4u * n + 1u) ++height;  // nodeCount = (4^(H+1) - 1) / 3
  for (uint q = 4u; q <= k; q *= 4u) ++shallower;                   // floor(log4 K)
  for (float s = 4.0f; s <= side && resolved < 16u; s *= 2.0f) ++resolved;  // floor(log2(side)), at least 1
  const uint maxLevel = min(height > shallower ? max(height - shallower, 1u) : 1u, resolved);
  float2 lo, hi;
  for (uint s = 0; s < k; ++s) {
    vssm_kernel_box(m, c, w, s, strips, &lo, &hi);
    if (scheme == VSSM_SCHEME_UNIFORM)
      vssm_uniform(m, r, lo, hi, d, (d + k - 1u) / k, search, acc);
    else
      vssm_adaptive(m, r, lo, hi, maxLevel, search, acc);
  }
}

// Beyond the paper: the fallback of a kernel whose blockers lie at several depths. Eq. 4's single blocker
// z_occ = mu - sigma^2 / (t - mu) is where all of them would sit if the kernel held one blocker depth and receivers at
// t, and the Chebyshev bound is tight for exactly that two-depth mix (Cantelli). One blocker depth puts z_occ at the
// kernel's nearest texel z_min; occluders stacked inside the kernel (a plate above a plate under a large light) put it
// between them, and there the bound overstates the lit share (P >= the true one), which also moves eq. 4's blocker
// towards the light (a wider penumbra kernel): both let light into the umbra (stacked planes, light radius 2: a
// quarter of the umbra pixels above 0.1; radius 3: four fifths). Where z_occ - z_min exceeds stackedSpread
// (t - z_min), the kernel is sampled instead: stackedTaps^2 jittered cells (Bavoil 2008's, as the contact PCF; on a
// disk kernel the taps inside the disk), in the search the mean depth of the taps that block (PCSS's blocker average,
// -1 for none), in the shading the lit share of bilinear comparisons. Subdividing would not help: Algorithm 2 pools
// its normal sub-kernels into one bound, the same mix again.
inline int vssm_stacked(const VssmMaps* m, float zocc, float zmin, float t) {
  return m->p.stackedSpread > 0.0f && zocc - zmin > m->p.stackedSpread * (t - zmin);
}

inline float vssm_stacked_taps(const VssmMaps* m, const VssmReceiver* r, float2 c, float w, int search) {
  const int taps = (int)m->p.stackedTaps;
  const uint n = (uint)(taps * taps);
  const float cell = 2.0f * w / (float)taps;
  float sum = 0.0f, count = 0.0f, blocked = 0.0f;
  for (int j = 0; j < taps; ++j)
    for (int i = 0; i < taps; ++i) {
      const uint tap = (r->seed * 2u * n + (search ? n : 0u) + (uint)(j * taps + i)) * 2u;
      const float2 pos = c - w + cell * (float2)((float)i + rot_hash01(tap), (float)j + rot_hash01(tap + 1u));
      if (m->p.diskStrips != 0u && length(pos - c) > w) continue;
      count += 1.0f;
      if (!search) {
        sum += sc_compare_bilinear(m->depth, m->lv->width, m->lv->height, pos, vssm_tap_depth(r, pos));
        continue;
      }
      const float z = sc_fetch(m->depth, m->lv->width, m->lv->height, (int)pn_floor(pos.x), (int)pn_floor(pos.y));
      if (z < vssm_tap_depth(r, pos)) {
        blocked += 1.0f;
        sum += (z - m->p.depthNear) * m->p.depthInvRange;
      }
    }
  if (search) return blocked > 0.0f ? sum / blocked : -1.0f;
  if (count > 0.0f) return sum / count;
  return sc_compare_bilinear(m->depth, m->lv->width, m->lv->height, c, vssm_tap_depth(r, c));  // no tap in the disk
}

// Beyond the paper (--vssm-search adaptive): whether any tap of the search kernel of half-width w can find a blocker,
// told from the HSM. L8 and the narrowing above read the square around the kernel and compare its nearest texel with
// the receiver's own t, the strictest comparison; a texel in its corner, one in front of t by less than the slope
// bias at its offset, or a caster at depth z farther from the receiver than the light's cone cut at z (the narrowed
// kernel is the cone cut at the square's nearest texel, which may lie elsewhere) passes that test, and such a kernel
// was subdivided only to find no blocker (under a radius-2 spot on default.json, 55,000 of 90,000 pixels at 21
// sub-kernels each). Here the square, widened by a texel, is covered by at most VSSM_BLOCKER_NODES nodes a side of the
// finest HSM level (or the map's texels), and a node whose nearest depth z_n is known holds no blocker for this
// receiver when it lies farther than min(w, the cone's half-width at z_n) from it (deeper texels' cones are narrower)
// or when z_n passes the strictest comparison a tap can make on it, t - tSlope d (d its distance, less a bilinear tap's
// reach where positive); each node's box is its nominal share of the map widened by one of its own texels (a level's
// texel covers no more). A node that fails is not the end: its children on the next finer level are tested in its place
// (depth first, down to the map's own texels), since a node's nearest depth may be the receiver's own surface, tilted
// to the light, whose texels each pass their own offset's bias; the search fails only at a texel that can block, or
// after VSSM_BLOCKER_BUDGET node tests (or a full stack). Tested before the kernel's moments are read: no node can hold
// a blocker, and the search ends with none (path 5) without moments or subdivision.
// Four nodes a side to start: eight made twice the node tests (default.json under a radius-2 spot: 2.6 M against 1.3
// M for the same answers), two 1.7 M and hit the budget on 45 pixels.
#define VSSM_BLOCKER_NODES 4
#define VSSM_BLOCKER_BUDGET 256
#define VSSM_BLOCKER_STACK 32

// Level l of the HSM as the descent reads it: the map itself at 0, else m->levels[l - 1].
inline PyramidLevel vssm_hsm_level(const VssmMaps* m, uint l) {
  const PyramidLevel base = {0u, m->lv->width, m->lv->height, 0u};
  return l > 0u ? m->levels[l - 1u] : base;
}

// Whether node (x, y) of HSM level l can hold a texel that blocks a tap of the search kernel of half-width w.
inline bool vssm_node_may_block(const VssmMaps* m, const VssmReceiver* r, float w, uint l, PyramidLevel level, int x,
                                int y) {
  __constant const LightViewGpu* lv = m->lv;
  const size_t at = (size_t)y * level.width + (size_t)x;
  const float nearest = l > 0u ? m->hsm[level.offset + at].x : m->depth[at];
  if (!isfinite(nearest)) return false;  // nothing drawn
  const float2 size = (float2)((float)lv->width, (float)lv->height);
  const float2 node = size / (float2)((float)level.width, (float)level.height);  // map texels per node
  // Halving exactly from the map (every size above even), a node covers exactly its share.
  const bool exact = level.width << l == lv->width && level.height << l == lv->height;
  const float2 overhang = exact ? (float2)(0.0f) : node;
  const float2 lo = (float2)((float)x, (float)y) * node - overhang;
  const float2 hi = (float2)((float)(x + 1), (float)(y + 1)) * node + overhang;
  const float reach = length(fmax(fmax(lo - r->uv, r->uv - hi), 0.0f)) - M_SQRT2_F;
  const float cone = clamp(lv_penumbra_texels(lv, r->depth, fmax(nearest, lv->zNear)), 0.5f, m->p.maxRadius);
  if (reach > fmin(w, cone)) return false;  // beyond the kernel, or beyond the cone its own depth cuts
  return moments_normalize(nearest, m->p.depthNear, m->p.depthInvRange) < r->t - r->tSlope * fmax(reach, 0.0f);
}

inline bool vssm_no_blocker(const VssmMaps* m, const VssmReceiver* r, float w) {
  __constant const LightViewGpu* lv = m->lv;
  const uint width = lv->width, height = lv->height;
  const float2 size = (float2)((float)width, (float)height);
  const float2 a = clamp(r->uv - (w + 1.0f), (float2)(0.0f), size), b = clamp(r->uv + (w + 1.0f), a, size);
  if (!(b.x > a.x && b.y > a.y)) return true;    // only texels beyond the map, which hold no occluder
  int2 sx, sy;
  const uint top =
      pyramid_cover_level(m->levels, m->p.pyramidLevels, width, height, a, b, VSSM_BLOCKER_NODES - 1, &sx, &sy);
  uint stack[VSSM_BLOCKER_STACK];  // (level << 28) | (y << 14) | x: map sides up to 8192 (--map-size)
  int budget = VSSM_BLOCKER_BUDGET;
  for (int y0 = sy.x; y0 <= sy.y; ++y0)
    for (int x0 = sx.x; x0 <= sx.y; ++x0) {
      int depth = 0;
      stack[depth++] = top << 28 | (uint)y0 << 14 | (uint)x0;
      while (depth > 0) {
        const uint e = stack[--depth], l = e >> 28;
        const int x = (int)(e & 0x3fffu), y = (int)((e >> 14) & 0x3fffu);
        if (--budget < 0) return false;
        const PyramidLevel level = vssm_hsm_level(m, l);
        if (!vssm_node_may_block(m, r, w, l, level, x, y)) continue;
        if (l == 0u) return false;  // a texel that can block
        // Its children on level l - 1 (its footprint there: 1, 2 or 3 a side) within the square.
        const PyramidLevel finer = vssm_hsm_level(m, l - 1u);
        const PyramidTaps t = pyramid_footprint((uint)x, (uint)y, finer, level);
        const int2 cx = pyramid_cover_span(a.x, b.x, width, finer.width);
        const int2 cy = pyramid_cover_span(a.y, b.y, height, finer.height);
        for (int j = max(t.y0, cy.x); j <= min(t.y0 + t.ny - 1, cy.y); ++j)
          for (int i = max(t.x0, cx.x); i <= min(t.x0 + t.nx - 1, cx.y); ++i) {
            if (depth == VSSM_BLOCKER_STACK) return false;
            stack[depth++] = (l - 1u) << 28 | (uint)j << 14 | (uint)i;
          }
      }
    }
  return true;
}

// Alg. 1 L11-L15: the average blocker depth (normalised) over the search kernel of half-width w at c, or -1 when
// nothing blocks. A "non-planarity" kernel is subdivided (sec. 5.2): d1 from the normal group (eq. 5, then eq. 4),
// d2 from the PCF leaves, combined weighted by their blocker areas.
inline float vssm_blocker_depth(const VssmMaps* m, const VssmReceiver* r, float2 c, float w, float zmin,
                                int* subdivided, int* visited, int* stacked) {
  const float minVariance = m->p.minVariance;
  // Beyond the paper, first: a kernel where no texel can block has no blocker, whatever its moments say (a receiver
  // tilted to the light puts its own surface in front of t over the kernel: z_Avg < t, a planar "blocker" no tap is).
  const int none = m->p.searchScheme == VSSM_SCHEME_NONE;
  if (!none && m->p.searchNarrowings > 0u && vssm_no_blocker(m, r, w)) return -1.0f;
  const float2 e = vssm_kernel_moments(m, c, w);
  // L15 on a planar kernel (z_Avg < t), guarded: as P -> 1 (the limit z_Avg -> t of the non-planarity case) eq. 4
  // amplifies the bound's error by 1 / (1 - P), so above planarMaxLit the kernel is subdivided as well.
  const int planar = e.x < r->t;
  if (planar && (none || cheb_upper_bound(e, r->t, minVariance) <= m->p.planarMaxLit)) {
    const float zocc = vssm_occluder(e, r->t, minVariance);
    if (vssm_stacked(m, zocc, zmin, r->t)) {  // blockers at several depths
      *stacked = 1;
      return vssm_stacked_taps(m, r, c, w, 1);
    }
    return clamp(zocc, zmin, r->t);
  }
  if (none) return -1.0f;  // z_Avg >= t read as "no blocker", as VSM does
  *subdivided = 1;
  VssmAccum acc = vssm_accum_zero();
  vssm_kernel_subdivide(m, r, c, w, 1, &acc);
  *visited += acc.visited;
  float blocked = acc.pcfBlocked, depthSum = acc.pcfDepth;
  if (acc.vsmArea > 0.0f) {
    const float2 g = (float2)(acc.m1, acc.m2) / acc.vsmArea;
    const float area = (1.0f - cheb_upper_bound(g, r->t, minVariance)) * acc.vsmArea;
    // The normal group pools its sub-kernels into one bound: stacked blockers there are sampled as on a planar kernel.
    if (area > 0.0f && vssm_stacked(m, vssm_occluder(g, r->t, minVariance), zmin, r->t)) {
      *stacked = 1;
      return vssm_stacked_taps(m, r, c, w, 1);
    }
    if (area > 0.0f) {
      const float d1 = vssm_occluder(g, r->t, minVariance) - acc.shift / acc.vsmArea;
      blocked += area;
      depthSum += clamp(d1, zmin, r->t) * area;
    }
  }
  return blocked > 0.0f ? depthSum / blocked : -1.0f;
}

// The lit share of a shading kernel whose moments are `e` (L20), beyond the paper with p.firstMoment: the smaller of
// Chebyshev's one-sided bound and the first moment's two-depth share with the blocker search's depth zocc (both
// normalised). Write the kernel's texels as a share p at depth t or behind (lit, mean m_l >= t) and 1 - p in front of
// it (blockers, mean m_b): E(x) = (1 - p) m_b + p m_l, so p = (E(x) - m_b) / (m_l - m_b) <= (E(x) - m_b) / (t - m_b),
// which grows as m_b falls while E(x) < t. Taking the search's average blocker depth (eq. 4) for m_b assumes the
// penumbra kernel's blockers lie at least that far on average; then it is another upper bound, equal to Chebyshev's
// for two depths. Where the blockers spread in depth, Chebyshev's bound admits more light (the variance they add reads
// as lit texels) and this one less. Measured in docs/techniques/vssm.md, "The first moment's bound".
inline float vssm_lit_share(const VssmMaps* m, const VssmReceiver* r, float2 e, float zocc) {
  const float chebyshev = cheb_upper_bound(e, r->t, m->p.minVariance);
  if (!m->p.firstMoment || !(zocc < r->t)) return chebyshev;
  return fmin(chebyshev, clamp((e.x - zocc) / (r->t - zocc), 0.0f, 1.0f));
}

// Alg. 1 L17-L20 and Alg. 2 L28-L31: visibility over the penumbra kernel of half-width w at c: the Chebyshev bound
// L of the normal group weighted by VSMArea, 1 by LitArea and the PCF result L1 by PCFArea.
// Beyond the paper, first: the HSM's range over the penumbra kernel, as L8-L10 over the search kernel (lit, or umbra
// whatever the moments say, which blockers at several depths spread), then vssm_stacked_taps where they do.
// Beyond the paper, too: a tilted receiver (--vssm-tilt). L20 reads a planar kernel (E(x) < t) as blockers and a
// receiver at the one depth t (sec. 4's planar receiver); a receiver whose own plane moves across the kernel by its
// slope-scaled bias per texel times w (sc_receiver_sloped: the plane's depth step per texel of offset; under a sun
// tan(theta) tan(alpha) of the gap) by more than p.tiltShare of the gap t - z_occ is no such receiver, and there the
// bound failed most: on default.json at 640x360 the 834 pixels it selects (the camera's sides lit at grazing, N.L
// 0.18-0.26, among them) had 3.6x the mean error of the pixels that reach the moments. Their kernel is filtered by
// vssm_stacked_taps, whose taps compare with the slope-scaled bias at their own offsets, as pcss's do. A kernel whose
// mean lies behind t is subdivided, as the paper does (docs/techniques/vssm.md, "Tilted receivers").
// `path`: VSSM_PATH_LIT, VSSM_PATH_UMBRA, VSSM_PATH_TILTED or VSSM_PATH_STACKED where those decided, else unchanged.
inline float vssm_shade(const VssmMaps* m, const VssmReceiver* r, float2 c, float w, float zocc, int* subdivided,
                        int* visited, int* path) {
  const float2 range = vssm_hsm_range(m, c - w, c + w);
  if (range.x >= r->t) {
    *path = VSSM_PATH_LIT;
    return 1.0f;
  }
  if (range.y < r->t - r->tSlope * w * M_SQRT2_F) {
    *path = VSSM_PATH_UMBRA;
    return 0.0f;
  }
  const float2 e = vssm_kernel_moments(m, c, w);
  if (e.x < r->t) {
    if (m->p.tiltShare > 0.0f && r->tSlope * w > m->p.tiltShare * (r->t - zocc)) {
      *path = VSSM_PATH_TILTED;
      return vssm_stacked_taps(m, r, c, w, 0);
    }
    if (vssm_stacked(m, vssm_occluder(e, r->t, m->p.minVariance), range.x, r->t)) {
      *path = VSSM_PATH_STACKED;
      return vssm_stacked_taps(m, r, c, w, 0);
    }
    return vssm_lit_share(m, r, e, zocc);
  }
  if (m->p.shadeScheme == VSSM_SCHEME_NONE) return 1.0f;
  *subdivided = 1;
  VssmAccum acc = vssm_accum_zero();
  vssm_kernel_subdivide(m, r, c, w, 0, &acc);
  *visited += acc.visited;
  float lit = acc.litArea + (acc.pcfArea - acc.pcfBlocked);
  if (acc.vsmArea > 0.0f) lit += vssm_lit_share(m, r, (float2)(acc.m1, acc.m2) / acc.vsmArea, zocc) * acc.vsmArea;
  return clamp(lit / (acc.litArea + acc.vsmArea + acc.pcfArea), 0.0f, 1.0f);
}

typedef struct VssmResult {
  float visibility;
  float blocker;   // average blocker depth, world units (0: none searched or found)
  float penumbra;  // penumbra kernel half-width, texels (0: not computed)
  int visited;     // sub-kernels visited by subdivision
  int path;        // VSSM_PATH_*
} VssmResult;

inline VssmReceiver vssm_receiver(const VssmMaps* m, float2 uv, float depth, float bias, float biasSlope, uint seed) {
  VssmReceiver r;
  r.uv = uv, r.depth = depth, r.bias = bias, r.biasSlope = biasSlope, r.seed = seed;
  // Normalised as the moments stage does; beyond the far plane (1) nothing is known to lie deeper.
  r.t = fmin((depth - bias - m->p.depthNear) * m->p.depthInvRange, 1.0f);
  r.tSlope = biasSlope * m->p.depthInvRange;
  return r;
}

// L7: the search kernel's half-width, the light seen from the receiver cut by the map plane (the near plane).
inline float vssm_search_width(const VssmMaps* m, float depth) {
  return clamp(lv_penumbra_texels(m->lv, depth, m->lv->zNear), 0.5f, m->p.maxRadius);
}

// L8's lit test on L7's kernel, the first test vssm_pixel makes: exactly its answer for a receiver whose t is at least
// as strict (a smaller bias).
inline bool vssm_lit_at_once(const VssmMaps* m, const VssmReceiver* r) {
  const float wi = vssm_search_width(m, r->depth);
  return vssm_hsm_range(m, r->uv - wi, r->uv + wi).x >= r->t;
}

// A lit pixel's result (L8's early-out).
inline VssmResult vssm_lit(void) {
  const VssmResult lit = {1.0f, 0.0f, 0.0f, 0, VSSM_PATH_LIT};
  return lit;
}

inline VssmResult vssm_pixel(const VssmMaps* m, VssmReceiver r) {
  VssmResult out = vssm_lit();
  __constant const LightViewGpu* lv = m->lv;
  float wi = vssm_search_width(m, r.depth);
  float2 range;
  for (uint step = 0;; ++step) {
    range = vssm_hsm_range(m, r.uv - wi, r.uv + wi);
    // L8-L10, conservative for the slope bias as well: lit when every texel passes the strictest comparison
    // (the centre's), umbra when every texel fails the most lenient one (the kernel corner's).
    if (range.x >= r.t) return out;
    if (range.y < r.t - r.tSlope * wi * M_SQRT2_F) {
      out.visibility = 0.0f;
      out.path = VSSM_PATH_UMBRA;
      return out;
    }
    // Beyond the paper (pcss's adaptive search, kernels/pcss.cl): no texel of the kernel lies nearer than the HSM's
    // minimum, and a blocker at depth z >= z_min hides the light only inside the light's cone cut at z, which
    // narrows as z grows. The kernel cut at z_min holds every texel that can block: a lit receiver on a surface
    // tilted to the light (most of a frame) shrinks its kernel to a few texels and leaves by L8 instead of
    // subdividing a kernel sized for a caster at the near plane.
    if (step >= m->p.searchNarrowings) break;
    const float nearest = m->p.depthNear + range.x / m->p.depthInvRange;
    const float narrowed = clamp(lv_penumbra_texels(lv, r.depth, fmax(nearest, lv->zNear)), 0.5f, m->p.maxRadius);
    if (!(narrowed < wi)) break;
    wi = narrowed;
  }
  int subdivided = 0, stacked = 0;
  // The HSM tests above read the square around the kernel: conservative for a disk inside it.
  const float zocc = vssm_blocker_depth(m, &r, r.uv, wi, range.x, &subdivided, &out.visited, &stacked);
  if (zocc < 0.0f) {
    out.path = VSSM_PATH_NO_BLOCKER;
    return out;
  }
  out.blocker = m->p.depthNear + zocc / m->p.depthInvRange;
  const float wp = clamp(lv_penumbra_texels(lv, r.depth, out.blocker), 0.5f, m->p.maxRadius);  // L16
  out.penumbra = wp;
  if (r.depth - out.blocker < m->p.contactDepth) {  // sec. 6.4
    out.visibility = vssm_contact_pcf(m, &r, r.uv - wp, r.uv + wp);
    out.path = VSSM_PATH_CONTACT;
    return out;
  }
  int path = -1;
  out.visibility = vssm_shade(m, &r, r.uv, wp, zocc, &subdivided, &out.visited, &path);
  out.path = path >= 0 ? path : subdivided ? VSSM_PATH_SUBDIVIDED : VSSM_PATH_PLANAR;
  // A search kernel of stacked blockers: its segments traced as well, where they hide more
  // (kernels/shared/map_trace.h).
  if (stacked && m->p.stackedTrace && out.visibility > 0.0f)
    out.visibility = fmin(out.visibility, map_trace(m->depth, lv, r.uv, r.depth, r.bias, r.biasSlope, wi, r.seed));
  return out;
}

inline void vssm_store(VssmResult res, uint i, __global float4* debug, __global float* visibility) {
  visibility[i] = res.visibility;
  debug[i] = (float4)(res.blocker, res.penumbra, (float)res.visited, (float)res.path);
}

// Per camera pixel; debug = (blocker depth, penumbra half-width, sub-kernels visited, path; -1 for background).
__kernel void vssm_visibility(__global const float4* position, __global const float4* normal,
                              __global const float* depth, __constant const LightViewGpu* lv, ShadeFrame f,
                              __global const SAT_T* sat, SatTableDesc desc, __global const float* satOffset,
                              __global const float2* hsm, __constant const PyramidLevel* levels,
                              __constant const VssmNode* nodes, __constant const float* strips, VssmParams params,
                              __global float4* debug, __global float* visibility) {
  const uint count = f.width * f.height;
  const uint i = get_global_id(0);
  if (i >= count) return;
  visibility[i] = 1.0f;
  debug[i] = (float4)(0.0f, 0.0f, 0.0f, -1.0f);
  pyramid_prefetch_ahead(position, lv, depth, hsm, levels, params.pyramidLevels, i + PN_PREFETCH_AHEAD, count);
  const float4 p = position[i];
  if (p.w == 0.0f) return;
  const ShadowBias bias = {f.biasConstant, f.biasSlope, f.normalOffset};
  const float3 n = normal[i].xyz;
  const Receiver flat = sc_receiver_unsloped(lv, p.xyz, n, bias);
  if (!flat.valid) return;
  const VssmMaps m = {sat, satOffset, depth, hsm, levels, nodes, strips, lv, desc, params};
  // Beyond the paper, as pcss: L8's first lit test against the constant bias alone, which the slope-scaled bias can
  // only make more lenient. A pixel it lets go is lit whatever its slope (most of a frame: the casters' HSM holds
  // nothing near it) and skips the slope's four projections; the others take sc_receiver's receiver, the same results.
  const VssmReceiver unsloped = vssm_receiver(&m, flat.uv, flat.depth, flat.texel * bias.base, 0.0f, i);
  if (vssm_lit_at_once(&m, &unsloped)) {
    vssm_store(vssm_lit(), i, debug, visibility);
    return;
  }
  const Receiver rc = sc_receiver_sloped(lv, flat, p.xyz, n, bias);
  vssm_store(vssm_pixel(&m, vssm_receiver(&m, rc.uv, rc.depth, rc.bias, rc.biasSlope, i)), i, debug, visibility);
}
