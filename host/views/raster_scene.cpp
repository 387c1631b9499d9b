// Scene -> RasterGeometry: per material, alphaMaterial()'s record (host/scene/material.h) once its texture index is
// checked; the arrays are the scene's own.
#include "host/views/raster_scene.h"

#include <fmt/format.h>

#include <stdexcept>

#include "host/scene/solids.h"

namespace penumbra {

SceneGeometry::SceneGeometry(const Scene& scene, const Solids& solids) {
  materials_.reserve(scene.materials.size());
  for (const Material& m : scene.materials) {
    if (m.alphaTexture >= 0 && static_cast<size_t>(m.alphaTexture) >= scene.alphaTextures.size())
      throw std::invalid_argument(fmt::format("raster scene: material \"{}\": alpha texture {} out of range ({} textures)",
                                              m.name, m.alphaTexture, scene.alphaTextures.size()));
    materials_.push_back({alphaMaterial(m, scene.alphaTextures), m.mayDiscard(), m.doubleSided, m.name.c_str()});
  }
  geometry_.positions = scene.positions;
  geometry_.normals = scene.normals;
  geometry_.triangles = scene.triangles;
  geometry_.objectIds = scene.objectIds;
  geometry_.materials = materials_;
  geometry_.materialIds = scene.materialIds;
  geometry_.uvs = scene.uvs;
  geometry_.alphaTexels = scene.alphaTexels;
  for (size_t s = 0; s < solids.bounds.size(); ++s)
    solids_.push_back({solids.bounds[s].min, solids.bounds[s].max, solids.counterClockwiseOut[s] != 0});
  geometry_.solidOf = solids.solidOf;
  geometry_.solids = solids_;
}

void uploadScene(Rasterizer& raster, const Scene& scene) { uploadScene(raster, scene, Solids{}); }

void uploadScene(Rasterizer& raster, const Scene& scene, const Solids& solids) {
  raster.setGeometry(SceneGeometry(scene, solids).geometry());
}

}  // namespace penumbra
