// What the rasterizer draws, as plain arrays (Rasterizer::setGeometry): world-space triangles with their vertex
// normals and object ids, and the alpha-tested and single-sided materials as the records its kernels read
// (kernels/shared/alpha.h). The rasterizer knows nothing of scenes or glTF: host/views/raster_scene.h makes these
// views of a Scene.
#pragma once

#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "kernels/shared/alpha.h"

namespace penumbra {

// A closed group of triangles (RasterGeometry::solidOf): a segment from a point outside it that meets it first crosses
// one of its triangles from that triangle's outer side (host/scene/solids.h finds them).
struct RasterSolid {
  glm::vec3 min{0.0f}, max{0.0f};   // its box
  bool counterClockwiseOut = true;  // which winding faces out
};

// One material as far as the rasterizer cares.
struct RasterMaterial {
  // The record the fine stage samples: cutoff, alpha factor, texture transform and sampler, and the texture's place
  // in RasterGeometry::alphaTexels (texelOffset, width, height; read only when mayDiscard and width > 0).
  AlphaMaterial alpha{};
  bool mayDiscard = false;  // some fragment may fall below the cutoff (alpha-tested with a texture or a low factor)
  bool doubleSided = true;  // false: the camera's G-buffer culls its back faces (RasterView::cullSingleSided)
  const char* name = "";    // for messages; may be empty
};

// Views of the caller's arrays, read during Rasterizer::setGeometry only.
struct RasterGeometry {
  std::span<const glm::vec3> positions;  // world space
  std::span<const glm::vec3> normals;    // empty, or one per position (the G-buffer's shading normals)
  std::span<const glm::uvec3> triangles;  // indices into positions, counter-clockwise front faces
  std::span<const uint32_t> objectIds;    // empty (all 0), or one per triangle
  // Empty: every triangle opaque and double-sided, and materialIds empty. Otherwise one id per triangle.
  std::span<const RasterMaterial> materials;
  std::span<const uint32_t> materialIds;
  std::span<const glm::vec2> uvs;  // one per position when a material has an alpha texture, else may be empty
  std::span<const uint8_t> alphaTexels;  // every alpha texture, one byte per texel (RasterMaterial::alpha)
  // Empty, or one entry per triangle: the index of the solid it bounds in `solids`, or kNoSolid
  // (RasterView::cullSolidsFarSides).
  std::span<const int32_t> solidOf;
  std::span<const RasterSolid> solids;
  static constexpr int32_t kNoSolid = -1;
};

}  // namespace penumbra
