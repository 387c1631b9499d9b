// The host side of the rasterizer's alpha tests and sidedness: from the geometry's materials (raster/geometry.h), the
// per-triangle material bits setup reads (RASTER_TRI_*), the records of the alpha-tested triangles the fine stage
// reads (AlphaTriangle) and one AlphaMaterial per material (kernels/shared/alpha.h), checked against the geometry.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/shared/alpha.h"
#include "raster/geometry.h"
#include "raster/plan.h"
#include "raster/types.h"

namespace penumbra::raster {

struct MaterialTables {
  SceneMaterials summary;
  std::vector<uint32_t> triangleBits;         // one per triangle when summary.needsTriangleBits(), else empty
  std::vector<AlphaTriangle> alphaTriangles;  // the triangles whose material may discard, in geometry order
  std::vector<AlphaMaterial> materials;       // one per RasterGeometry::materials entry
  // One per triangle when summary.alphaTested, else empty: its alphaTriangles entry, ALPHA_NO_TRIANGLE if opaque.
  std::vector<uint32_t> alphaIndex;
};

// Throws std::invalid_argument ("raster scene: ...") for material ids, texture coordinates or alpha textures that
// do not match the geometry, or more alpha-tested triangles than RASTER_MAX_ALPHA_TRIANGLES.
MaterialTables materialTables(const RasterGeometry& geometry);

}  // namespace penumbra::raster
