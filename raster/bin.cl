// Binning, stage 2 of 4 (Laine & Karras 2011, section 4.2, with a count-scan-fill queue layout instead of their
// per-SM queues): every set-up triangle is entered into the queue of each 128x128-pixel bin whose samples it may
// cover. bin_count counts entries per bin (one global atomic per entry, or on CPUs per run of entries into one bin:
// RASTER_BIN_RUN), bin_scan turns counts into offsets in one bin queue (also used for the coarse stage's per-bin
// totals), bin_fill writes entries below binCapacity.
// The order inside a bin queue depends on atomics; nothing downstream depends on it (the depth test is a total
// order on (depth, triangle id)).
#include "raster/constants.h"
#include "raster/coverage.h"
#include "raster/types.h"

#ifndef RASTER_WG_BIN
#define RASTER_WG_BIN 64
#endif
// Records per work-item (the table's binRun column, raster/constants.h): 1 on GPUs; on CPUs a run, so that an item
// can merge consecutive entries into the same bin (dense meshes keep neighbouring triangles in one bin) into one
// global atomic: the atomics, not the record reads, bound this stage there.
#ifndef RASTER_BIN_RUN
#define RASTER_BIN_RUN 1
#endif

// Records written by setup this run: one per input triangle plus the appended fan triangles that fitted.
static uint binRecordCount(const RasterViewParams* p, __global const RasterCounters* counters) {
  return p->triangleCount + min(counters->extraTriangles, p->extraCapacity);
}

// Calls BODY(bin) for every bin of the view whose samples the record `t` may cover.
#define BIN_FOR_EACH(t, p, BODY)                                                                  \
  do {                                                                                            \
    int bx0_ = (t).bbox[0] >> RASTER_BIN_PIXEL_LOG2, by0_ = (t).bbox[1] >> RASTER_BIN_PIXEL_LOG2; \
    int bx1_ = (t).bbox[2] >> RASTER_BIN_PIXEL_LOG2, by1_ = (t).bbox[3] >> RASTER_BIN_PIXEL_LOG2; \
    bool single_ = bx0_ == bx1_ && by0_ == by1_;                                                  \
    for (int by_ = by0_; by_ <= by1_; ++by_)                                                      \
      for (int bx_ = bx0_; bx_ <= bx1_; ++bx_) {                                                  \
        bool hit_ = single_;                                                                      \
        if (!hit_) {                                                                              \
          int px_ = bx_ << RASTER_BIN_PIXEL_LOG2, py_ = by_ << RASTER_BIN_PIXEL_LOG2;             \
          int span_ = (1 << RASTER_BIN_PIXEL_LOG2) - 1;                                           \
          RASTER_RECT_OVERLAPS(t, (p).conservative, px_, py_, px_ + span_, py_ + span_, hit_);     \
        }                                                                                         \
        if (hit_) BODY(by_*(p).binsX + bx_);                                                      \
      }                                                                                           \
  } while (0)

// RasterViewParams::casterTiles: a valid record's box joins `box` (RasterCounters::casterBox's encoding) when the
// record is a caster's.
static inline void binJoinCasterBox(const RasterViewParams* p, const RasterTriangle* t, uint* box) {
  if (!p->casterTiles || (t->flags & RASTER_FLAG_NONCASTER) != 0u) return;
  box[0] = max(box[0], RASTER_CASTER_BOX_FLIP - t->bbox[0]), box[1] = max(box[1], RASTER_CASTER_BOX_FLIP - t->bbox[1]);
  box[2] = max(box[2], (uint)t->bbox[2] + 1u), box[3] = max(box[3], (uint)t->bbox[3] + 1u);
}

// A work-item's joined box into counters->casterBox (nothing when it holds no caster).
static inline void binStoreCasterBox(__global RasterCounters* counters, const uint* box) {
  if (box[2] == 0u) return;
  for (int k = 0; k < 4; ++k) atomic_max(&counters->casterBox[k], box[k]);
}

#if RASTER_BIN_RUN == 1
// binCount[binsX * binsY] must be zero on entry, and counters->casterBox when p.casterTiles is set.
__kernel __attribute__((reqd_work_group_size(RASTER_WG_BIN, 1, 1))) void bin_count(__global const RasterTriangle* tris,
                                                                                   __global RasterCounters* counters,
                                                                                   __global uint* binCount,
                                                                                   const RasterViewParams p) {
  const uint i = get_global_id(0);
  if (i >= binRecordCount(&p, counters)) return;
  const RasterTriangle t = tris[i];
  if ((t.flags & RASTER_FLAG_VALID) == 0) return;
  uint box[4] = {0u, 0u, 0u, 0u};
  binJoinCasterBox(&p, &t, box);
  binStoreCasterBox(counters, box);
#define BIN_COUNT_ONE(bin) atomic_inc(&binCount[bin])
  BIN_FOR_EACH(t, p, BIN_COUNT_ONE);
#undef BIN_COUNT_ONE
}
#else
// The same counts, from RASTER_BIN_RUN records per work-item: one atomic per run of entries into the same bin (and
// the run's casters' box joined once).
__kernel __attribute__((reqd_work_group_size(RASTER_WG_BIN, 1, 1))) void bin_count(__global const RasterTriangle* tris,
                                                                                   __global RasterCounters* counters,
                                                                                   __global uint* binCount,
                                                                                   const RasterViewParams p) {
  const uint records = binRecordCount(&p, counters);
  if (records == 0 || get_global_id(0) > (records - 1) / RASTER_BIN_RUN) return;
  const uint first = get_global_id(0) * RASTER_BIN_RUN, end = first + min((uint)RASTER_BIN_RUN, records - first);
  int runBin = -1;
  uint run = 0;
  uint box[4] = {0u, 0u, 0u, 0u};
#define BIN_COUNT_RUN(bin)                                 \
  do {                                                     \
    if ((bin) != runBin) {                                 \
      if (run != 0) atomic_add(&binCount[runBin], run);    \
      runBin = (bin), run = 0;                             \
    }                                                      \
    ++run;                                                 \
  } while (0)
  for (uint i = first; i < end; ++i) {
    const RasterTriangle t = tris[i];
    if ((t.flags & RASTER_FLAG_VALID) == 0) continue;
    binJoinCasterBox(&p, &t, box);
    BIN_FOR_EACH(t, p, BIN_COUNT_RUN);
  }
#undef BIN_COUNT_RUN
  if (run != 0) atomic_add(&binCount[runBin], run);
  binStoreCasterBox(counters, box);
}
#endif

// Exclusive scan of counts[n] (n <= RASTER_MAX_BINS) in one work-group: offsets[i] (RASTER_SATURATED from
// 2^32 - 1 on, past every capacity), zero[i] = 0 (the fill pass's cursors), and the 64-bit total into
// counters->binEntries (which == 0) or counters->tileEntries (which == 1).
__kernel __attribute__((reqd_work_group_size(RASTER_SCAN_WG, 1, 1))) void bin_scan(__global const uint* counts,
                                                                                   __global uint* offsets,
                                                                                   __global uint* zero, uint n,
                                                                                   __global RasterCounters* counters,
                                                                                   uint which) {
  __local ulong sums[RASTER_SCAN_WG];
  const uint lid = get_local_id(0), first = lid * RASTER_SCAN_ITEMS;
  ulong own = 0;
  for (uint k = 0; k < RASTER_SCAN_ITEMS; ++k)
    if (first + k < n) own += counts[first + k];
  sums[lid] = own;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint step = 1; step < RASTER_SCAN_WG; step <<= 1) {  // Hillis-Steele inclusive scan
    ulong add = lid >= step ? sums[lid - step] : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    sums[lid] += add;
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  ulong running = sums[lid] - own;
  for (uint k = 0; k < RASTER_SCAN_ITEMS; ++k)
    if (first + k < n) {
      offsets[first + k] = running < RASTER_SATURATED ? (uint)running : RASTER_SATURATED;
      zero[first + k] = 0;
      running += counts[first + k];
    }
  if (lid == RASTER_SCAN_WG - 1) {
    if (which == 0)
      counters->binEntries = sums[lid];
    else
      counters->tileEntries = sums[lid];
  }
}

#if RASTER_BIN_RUN == 1
// binCursor must be zero on entry (bin_scan clears it).
__kernel __attribute__((reqd_work_group_size(RASTER_WG_BIN, 1, 1))) void bin_fill(
    __global const RasterTriangle* tris, __global const RasterCounters* counters, __global const uint* binOffset,
    __global uint* binCursor, __global uint* binEntries, const RasterViewParams p) {
  const uint i = get_global_id(0);
  if (i >= binRecordCount(&p, counters)) return;
  const RasterTriangle t = tris[i];
  if ((t.flags & RASTER_FLAG_VALID) == 0) return;
#define BIN_FILL_ONE(bin)                                                                            \
  do {                                                                                               \
    uint slot_ = atomic_inc(&binCursor[bin]), offset_ = binOffset[bin];                              \
    if (offset_ < p.binCapacity && slot_ < p.binCapacity - offset_) binEntries[offset_ + slot_] = i; \
  } while (0)
  BIN_FOR_EACH(t, p, BIN_FILL_ONE);
#undef BIN_FILL_ONE
}
#else
// Writes `run` pending entries of bin `bin` at slots reserved with one atomic, below binCapacity.
static void binFlush(int bin, const uint* pending, uint run, __global const uint* binOffset, __global uint* binCursor,
                     __global uint* binEntries, uint capacity) {
  const uint slot = atomic_add(&binCursor[bin], run), offset = binOffset[bin];
  for (uint k = 0; k < run; ++k)
    if (offset < capacity && slot + k < capacity - offset) binEntries[offset + slot + k] = pending[k];
}

// The same entries, from RASTER_BIN_RUN records per work-item: a run of entries into the same bin (at most one per
// record) waits in private memory and is placed with one atomic.
__kernel __attribute__((reqd_work_group_size(RASTER_WG_BIN, 1, 1))) void bin_fill(
    __global const RasterTriangle* tris, __global const RasterCounters* counters, __global const uint* binOffset,
    __global uint* binCursor, __global uint* binEntries, const RasterViewParams p) {
  const uint records = binRecordCount(&p, counters);
  if (records == 0 || get_global_id(0) > (records - 1) / RASTER_BIN_RUN) return;
  const uint first = get_global_id(0) * RASTER_BIN_RUN, end = first + min((uint)RASTER_BIN_RUN, records - first);
  uint pending[RASTER_BIN_RUN];
  int runBin = -1;
  uint run = 0;
#define BIN_FILL_RUN(bin)                                                                           \
  do {                                                                                              \
    if ((bin) != runBin) {                                                                          \
      if (run != 0) binFlush(runBin, pending, run, binOffset, binCursor, binEntries, p.binCapacity); \
      runBin = (bin), run = 0;                                                                      \
    }                                                                                               \
    pending[run++] = i;                                                                             \
  } while (0)
  for (uint i = first; i < end; ++i) {
    const RasterTriangle t = tris[i];
    if ((t.flags & RASTER_FLAG_VALID) != 0) BIN_FOR_EACH(t, p, BIN_FILL_RUN);
  }
#undef BIN_FILL_RUN
  if (run != 0) binFlush(runBin, pending, run, binOffset, binCursor, binEntries, p.binCapacity);
}
#endif
