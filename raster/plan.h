// Planning one draw of the rasterizer (plan, then record): the validated view turned into the kernels' parameter
// block, the bin and tile grids and the launched ranges, and the per-device work-group table row.
#pragma once

#include <cstddef>
#include <cstdint>

#include "host/cl/device.h"
#include "raster/rasterizer.h"
#include "raster/types.h"

namespace penumbra::raster {

// One row of the work-group table in raster/constants.h.
struct WorkGroups {
  size_t setup = 0, bin = 0, gbuffer = 0;
  size_t fine = 0;    // 0: a work-group per tile, an item per pixel; N > 0: N tiles per work-group, an item per tile
  size_t coarse = 0;  // 0: a work-group per bin, an item per tile; N > 0: N bins per work-group, an item per bin
  size_t binRun = 1;  // records per bin_count / bin_fill work-item
};
// The row of raster/constants.h for `device` (by vendor and platform, or as PENUMBRA_LAYOUTS forces: "gpu" the
// default row, "nvidia" NVIDIA's), each size capped by the device's work-group limit.
WorkGroups workGroupsFor(const DeviceInfo& device);

struct Plan {
  RasterViewParams params{};                   // everything but the capacities, which the recording fills in
  size_t pixels = 0;                           // width * height
  size_t bins = 0, tiles = 0;                  // grid sizes over the whole viewport
  size_t launchedBins = 0, launchedTiles = 0;  // those overlapping the scissor (coarse / fine work-groups)
  size_t scissorPixels = 0;                    // pixels inside the scissor (G-buffer work-items)
  const Buffer<uint32_t>* tileMask = nullptr;  // RasterView::tileMask (params.tileMasked set with it)
  bool empty() const { return scissorPixels == 0; }
};

// What a draw needs to know of the uploaded scene's materials (Rasterizer::setGeometry).
struct SceneMaterials {
  bool alphaTested = false;     // some triangle is alpha-tested
  bool anySingleSided = false;  // some triangle's material is single-sided
  bool allSingleSided = false;  // every triangle's is
  // Whether setup needs the per-triangle bits (RASTER_TRI_*) at all: alpha tests, or sidedness that differs.
  bool needsTriangleBits() const { return alphaTested || (anySingleSided && !allSingleSided); }
};

// Validates `view` (std::invalid_argument naming the problem) and plans a draw of `triangleCount` triangles over
// `vertexCount` vertices whose materials are `materials`: a view that culls single-sided triangles culls every back
// face when all are single-sided, and reads the per-triangle bits when only some are.
Plan makePlan(const RasterView& view, uint32_t triangleCount, uint32_t vertexCount,
              const SceneMaterials& materials = {});

}  // namespace penumbra::raster
