// Material records: the KHR_texture_transform matrix and the AlphaMaterial the kernels and the Embree reference share.
#include "host/scene/material.h"

#include <cmath>

namespace penumbra {

const char* alphaModeName(AlphaMode mode) {
  switch (mode) {
    case AlphaMode::kMask:
      return "MASK";
    case AlphaMode::kBlend:
      return "BLEND";
    case AlphaMode::kOpaque:
      break;
  }
  return "OPAQUE";
}

Material plainMaterial() {
  Material m;
  m.name = "(no material)";
  return m;
}

void uvTransformMatrix(const UvTransform& t, float out[6]) {
  const double c = std::cos(double{t.rotation}), s = std::sin(double{t.rotation});
  const double sx = t.scale.x, sy = t.scale.y;
  // T R S: the rotation's rows (c, s) and (-s, c) times diag(sx, sy), then the offset.
  out[0] = static_cast<float>(c * sx), out[1] = static_cast<float>(s * sy), out[2] = t.offset.x;
  out[3] = static_cast<float>(-s * sx), out[4] = static_cast<float>(c * sy), out[5] = t.offset.y;
}

AlphaMaterial alphaMaterial(const Material& material, const std::vector<AlphaTexture>& textures) {
  AlphaMaterial m{};
  uvTransformMatrix(material.uvTransform, m.transform);
  m.cutoff = material.mayDiscard() ? material.alphaCutoff : 0.0f;
  m.factor = material.baseAlpha;
  m.wrapS = material.wrapS, m.wrapT = material.wrapT, m.filter = material.filter;
  if (material.needsUvs()) {
    const AlphaTexture& texture = textures.at(static_cast<size_t>(material.alphaTexture));
    m.texelOffset = static_cast<uint32_t>(texture.offset);
    m.width = static_cast<int>(texture.width), m.height = static_cast<int>(texture.height);
  }
  return m;
}

}  // namespace penumbra
