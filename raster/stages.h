// The rasterizer's kernels behind one typed wrapper per launch (plan, then record): each sets its arguments in
// one place, sizes its ND-range from the Plan and reports to the profiler as raster/<kernel>. Also the device
// buffers a draw works on: the scene, and the queues with their counters and capacities.
#pragma once

#include <cstdint>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/cl/kernel.h"
#include "kernels/shared/alpha.h"
#include "raster/plan.h"
#include "raster/rasterizer.h"
#include "raster/types.h"

namespace penumbra::raster {

// The scene on the device, flattened: 3 floats per position and normal, 3 indices per triangle; the alpha-tested
// triangles' records, their materials and the alpha atlas, and the per-triangle material bits (RASTER_TRI_*) when
// materials.needsTriangleBits() (else each of these holds one unused entry: OpenCL has no empty buffers).
struct SceneBuffers {
  Buffer<float> positions, normals;
  Buffer<uint32_t> triangles, objectIds;
  Buffer<uint32_t> triangleBits;
  Buffer<uint32_t> alphaIndex;  // per triangle: its alphaTriangles entry or ALPHA_NO_TRIANGLE (when alpha-tested)
  Buffer<AlphaTriangle> alphaTriangles;
  Buffer<AlphaMaterial> alphaMaterials;
  Buffer<uint8_t> alphaTexels;
  // The draw's RASTER_CULL_* code per triangle when it drops the far sides of solids (RasterView::cullSolidsFarSides),
  // made for the view's centre (Rasterizer::draw); else one unused entry.
  Buffer<uint8_t> solidSides;
  uint32_t vertexCount = 0, triangleCount = 0;
  SceneMaterials materials;
};

// Queues of one draw. Per-bin arrays always hold RASTER_MAX_BINS entries; per-tile arrays at least plan.tiles.
struct Queues {
  Buffer<RasterTriangle> records;   // triangleCount + extraCapacity set-up records
  Buffer<RasterCounters> counters;  // one
  Buffer<uint32_t> binCount, binOffset, binCursor, binTileTotal, binTileBase;
  Buffer<uint32_t> tileCount, tileOffset;
  Buffer<uint32_t> binEntries, tileEntries;  // binCapacity, tileCapacity entries
  Buffer<uint16_t> binTiles;                 // binCapacity entries: the coarse CPU layout's tile codes (coarse.cl)
  Buffer<uint32_t> noTileMask;               // one entry: the tile-mask argument of draws without one
  uint32_t extraCapacity = 0, binCapacity = 0, tileCapacity = 0;
};

class Stages {
 public:
  explicit Stages(Context& ctx);

  // Clears the counters, then: setup, bin (count, scan, fill), coarse (count, scan, fill), fine into depth/ids (not
  // for conservative plans, which leave depth and ids untouched and end with the tile queue). emptyTiles: fine's
  // per-tile record where plan.params.emptyTiles is set (RasterTargets::keepEmptyTiles), casterFree where
  // plan.params.casterTiles is (RasterView::recordCasterTiles); else any buffer.
  void record(const Plan& plan, const SceneBuffers& scene, Queues& queues, Buffer<float>& depth,
              Buffer<uint32_t>& triangleIds, Buffer<uint32_t>& emptyTiles, Buffer<uint32_t>& casterFree);
  // Whether fine keeps RasterTargets::emptyTiles on this device: its CPU layout, whose empty tiles are stored by a
  // core (a GPU's store them at its bandwidth, microseconds for a 4096^2 map).
  bool keepsEmptyTiles() const { return groups_.fine != 0; }
  // Position, normal and object id from the triangle ids `record` wrote into gbuffer.
  void gbuffer(const Plan& plan, const SceneBuffers& scene, GBuffer& gbuffer);

 private:
  RasterViewParams params(const Plan& plan, const Queues& queues) const;
  void coarse(const Plan& plan, Queues& queues, const RasterViewParams& p, const Buffer<uint32_t>& mask);

  Context& ctx_;
  WorkGroups groups_;
  Kernel setup_, binCount_, binScan_, binFill_, coarseCount_, coarseFill_, fine_, gbuffer_;
};

}  // namespace penumbra::raster
