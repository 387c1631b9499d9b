// Confidence-based jittered shadow maps (Luksch sec. 6, after Scherzer et al. 2007): the light's map is drawn N
// times with sub-texel jitter; each pass tests every receiver against its nearest texel as sm does (or with the ID
// buffer, kernels/shared/id_buffer.h) and keeps the result of the most confident pass. Confidence of a lookup is
// its distance to the nearest texel centre (eq. 4), where the map's depth is exact. Accumulation modes (sec. 6.2,
// 6.3): simple (a pass whose confidence reaches a threshold may only add shadow), adapted (a pass replaces the kept
// result when it is more confident), optimal (adapted, with the confidence each pixel needs from the spacing of its
// G-buffer neighbours in the map, eq. 5, added so a pixel that has it is final, eq. 6). Each pass counts on the
// device, with one atomic per work-group, the pixels it changed and those still below the confidence they need:
// the host's stopping rule (sec. 6.3) reads those counters, once a pass, with the texel box of the unconfident
// pixels' lookups (the next pass's scissor). Each pass also appends the pixels a later pass can still change to a
// work list, and the next pass runs over that list only: once most pixels are final (optimal, adapted at confidence
// 1), a pass costs what its few unconfident pixels cost, not the frame's. With exact edges, pass 0 settles every
// pixel whose texels disagree by its exact shadow ray (kernels/shared/exact_edges.h): it leaves the work list.
#define SHADOW_NORMAL_OFFSET_SCALED 0  // the whole normal offset at every angle (kernels/shared/shadow_common.h)
#include "kernels/shared/exact_edges.h"
#include "kernels/shared/id_buffer.h"
#include "kernels/shared/jittered.h"
#include "kernels/shared/shade.h"
#include "kernels/shared/shadow_common.h"

// Eq. 4: 1 at a texel centre, 0 on its border (max norm), for continuous texel coordinate `uv`.
inline float jittered_confidence(float2 uv) {
  float2 f = uv - floor(uv);
  return 1.0f - 2.0f * max(fabs(f.x - 0.5f), fabs(f.y - 0.5f));
}

// Eq. 5 as 1 - optConf = precision * tcDist_min * smSize: the distance in texels (max norm, as eq. 4) from the
// pixel's map position to the nearest covered G-buffer neighbour's, times `precision` (1: the paper, a lookup
// within half a pixel spacing of its texel centre is final; smaller: stricter). The minimum over the four
// neighbours keeps the pixel's own surface at a depth discontinuity (Fig. 5); a pixel with no covered neighbour
// needs no more than its first sample (1). For covered pixel i at world position p through map `lv`.
inline float jittered_slack(__global const float4* position, uint width, uint height, __constant const LightViewGpu* lv,
                            float precision, uint i, float4 p) {
  uint x = i % width, y = i / width;
  float2 here = lv_project(lv, p.xyz).xy;
  float best = INFINITY;
  for (int k = 0; k < 4; ++k) {
    int nx = (int)x + (k == 0) - (k == 1), ny = (int)y + (k == 2) - (k == 3);
    if (nx < 0 || ny < 0 || nx >= (int)width || ny >= (int)height) continue;
    float4 q = position[ny * width + nx];
    if (q.w == 0.0f) continue;
    float2 d = fabs(lv_project(lv, q.xyz).xy - here);
    float dist = max(d.x, d.y);
    if (isfinite(dist)) best = min(best, dist);
  }
  return isfinite(best) ? min(precision * best, 1.0f) : 1.0f;
}

// Whether every texel within JITTER_AGREEMENT_RADIUS of the lookup's texel `t` gives the result `lit` against the
// receiver's plane (depth at uv, light depth gradient g per texel) extended to that texel's centre. Beyond Luksch:
// where it holds in several passes with different jitter, the later passes, whose nearest texel lies within half a
// texel of the receiver, would find the same result, so the pixel is as final as a confident one. One pass is not
// enough: a caster thinner than a texel slips between all of one grid's centres (measured in the README).
inline bool jittered_agree(const float* occluders, float2 t, float2 uv, float depth, float2 g, float lit) {
  int k = 0;
  for (int dy = -JITTER_AGREEMENT_RADIUS; dy <= JITTER_AGREEMENT_RADIUS; ++dy)
    for (int dx = -JITTER_AGREEMENT_RADIUS; dx <= JITTER_AGREEMENT_RADIUS; ++dx) {
      float2 n = t + (float2)((float)dx, (float)dy);
      if (sc_lit(occluders[k++], depth + dot(g, n + 0.5f - uv)) != lit) return false;
    }
  return true;
}

// The occluder depths jittered_agree compares: the texels within JITTER_AGREEMENT_RADIUS of texel `t`, row by row
// (the lookup's own at JITTER_NEIGHBOURS / 2); only the lookup's own when `all` is false.
inline void jittered_gather(__global const float* map, int width, int height, float2 t, bool all, float* occluders) {
  int k = 0;
  for (int dy = -JITTER_AGREEMENT_RADIUS; dy <= JITTER_AGREEMENT_RADIUS; ++dy)
    for (int dx = -JITTER_AGREEMENT_RADIUS; dx <= JITTER_AGREEMENT_RADIUS; ++dx, ++k)
      if (all || k == JITTER_NEIGHBOURS / 2) occluders[k] = sc_fetch(map, width, height, (int)t.x + dx, (int)t.y + dy);
}

// The counter flags of a receiver this pass could not test (outside a reduced map, behind a warp's eye): it keeps
// what it has, unconfident and listed as its kept confidence says.
inline uint jittered_untested(JitterShade s, float stored) {
  float needed = s.mode == JITTER_SIMPLE ? s.threshold : 1.0f;
  return JITTER_COUNT_COVERED | (stored < needed ? JITTER_COUNT_UNCONFIDENT : 0u) |
         (s.mode == JITTER_SIMPLE || stored < 1.0f ? JITTER_COUNT_ACTIVE : 0u);
}

// One pixel's update by this pass, on its state `px`; returns the counter flags (JITTER_COUNT_*) it raises.
// `agree`: the lookup's neighbourhood agrees with it (jittered_agree); in optimal mode px->streak counts the
// consecutive passes whose neighbourhood agreed with the kept result, and s.agreement of them settle the pixel:
// kept = JITTER_SETTLED (above any confidence), final.
inline uint jittered_update(JitterShade s, int pass, float lit, float conf, float slack, bool agree, JitterPixel* px) {
  float stored = px->kept;
  uint flags = JITTER_COUNT_COVERED;
  if (s.mode == JITTER_SIMPLE) {
    if (conf >= s.threshold) {
      px->kept = max(stored, conf);
      if (lit == 0.0f && px->lit != 0.0f) {
        px->lit = 0.0f;
        px->pass = (float)(pass + 1);
        flags |= JITTER_COUNT_CHANGED;
      }
    }
    // Any later lookup at or above the threshold may still add shadow.
    return flags | JITTER_COUNT_ACTIVE | (max(stored, conf) < s.threshold ? JITTER_COUNT_UNCONFIDENT : 0u);
  }
  float c = s.mode == JITTER_OPTIMAL ? min(conf + slack, 1.0f) : conf;  // eq. 6: saturate(conf + (1 - optConf))
  if (c > stored) {  // the paper's "rendered fragment"; it counts as changed when it changes the result
    px->kept = c;
    if (pass > 0 && px->lit != lit) flags |= JITTER_COUNT_CHANGED;
    px->lit = lit;
    px->pass = (float)(pass + 1);
  }
  if (s.mode == JITTER_OPTIMAL && s.agreement > 0) {
    uint n = agree && px->lit == lit ? (pass == 0 ? 1u : px->streak + 1u) : 0u;
    px->streak = n;
    if (n >= (uint)s.agreement) {
      px->kept = JITTER_SETTLED;
      return flags;
    }
  }
  // Nothing beats confidence 1: such a pixel is final and leaves the work list.
  return flags | (max(stored, c) < 1.0f ? JITTER_COUNT_UNCONFIDENT | JITTER_COUNT_ACTIVE : 0u);
}

// Stores pixel i's state after a pass, and its visibility where the pass changed it (every pixel in pass 0).
inline void jittered_store(__global JitterPixel* state, __global float* visibility, uint i, JitterPixel px,
                           float before, int pass) {
  state[i] = px;
  if (pass == 0 || px.lit != before) visibility[i] = px.lit;
}

// A work-group's pass results, gathered for jittered_count.
typedef struct JitterGroup {
  uint flags[JITTER_GROUP];
  int2 texel[JITTER_GROUP];
  int4 tiles[JITTER_GROUP];
  int rank[JITTER_GROUP];          // an active pixel's place among the group's active ones
  int count[JITTER_COUNTERS + 1];  // the group's counters; then its base in the next work list
} JitterGroup;

// The pass's counters: work-group totals, then one global atomic per counter and group. The totals are plain loops
// over the group's flags, one work-item per counter (local atomics cost a CPU device 7 locked instructions a pixel).
// An active pixel also takes a slot in the next pass's work list: its rank among the group's active pixels after
// the group's base (the global counter's old value). The list's order varies from run to run with the groups'; no
// pixel's result depends on it. With a tile mask (tilesX > 0), an unconfident pixel also marks the map tiles
// (tileSize texels square) within JITTER_DRAW_MARGIN of its lookup for the next pass to draw.
inline void jittered_count(uint flags, int2 texel, uint pixel, __local JitterGroup* wg, __global int* counters,
                           __global uint* next, __global uint* tileMask, int tilesX, int tilesY, int tileSize) {
  uint lid = get_local_id(0);
  int4 box = (int4)(0, 0, -1, -1);  // the map tiles this pixel marks (x0, y0, x1, y1); none
  if ((flags & JITTER_COUNT_UNCONFIDENT) && tilesX > 0) {
    // texel >= -1: the division rounds towards 0. A vector bound: oclgrind 21.10 gets max(int2, int) wrong.
    int2 lo = max((texel - JITTER_DRAW_MARGIN) / tileSize, (int2)(0));
    int2 hi = min((texel + JITTER_DRAW_MARGIN) / tileSize, (int2)(tilesX - 1, tilesY - 1));
    // Lane by lane: clang builds (int4)(lo, hi) from shuffles with undef lanes, on which oclgrind 21.10's
    // uninitialised-value check crashes (tests/data/oclgrind/shuffle_undef.c).
    box = (int4)(lo.x, lo.y, hi.x, hi.y);
  }
  wg->flags[lid] = flags, wg->texel[lid] = texel, wg->tiles[lid] = box;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid < JITTER_BOX_MIN_X) {  // pixels with flag bit lid
    int n = 0;
    for (int j = 0; j < JITTER_GROUP; ++j) n += (int)((wg->flags[j] >> lid) & 1u);
    wg->count[lid] = n;
  } else if (lid < JITTER_COUNTERS) {  // min x, min y, max x, max y of the unconfident pixels' lookups
    bool low = lid < JITTER_BOX_MIN_X + 2, y = (lid - JITTER_BOX_MIN_X) & 1u;
    int v = low ? INT_MAX : INT_MIN;
    for (int j = 0; j < JITTER_GROUP; ++j)
      if (wg->flags[j] & JITTER_COUNT_UNCONFIDENT) {
        int t = y ? wg->texel[j].y : wg->texel[j].x;
        v = low ? min(v, t) : max(v, t);
      }
    wg->count[lid] = v;
  } else if (lid == JITTER_COUNTERS) {
    int r = 0;
    for (int j = 0; j < JITTER_GROUP; ++j) {
      wg->rank[j] = r;
      r += (wg->flags[j] & JITTER_COUNT_ACTIVE) ? 1 : 0;
    }
  }
  // Neighbouring work-items mostly look up the same tiles: a tile the previous one marks is left to it, and the
  // marks are plain stores of one value (no atomics, no read). The box spans at most 2x2 tiles
  // (JITTER_DRAW_MARGIN < tileSize): four candidate marks, no loop.
  int4 previous = lid > 0 ? wg->tiles[lid - 1] : (int4)(0, 0, -1, -1);
  for (int k = 0; k < 4; ++k) {
    int tx = k & 1 ? box.z : box.x, ty = k & 2 ? box.w : box.y;
    bool repeat = (k & 1 && box.z == box.x) || (k & 2 && box.w == box.y);
    bool theirs = tx >= previous.x && tx <= previous.z && ty >= previous.y && ty <= previous.w;
    if (box.x <= box.z && !repeat && !theirs) tileMask[ty * tilesX + tx] = 1u;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid < JITTER_BOX_MIN_X && wg->count[lid] > 0) {
    int base = atomic_add(&counters[lid], wg->count[lid]);
    if (lid == JITTER_ACTIVE) wg->count[JITTER_COUNTERS] = base;
  }
  if (lid == JITTER_BOX_MIN_X || lid == JITTER_BOX_MIN_X + 1) atomic_min(&counters[lid], wg->count[lid]);
  if (lid == JITTER_BOX_MIN_X + 2 || lid == JITTER_BOX_MIN_X + 3) atomic_max(&counters[lid], wg->count[lid]);
  barrier(CLK_LOCAL_MEM_FENCE);
  if (flags & JITTER_COUNT_ACTIVE) next[wg->count[JITTER_COUNTERS] + wg->rank[lid]] = pixel;
}

// sm's test of covered pixel i (world position p) through map `lv`, the pass's update of its state `px` (eq. 4-6
// with the required confidence's `slack`) and its counter flags; `texel` receives the lookup's texel. With `record`,
// px also receives what a later pass needs to move the lookup instead of projecting again (texel position, the
// biased depth at it, the receiver plane's depth gradient in texels, valid, the id lookup's position). With `edges`
// (pass 0 with exact edges), a pixel whose texels disagree is settled by its exact shadow ray instead.
inline uint jittered_lookup(__global const float4* position, __global const float4* normal, uint width, uint height,
                            __global const float* map, __constant const LightViewGpu* lv, ShadowBias bias,
                            int receiverPlane, int idMode, __global const uint* mapIds, __global const uint* objectIds,
                            __global const uint* pixelTriangle, __global const uint* pixelObject, JitterShade s,
                            int pass, float slack, uint i, float4 p, bool record, const EdgeScene* edges, int2* texel,
                            JitterPixel* px) {
  ReceiverPlane rp;
  Receiver r = sc_hard_receiver(receiverPlane, position, lv, width, height, i, p.xyz, normal[i].xyz, bias, &rp);
  if (!r.valid) return 0u;
  float2 idUv = lv_project(lv, p.xyz).xy;
  float lit = id_visibility(mapIds, objectIds, lv->width, lv->height, idUv, id_pixel(pixelTriangle, i, idMode),
                            id_pixel(pixelObject, i, idMode), idMode, sc_hard_lit(map, lv, r, rp, bias.base * r.texel));
  float depth = rp.valid ? r.depth - bias.base * r.texel : r.depth - r.bias;  // as sc_hard_lit
  *texel = convert_int2_sat(clamp(floor(r.uv), -1.0f, (float)max(lv->width, lv->height)));
  if (record) {
    px->u = r.uv.x, px->v = r.uv.y, px->depth = depth, px->valid = 1.0f;
    px->gu = rp.gradient.x, px->gv = rp.gradient.y, px->idU = idUv.x, px->idV = idUv.y;
  }
  if (edges != 0) {
    const float exact =
        edge_exact_lit(map, mapIds, lv, p.xyz, pixelTriangle[i], normal[i].xyz, rp,
                       rp.valid ? bias.base * r.texel : r.bias, lit, convert_int2(floor(r.uv)), true, edges);
    if (exact >= 0.0f) {
      px->lit = exact, px->kept = JITTER_SETTLED, px->pass = (float)(pass + 1);
      return JITTER_COUNT_COVERED;
    }
  }
  bool agree = false;
  if (s.agreement > 0 && idMode == ID_BUFFER_OFF) {
    float occluders[JITTER_NEIGHBOURS];
    jittered_gather(map, lv->width, lv->height, floor(r.uv), true, occluders);
    agree = jittered_agree(occluders, floor(r.uv), r.uv, depth, rp.gradient, lit);
  }
  return jittered_update(s, pass, lit, jittered_confidence(r.uv), slack, agree, px);
}

// Pass 0: sm's test of every receiver through the first map, kept in its state as a record of the lookup that later
// passes move with their jitter instead of projecting again (jittered_pass), and (optimal) eq. 5's slack of every
// pixel in pass 0's texels, which translations and the common rotation scale keep for every pass (background: 1;
// other modes: 0). Every pixel's state and visibility are written (background: lit, nothing kept).
__kernel __attribute__((reqd_work_group_size(JITTER_GROUP, 1, 1))) void jittered_first(
    __global const float4* position, __global const float4* normal, __global const float* map,
    __constant const LightViewGpu* lv, ShadeFrame f, __global const uint* mapIds, __global const uint* objectIds,
    __global const uint* pixelTriangle, __global const uint* pixelObject, JitterShade s,
    __global const float* positions, __global const uint* triangles, __global const uint* alphaIndex,
    __global const AlphaTriangle* alphaTriangles, __global const AlphaMaterial* alphaMaterials,
    __global const uchar* alphaTexels, __global JitterPixel* state, __global int* counters, __global uint* next,
    __global uint* tileMask, __global float* visibility) {
  const uint width = f.width, height = f.height;
  const EdgeScene edges = {positions,
                           triangles,
                           s.triangleCount,
                           {alphaIndex, alphaTriangles, alphaMaterials, alphaTexels, s.alphaTested},
                           s.sceneRadius};
  __local JitterGroup wg;
  uint i = get_global_id(0), flags = 0;
  int2 texel = (int2)(0);
  float4 p = i < width * height ? position[i] : (float4)(0.0f);
  JitterPixel px = {0.0f};
  px.kept = -1.0f, px.lit = 1.0f;
  if (s.mode == JITTER_OPTIMAL && i < width * height)
    px.slack = p.w == 0.0f ? 1.0f : jittered_slack(position, width, height, lv, s.precision, i, p);
  if (p.w != 0.0f) {
    ShadowBias bias = {f.biasConstant, f.biasSlope, f.normalOffset};
    flags =
        jittered_lookup(position, normal, width, height, map, lv, bias, f.receiverPlane, f.idMode, mapIds, objectIds,
                        pixelTriangle, pixelObject, s, 0, px.slack, i, p, true, s.exactEdges ? &edges : 0, &texel, &px);
  }
  if (i < width * height) jittered_store(state, visibility, i, px, 1.0f, 0);
  jittered_count(flags, texel, i, &wg, counters, next, tileMask, s.tilesX, s.tilesY, s.tileSize);
}

// Pass k > 0 of LiSPSM n-parameter jittering (Luksch sec. 6.5.1): the pass's warp differs from pass 0's, so it is no
// similarity of it and every listed pixel is projected again, as in pass 0, with eq. 5's required confidence taken
// in this pass's texels (the paper: "the optimal confidence has to be recalculated whenever n is changed"; biased by
// it, confidences of differently warped passes compare again). Over the previous pass's work list.
__kernel __attribute__((reqd_work_group_size(JITTER_GROUP, 1, 1))) void jittered_reproject(
    __global const float4* position, __global const float4* normal, __global const uint* work,
    __global const float* map, __constant const LightViewGpu* lv, ShadeFrame f, __global const uint* mapIds,
    __global const uint* objectIds, __global const uint* pixelTriangle, __global const uint* pixelObject,
    JitterShade s, JitterPass jp, __global JitterPixel* state, __global int* counters, __global uint* next,
    __global float* visibility) {
  const uint width = f.width, height = f.height, count = jp.count;
  const int pass = jp.pass;
  __local JitterGroup wg;
  uint flags = 0, i = get_global_id(0) < count ? work[get_global_id(0)] : 0u;
  int2 texel = (int2)(0);
  if (get_global_id(0) < count) {
    float4 p = position[i];
    JitterPixel px = state[i];
    float before = px.lit;
    float slack = s.mode == JITTER_OPTIMAL ? jittered_slack(position, width, height, lv, s.precision, i, p) : 0.0f;
    ShadowBias bias = {f.biasConstant, f.biasSlope, f.normalOffset};
    flags = jittered_lookup(position, normal, width, height, map, lv, bias, f.receiverPlane, f.idMode, mapIds,
                            objectIds, pixelTriangle, pixelObject, s, pass, slack, i, p, false, 0, &texel, &px);
    // A receiver whose lookup fails here (behind this warp's eye) keeps what it has and stays listed.
    if (flags == 0u) flags = jittered_untested(s, px.kept);
    jittered_store(state, visibility, i, px, before, pass);
  }
  // No tile mask: each warp has its own texels.
  jittered_count(flags, texel, i, &wg, counters, next, next, 0, 0, 1);
}

// Pass k > 0: the map differs from pass 0's by a similarity (the host's texelTransform: its rotation, the zoom s of a
// reduced frustum, its shift), so a receiver's texel position is c + s R (uv_0 - c) + shift, its plane's gradient
// R g_0 / s, and the confidence it needs (eq. 5's slack, in pass 0's texels) s times as many texels: Luksch eq. 7
// scales the required confidence by the reduced frustum for the same reason (it prints f_reduced / f; the sampling
// rate it argues from grows by s, the ratio of texel sizes, which we use). A receiver outside a reduced map (across
// its window or beyond its far plane) keeps what it has. The depth comparison is sc_hard_lit's against the moved
// lookup. It runs over the previous pass's work list (`work`, `count` pixels) and writes the next one (`next`).
__kernel __attribute__((reqd_work_group_size(JITTER_GROUP, 1, 1))) void jittered_pass(
    __global const uint* work, __global const float* map, __global const uint* mapIds, __global const uint* objectIds,
    __global const uint* pixelTriangle, __global const uint* pixelObject, JitterShade s, JitterPass jp,
    __global JitterPixel* state, __global int* counters, __global uint* next, __global uint* tileMask,
    __global float* visibility) {
  const uint count = jp.count;
  const int mapWidth = jp.mapWidth, mapHeight = jp.mapHeight, idMode = jp.idMode, pass = jp.pass;
  const float4 jitter = jp.jitter;
  const float mapFar = jp.mapFar;
  __local JitterGroup wg;
  __local JitterPixel staged[JITTER_GROUP];
  __local float near[JITTER_GROUP * JITTER_NEIGHBOURS];
  uint flags = 0, lid = get_local_id(0), i = get_global_id(0) < count ? work[get_global_id(0)] : 0u;
  int2 texel = (int2)(0);
  // The listed pixels and their lookups lie scattered over the frame and the map: the group gathers their states,
  // then the texels they compare, each with nothing else between the loads, so that a CPU device overlaps the cache
  // misses (the poles view's 31 later passes, alternating runs: 59-75 ms against 63-101 ms loading in place).
  if (get_global_id(0) < count) staged[lid] = state[i];
  barrier(CLK_LOCAL_MEM_FENCE);
  JitterPixel px = {0.0f};
  if (get_global_id(0) < count) px = staged[lid];
  float2 centre = 0.5f * (float2)(mapWidth, mapHeight), cs = jitter.xy, offset = jitter.zw;
  float2 d = (float2)(px.u, px.v) - centre;
  float2 uv = centre + (float2)(cs.x * d.x - cs.y * d.y, cs.y * d.x + cs.x * d.y) + offset, t = floor(uv);
  bool agreement = s.agreement > 0 && idMode == ID_BUFFER_OFF;
  float occluders[JITTER_NEIGHBOURS];
  if (px.valid != 0.0f) {
    jittered_gather(map, mapWidth, mapHeight, t, agreement, occluders);
    for (int k = 0; k < JITTER_NEIGHBOURS; ++k) near[lid * JITTER_NEIGHBOURS + k] = occluders[k];
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (px.valid != 0.0f) {
    for (int k = 0; k < JITTER_NEIGHBOURS; ++k) occluders[k] = near[lid * JITTER_NEIGHBOURS + k];
    float before = px.lit;
    float2 e = (float2)(px.idU, px.idV) - centre;
    float2 idUv = centre + (float2)(cs.x * e.x - cs.y * e.y, cs.y * e.x + cs.x * e.y) + offset;
    float zoom2 = dot(cs, cs);
    float2 g = (float2)(cs.x * px.gu - cs.y * px.gv, cs.y * px.gu + cs.x * px.gv) / zoom2;
    float depthLit = sc_lit(occluders[JITTER_NEIGHBOURS / 2], px.depth + dot(g, t + 0.5f - uv));
    float lit = id_visibility(mapIds, objectIds, mapWidth, mapHeight, idUv, id_pixel(pixelTriangle, i, idMode),
                              id_pixel(pixelObject, i, idMode), idMode, depthLit);
    // A reduced map ends at its slice's deepest receiver: farther receivers are not in it, wherever they project.
    bool inside =
        uv.x >= 0.0f && uv.y >= 0.0f && uv.x < (float)mapWidth && uv.y < (float)mapHeight && px.depth <= mapFar;
    bool agree = inside && agreement && jittered_agree(occluders, t, uv, px.depth, g, lit);
    if (inside)
      flags = jittered_update(s, pass, lit, jittered_confidence(uv), px.slack * sqrt(zoom2), agree, &px);
    else  // outside a reduced frustum
      flags = jittered_untested(s, px.kept);
    texel = convert_int2_sat(clamp(t, -1.0f, (float)max(mapWidth, mapHeight)));
    jittered_store(state, visibility, i, px, before, pass);
  }
  jittered_count(flags, texel, i, &wg, counters, next, tileMask, s.tilesX, s.tilesY, s.tileSize);
}
