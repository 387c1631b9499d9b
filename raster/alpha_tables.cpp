// Material tables for the rasterizer: validation first (every id, coordinate count and texel range the kernels would
// read), then one pass over the triangles.
#include "raster/alpha_tables.h"

#include <stdexcept>

#include <fmt/format.h>

namespace penumbra::raster {
namespace {

void validate(const Scene& scene) {
  const auto fail = [](const std::string& msg) { throw std::invalid_argument("raster scene: " + msg); };
  if (scene.materials.empty()) {
    if (!scene.materialIds.empty()) fail(fmt::format("{} material ids but no materials", scene.materialIds.size()));
    return;
  }
  if (scene.materialIds.size() != scene.triangles.size())
    fail(fmt::format("{} material ids for {} triangles", scene.materialIds.size(), scene.triangles.size()));
  for (size_t t = 0; t < scene.materialIds.size(); ++t)
    if (scene.materialIds[t] >= scene.materials.size())
      fail(fmt::format("triangle {}: material {} out of range ({} materials)", t, scene.materialIds[t],
                       scene.materials.size()));
  bool uvs = false;
  for (const Material& m : scene.materials) {
    uvs = uvs || m.needsUvs();
    if (m.alphaTexture < 0) continue;
    if (static_cast<size_t>(m.alphaTexture) >= scene.alphaTextures.size())
      fail(fmt::format("material \"{}\": alpha texture {} out of range ({} textures)", m.name, m.alphaTexture,
                       scene.alphaTextures.size()));
  }
  if (uvs && scene.uvs.size() != scene.positions.size())
    fail(fmt::format("{} texture coordinates for {} positions", scene.uvs.size(), scene.positions.size()));
  if (scene.alphaTexels.size() > UINT32_MAX) fail(fmt::format("{} alpha texels exceed 2^32 - 1", scene.alphaTexels.size()));
  for (const AlphaTexture& t : scene.alphaTextures)
    if (t.width == 0 || t.height == 0 || t.offset + uint64_t{t.width} * t.height > scene.alphaTexels.size())
      fail(fmt::format("alpha texture {}: {}x{} texels at {} outside the {} texels", t.name, t.width, t.height,
                       t.offset, scene.alphaTexels.size()));
}

AlphaTriangle alphaTriangle(const Scene& scene, size_t t) {
  AlphaTriangle a{};
  for (int k = 0; k < 3; ++k) {
    const uint32_t v = scene.triangles[t][k];
    for (int c = 0; c < 3; ++c) a.position[3 * k + c] = scene.positions[v][c];
    const glm::vec2 uv = scene.uvs.empty() ? glm::vec2(0.0f) : scene.uvs[v];
    a.uv[2 * k] = uv.x, a.uv[2 * k + 1] = uv.y;
  }
  a.material = scene.materialIds[t];
  return a;
}

}  // namespace

MaterialTables materialTables(const Scene& scene) {
  validate(scene);
  MaterialTables out;
  if (scene.materials.empty()) return out;
  for (const Material& m : scene.materials) out.materials.push_back(alphaMaterial(m, scene.alphaTextures));
  size_t single = 0;
  for (size_t t = 0; t < scene.triangles.size(); ++t) {
    const Material& m = scene.materials[scene.materialIds[t]];
    single += !m.doubleSided;
    out.summary.alphaTested = out.summary.alphaTested || m.mayDiscard();
  }
  out.summary.anySingleSided = single > 0;
  out.summary.allSingleSided = single > 0 && single == scene.triangles.size();
  if (!out.summary.needsTriangleBits()) return out;
  out.triangleBits.resize(scene.triangles.size());
  if (out.summary.alphaTested) out.alphaIndex.assign(scene.triangles.size(), ALPHA_NO_TRIANGLE);
  for (size_t t = 0; t < scene.triangles.size(); ++t) {
    const Material& m = scene.materials[scene.materialIds[t]];
    uint32_t bits = m.doubleSided ? 0u : RASTER_TRI_SINGLE_SIDED;
    if (m.mayDiscard()) {
      if (out.alphaTriangles.size() >= RASTER_MAX_ALPHA_TRIANGLES)
        throw std::invalid_argument(fmt::format("raster scene: more than {} alpha-tested triangles",
                                                RASTER_MAX_ALPHA_TRIANGLES));
      out.alphaIndex[t] = static_cast<uint32_t>(out.alphaTriangles.size());
      bits |= RASTER_TRI_ALPHA | out.alphaIndex[t] << RASTER_TRI_ALPHA_SHIFT;
      out.alphaTriangles.push_back(alphaTriangle(scene, t));
    }
    out.triangleBits[t] = bits;
  }
  return out;
}

}  // namespace penumbra::raster
