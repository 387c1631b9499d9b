// Material tables for the rasterizer: validation first (every id, coordinate count and texel range the kernels would
// read), then one pass over the triangles.
#include "raster/alpha_tables.h"

#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace penumbra::raster {
namespace {

[[noreturn]] void fail(const std::string& msg) { throw std::invalid_argument("raster scene: " + msg); }

// The material's alpha texture lies inside the atlas (only textured alpha tests read one).
void validateTexture(const RasterMaterial& m, size_t index, size_t texels) {
  const AlphaMaterial& a = m.alpha;
  if (!m.mayDiscard || (a.width == 0 && a.height == 0)) return;
  if (a.width <= 0 || a.height <= 0 ||
      uint64_t{a.texelOffset} + uint64_t(a.width) * uint64_t(a.height) > texels)
    fail(fmt::format("material {} \"{}\": alpha texture {}x{} texels at {} outside the {} texels", index, m.name,
                     a.width, a.height, a.texelOffset, texels));
}

void validate(const RasterGeometry& g) {
  if (g.materials.empty()) {
    if (!g.materialIds.empty()) fail(fmt::format("{} material ids but no materials", g.materialIds.size()));
    return;
  }
  if (g.materialIds.size() != g.triangles.size())
    fail(fmt::format("{} material ids for {} triangles", g.materialIds.size(), g.triangles.size()));
  for (size_t t = 0; t < g.materialIds.size(); ++t)
    if (g.materialIds[t] >= g.materials.size())
      fail(fmt::format("triangle {}: material {} out of range ({} materials)", t, g.materialIds[t],
                       g.materials.size()));
  if (g.alphaTexels.size() > UINT32_MAX) fail(fmt::format("{} alpha texels exceed 2^32 - 1", g.alphaTexels.size()));
  bool uvs = false;
  for (size_t i = 0; i < g.materials.size(); ++i) {
    validateTexture(g.materials[i], i, g.alphaTexels.size());
    uvs = uvs || (g.materials[i].mayDiscard && g.materials[i].alpha.width > 0);
  }
  if (uvs && g.uvs.size() != g.positions.size())
    fail(fmt::format("{} texture coordinates for {} positions", g.uvs.size(), g.positions.size()));
}

AlphaTriangle alphaTriangle(const RasterGeometry& g, size_t t) {
  AlphaTriangle a{};
  for (int k = 0; k < 3; ++k) {
    const uint32_t v = g.triangles[t][k];
    for (int c = 0; c < 3; ++c) a.position[3 * k + c] = g.positions[v][c];
    const glm::vec2 uv = g.uvs.empty() ? glm::vec2(0.0f) : g.uvs[v];
    a.uv[2 * k] = uv.x, a.uv[2 * k + 1] = uv.y;
  }
  a.material = g.materialIds[t];
  return a;
}

}  // namespace

MaterialTables materialTables(const RasterGeometry& g) {
  validate(g);
  MaterialTables out;
  if (g.materials.empty()) return out;
  for (const RasterMaterial& m : g.materials) out.materials.push_back(m.alpha);
  size_t single = 0;
  for (size_t t = 0; t < g.triangles.size(); ++t) {
    const RasterMaterial& m = g.materials[g.materialIds[t]];
    single += !m.doubleSided;
    out.summary.alphaTested = out.summary.alphaTested || m.mayDiscard;
  }
  out.summary.anySingleSided = single > 0;
  out.summary.allSingleSided = single > 0 && single == g.triangles.size();
  if (!out.summary.needsTriangleBits()) return out;
  out.triangleBits.resize(g.triangles.size());
  if (out.summary.alphaTested) out.alphaIndex.assign(g.triangles.size(), ALPHA_NO_TRIANGLE);
  for (size_t t = 0; t < g.triangles.size(); ++t) {
    const RasterMaterial& m = g.materials[g.materialIds[t]];
    uint32_t bits = m.doubleSided ? 0u : RASTER_TRI_SINGLE_SIDED;
    if (m.mayDiscard) {
      if (out.alphaTriangles.size() >= RASTER_MAX_ALPHA_TRIANGLES)
        fail(fmt::format("more than {} alpha-tested triangles", RASTER_MAX_ALPHA_TRIANGLES));
      out.alphaIndex[t] = static_cast<uint32_t>(out.alphaTriangles.size());
      bits |= RASTER_TRI_ALPHA | out.alphaIndex[t] << RASTER_TRI_ALPHA_SHIFT;
      out.alphaTriangles.push_back(alphaTriangle(g, t));
    }
    out.triangleBits[t] = bits;
  }
  return out;
}

}  // namespace penumbra::raster
