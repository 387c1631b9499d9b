// A Scene as the rasterizer's plain arrays (raster/geometry.h): its materials turned into the records the kernels
// read (each alpha texture located in the scene's atlas) and its solids (host/scene/solids.h) as RasterSolids,
// everything else viewed in place. The one place where host/scene meets raster/.
#pragma once

#include <cstdint>
#include <vector>

#include "host/scene/scene.h"
#include "host/scene/solids.h"
#include "raster/geometry.h"
#include "raster/rasterizer.h"

namespace penumbra {

class SceneGeometry {
 public:
  // Views of `scene` and its `solids` (findSolids(scene)), which must outlive this object. Throws
  // std::invalid_argument ("raster scene: ...") for a material whose alpha texture is not one of the scene's.
  SceneGeometry(const Scene& scene, const Solids& solids);
  SceneGeometry(const SceneGeometry&) = delete;
  SceneGeometry& operator=(const SceneGeometry&) = delete;

  const RasterGeometry& geometry() const { return geometry_; }

 private:
  std::vector<RasterMaterial> materials_;
  std::vector<RasterSolid> solids_;
  RasterGeometry geometry_;
};

// Uploads the scene's triangles, materials and solids to `raster` (Rasterizer::setGeometry). The first form uploads no
// solids, so no draw leaves their far sides out: for rasterizers that draw no light view (the reference's G-buffer,
// whose timed upload must not find them) and tests of other things; the Renderer finds them once (findSolids).
void uploadScene(Rasterizer& raster, const Scene& scene);
void uploadScene(Rasterizer& raster, const Scene& scene, const Solids& solids);

}  // namespace penumbra
