// VSSM lookups (Yang et al. 2010): mean moments of a box from the SAT (sec. 4.1, Alg. 1 L3), the depth range of
// a box from the min-max hierarchical shadow map (sec. 6.1, mip-map HSM), point and bilinear PCF taps
// (sec. 5.1 option 2, sec. 6.4) and the jitter of the contact PCF. OpenCL C only; include after
// kernels/shared/sat.h with SAT_CHANNELS=2.
#ifndef PENUMBRA_KERNELS_SHARED_VSSM_LOOKUP_H
#define PENUMBRA_KERNELS_SHARED_VSSM_LOOKUP_H

#include "kernels/shared/moments.h"
#include "kernels/shared/pyramid.h"
#include "kernels/shared/rotation.h"
#include "kernels/shared/sat.h"
#include "kernels/shared/shadow_common.h"
#include "kernels/shared/vssm.h"

// Everything one pixel reads.
typedef struct VssmMaps {
  __global const SAT_T* sat;        // SAT of the normalised VSM moments (z, z^2)
  __global const float* satOffset;  // fp32 tables: the offset; unused otherwise
  __global const float* depth;      // the light's linear depth map (+INFINITY where empty)
  __global const float2* hsm;       // levels 1.. of the depth's min-max pyramid (level 0: `depth`)
  __constant const PyramidLevel* levels;
  __constant const VssmNode* nodes;
  __constant const float* strips;  // the disk strips' half-widths (VSSM_MAX_DISK_STRIPS)
  __constant const LightViewGpu* lv;
  SatTableDesc desc;
  VssmParams p;
} VssmMaps;

// The receiver in both depth spaces: world for PCF taps (as pcf/pcss compare), normalised for the moments.
typedef struct VssmReceiver {
  float2 uv;        // texel coordinates
  float depth;      // linear light depth, world units
  float bias;       // constant bias at the centre, world units
  float biasSlope;  // bias per texel of offset from uv, world units
  float t;          // normalised (depth - bias)
  float tSlope;     // normalised biasSlope
  uint seed;        // pixel index: jitter of the contact PCF
} VssmReceiver;

// Mean (E(x), E(x^2)) over [lo, hi] (map texels). Texels outside the map hold no occluder: normalised depth 1, as
// sc_fetch's +INFINITY is for the PCF taps, so a kernel that leaves the map is not darkened by its inside part. The
// SAT may hold blocks of satReduce^2 texels (moments_vsm_reduced): the box is then read in block units, exact for
// boxes of whole blocks and the block means' bilinear integral between them. It covers the window p.sat* of the map
// (vssmCastersWindow: every caster texel and the widest box around it), and texels outside the window count as
// outside the map: a box that reaches past it meets no caster, so its moments are its receivers' own surface, which
// blocks nothing.
inline float2 vssm_box_moments(const VssmMaps* m, float2 lo, float2 hi) {
  const float2 origin = (float2)((float)m->p.satX, (float)m->p.satY);
  const float2 size = (float2)((float)m->p.satWidth, (float)m->p.satHeight);
  lo -= origin, hi -= origin;
  const float2 a = clamp(lo, (float2)(0.0f), size), b = clamp(hi, a, size);
  const float inside = (b.x - a.x) * (b.y - a.y), area = (hi.x - lo.x) * (hi.y - lo.y);
  const float block = (float)m->p.satReduce;
  float2 sum = (float2)(0.0f);
  if (inside > 0.0f) sum = sat_box_sum(m->sat, m->desc, m->satOffset, a / block, b / block) * (block * block);
  return (sum + (float2)(area - inside)) / area;
}

// (min, max) of normalised depth over every texel [lo, hi] touches (pyramid_depth_range_of over the light depths,
// then normalised as the moments are: the normalisation never decreases, so it maps the raw range onto the range of
// the normalised texels exactly); background, NaN and parts outside the map count as depth 1.
inline float2 vssm_hsm_range(const VssmMaps* m, float2 lo, float2 hi) {
  const float2 raw = pyramid_depth_range_of(m->depth, m->hsm, m->levels, m->p.pyramidLevels, m->lv->width,
                                            m->lv->height, lo, hi, INFINITY);
  return (float2)(moments_normalize(raw.x, m->p.depthNear, m->p.depthInvRange),
                  moments_normalize(raw.y, m->p.depthNear, m->p.depthInvRange));
}

// World depth a tap at texel position `pos` compares with: the PCF bias grows with the tap offset (pcf.cl).
inline float vssm_tap_depth(const VssmReceiver* r, float2 pos) {
  return r->depth - r->bias - r->biasSlope * length(pos - r->uv);
}

// Sec. 6.4: 3 x 3 jittered bilinear PCF (Bavoil 2008) over [lo, hi]: one bilinear comparison at a random
// point of each of 3 x 3 cells. Returns the lit fraction.
inline float vssm_contact_pcf(const VssmMaps* m, const VssmReceiver* r, float2 lo, float2 hi) {
  const float2 cell = (hi - lo) / 3.0f;
  float lit = 0.0f;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const uint tap = r->seed * 18u + (uint)(j * 3 + i) * 2u;
      const float2 pos = lo + cell * (float2)((float)i + rot_hash01(tap), (float)j + rot_hash01(tap + 1u));
      lit += sc_compare_bilinear(m->depth, m->lv->width, m->lv->height, pos, vssm_tap_depth(r, pos));
    }
  return lit / 9.0f;
}

#endif
