// Kernel wrappers of the rasterizer: the pass list of one draw, in order, every launch named raster/<kernel>.
#include "raster/stages.h"

#include <fmt/format.h>

#include <string>

namespace penumbra::raster {
namespace {

std::string buildOptions(const WorkGroups& groups) {
  return fmt::format(
      "-DRASTER_WG_SETUP={} -DRASTER_WG_BIN={} -DRASTER_WG_GBUFFER={} -DRASTER_WG_FINE={} -DRASTER_SETUP_VECTOR={} "
      "-DRASTER_WG_COARSE={} -DRASTER_BIN_RUN={}",
      groups.setup, groups.bin, groups.gbuffer, groups.fine, groups.fine != 0 ? 1 : 0, groups.coarse, groups.binRun);
}

Kernel makeKernel(Context& ctx, const WorkGroups& groups, const char* source, const char* entry) {
  return Kernel(ctx, source, entry, "raster", buildOptions(groups));
}

}  // namespace

Stages::Stages(Context& ctx)
    : ctx_(ctx),
      groups_(workGroupsFor(ctx.info())),
      setup_(makeKernel(ctx, groups_, "raster/setup.cl", "setup_triangles")),
      binCount_(makeKernel(ctx, groups_, "raster/bin.cl", "bin_count")),
      binScan_(makeKernel(ctx, groups_, "raster/bin.cl", "bin_scan")),
      binFill_(makeKernel(ctx, groups_, "raster/bin.cl", "bin_fill")),
      coarseCount_(makeKernel(ctx, groups_, "raster/coarse.cl", "coarse_count")),
      coarseFill_(makeKernel(ctx, groups_, "raster/coarse.cl", "coarse_fill")),
      fine_(makeKernel(ctx, groups_, "raster/fine.cl", "fine_raster")),
      gbuffer_(makeKernel(ctx, groups_, "raster/gbuffer.cl", "gbuffer_resolve")) {}

RasterViewParams Stages::params(const Plan& plan, const Queues& queues) const {
  RasterViewParams p = plan.params;
  p.extraCapacity = queues.extraCapacity;
  p.binCapacity = queues.binCapacity;
  p.tileCapacity = queues.tileCapacity;
  return p;
}

void Stages::record(const Plan& plan, const SceneBuffers& scene, Queues& q, Buffer<float>& depth,
                    Buffer<uint32_t>& triangleIds, Buffer<uint32_t>& emptyTiles, Buffer<uint32_t>& casterFree) {
  const RasterViewParams p = params(plan, q);
  const size_t records = size_t{scene.triangleCount} + q.extraCapacity;
  const size_t binItems = (records + groups_.binRun - 1) / groups_.binRun;  // groups_.binRun records per item
  const cl_uint bins = static_cast<cl_uint>(plan.bins);
  q.counters.fill(ctx_, RasterCounters{});
  q.binCount.fill(ctx_, 0u);
  q.binTileTotal.fill(ctx_, 0u);
  // Bytes floors (Kernel::moves): setup reads every vertex position and triangle's indices once (3 floats, 3
  // uints), and its material bits and solid code when the draw needs them (1 uint, 1 byte); fine writes one depth and
  // one triangle id per scissor pixel. Bins, tiles and alpha-texture reads are data-dependent.
  setup_.args(scene.positions, scene.triangles, scene.triangleBits, scene.solidSides, q.records, q.counters, p)
      .moves(uint64_t{scene.vertexCount} * 12 +
             uint64_t{scene.triangleCount} * ((p.triangleBits ? 16 : 12) + (p.solidSides ? 1 : 0)))
      .launch(scene.triangleCount, groups_.setup);
  binCount_.args(q.records, q.counters, q.binCount, p).launch(binItems, groups_.bin);
  binScan_.args(q.binCount, q.binOffset, q.binCursor, bins, q.counters, cl_uint{0})
      .launch(RASTER_SCAN_WG, RASTER_SCAN_WG);
  binFill_.args(q.records, q.counters, q.binOffset, q.binCursor, q.binEntries, p).launch(binItems, groups_.bin);
  if (plan.tileMask == nullptr && q.noTileMask.size() == 0) q.noTileMask.allocate(ctx_, 1);
  const Buffer<uint32_t>& mask = plan.tileMask != nullptr ? *plan.tileMask : q.noTileMask;
  coarse(plan, q, p, mask);
  if (p.conservative) return;  // tile lists only (Rasterizer::drawTileLists)
  fine_
      .args(q.records, q.tileEntries, q.tileCount, q.tileOffset, mask, scene.alphaTriangles, scene.alphaMaterials,
            scene.alphaTexels, depth, triangleIds, emptyTiles, casterFree, q.counters, p)
      .moves(uint64_t{plan.scissorPixels} * (sizeof(float) + sizeof(uint32_t)))
      .launch(groups_.fine == 0 ? plan.launchedTiles * RASTER_FINE_WG : plan.launchedTiles,
              groups_.fine == 0 ? size_t{RASTER_FINE_WG} : groups_.fine);
}

// Coarse count, the scan of the bins' tile totals, coarse fill: a work-group per bin and an item per tile, or
// (CPUs, groups_.coarse > 0) an item per bin, groups_.coarse bins per work-group.
void Stages::coarse(const Plan& plan, Queues& q, const RasterViewParams& p, const Buffer<uint32_t>& mask) {
  const cl_uint bins = static_cast<cl_uint>(plan.bins), launched = static_cast<cl_uint>(plan.launchedBins);
  if (groups_.coarse == 0) {
    coarseCount_.args(q.records, q.binEntries, q.binCount, q.binOffset, mask, q.tileCount, q.binTileTotal, p)
        .launch(plan.launchedBins * RASTER_COARSE_WG, RASTER_COARSE_WG);
  } else {
    coarseCount_
        .args(q.records, q.binEntries, q.binCount, q.binOffset, mask, q.tileCount, q.binTileTotal, q.binTiles, p,
              launched)
        .launch(roundUp(plan.launchedBins, groups_.coarse), groups_.coarse);
  }
  binScan_.args(q.binTileTotal, q.binTileBase, q.binCursor, bins, q.counters, cl_uint{1})
      .launch(RASTER_SCAN_WG, RASTER_SCAN_WG);
  if (groups_.coarse == 0) {
    coarseFill_
        .args(q.records, q.binEntries, q.binCount, q.binOffset, mask, q.tileCount, q.binTileBase, q.tileOffset,
              q.tileEntries, p)
        .launch(plan.launchedBins * RASTER_COARSE_WG, RASTER_COARSE_WG);
  } else {
    coarseFill_
        .args(q.records, q.binEntries, q.binCount, q.binOffset, mask, q.tileCount, q.binTileBase, q.tileOffset,
              q.tileEntries, q.binTiles, p, launched)
        .launch(roundUp(plan.launchedBins, groups_.coarse), groups_.coarse);
  }
}

// gbuffer_resolve per scissor pixel: reads the triangle id and depth (8 B), writes position and normal (2 float4)
// and the object id (4 B). The triangles' vertices are read once per visible triangle at most: not counted.
constexpr uint64_t kGBufferBytesPerPixel = 8 + 2 * 16 + 4;

void Stages::gbuffer(const Plan& plan, const SceneBuffers& scene, GBuffer& g) {
  gbuffer_
      .args(scene.positions, scene.normals, scene.triangles, scene.objectIds, g.triangleId, g.depth, g.position,
            g.normal, g.objectId, plan.params)
      .moves(uint64_t{plan.scissorPixels} * kGBufferBytesPerPixel)
      .launch(plan.scissorPixels, groups_.gbuffer);
}

}  // namespace penumbra::raster
