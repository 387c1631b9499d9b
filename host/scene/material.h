// What shadows need of a glTF material (glTF 2.0 sec. 3.9): its alpha mode, cutoff, base-colour alpha factor and
// texture (texCoord set, KHR_texture_transform, sampler), and whether it is double-sided; plus the decoded alpha
// textures (one byte per texel) and the records the kernels and the Embree reference sample them through
// (kernels/shared/alpha.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "kernels/shared/alpha.h"

namespace penumbra {

enum class AlphaMode : uint8_t { kOpaque, kMask, kBlend };  // glTF alphaMode; BLEND is drawn as MASK

const char* alphaModeName(AlphaMode mode);  // "OPAQUE", "MASK", "BLEND"

// KHR_texture_transform: uv' = T(offset) R(rotation) S(scale) uv, with R the rotation the extension's example and its
// implementations use (KhronosGroup/glTF#1563): u' = cos r u + sin r v, v' = -sin r u + cos r v.
struct UvTransform {
  glm::vec2 offset{0.0f};
  float rotation = 0.0f;  // radians
  glm::vec2 scale{1.0f};
  bool identity() const { return offset == glm::vec2(0.0f) && rotation == 0.0f && scale == glm::vec2(1.0f); }
};

// The transform's 2x3 matrix as AlphaMaterial::transform holds it (rows u', v'), composed in double.
void uvTransformMatrix(const UvTransform& t, float out[6]);

struct Material {
  std::string name;
  AlphaMode alphaMode = AlphaMode::kOpaque;
  float alphaCutoff = 0.5f;  // MASK: the file's (default 0.5); BLEND: LoadOptions::blendCutoff
  float baseAlpha = 1.0f;    // baseColorFactor[3]
  int alphaTexture = -1;     // Scene::alphaTextures; -1: none (alpha = baseAlpha), also for textures without alpha
  int texCoord = 0;          // TEXCOORD_<n> the texture reads (KHR_texture_transform's override applied)
  UvTransform uvTransform;
  int wrapS = ALPHA_WRAP_REPEAT, wrapT = ALPHA_WRAP_REPEAT;
  int filter = ALPHA_FILTER_LINEAR;
  bool doubleSided = true;  // glTF's default material is single-sided; scenes without materials draw both sides

  bool alphaTested() const { return alphaMode != AlphaMode::kOpaque; }
  // Whether any fragment can be discarded: alpha-tested with a texture, or a constant alpha below the cutoff.
  bool mayDiscard() const { return alphaTested() && (alphaTexture >= 0 || baseAlpha < alphaCutoff); }
  // Whether its triangles need texture coordinates (Scene::uvs).
  bool needsUvs() const { return alphaTested() && alphaTexture >= 0; }
};

// The material of triangles that come without one (procedural geometry, a scene file's ground): opaque and
// double-sided, named "(no material)".
Material plainMaterial();

// One decoded alpha texture: width x height bytes at `offset` in Scene::alphaTexels, the image's top row first.
struct AlphaTexture {
  std::string name;  // "image 3 \"leaves.png\"" for messages and the summary
  uint32_t width = 0, height = 0;
  uint64_t offset = 0;
};

// The record the kernels and the reference sample through: the material's cutoff, factor, transform and sampler, and
// its texture's place in the atlas (`textures`); a material that cannot discard gets cutoff 0 (every fragment drawn).
AlphaMaterial alphaMaterial(const Material& material, const std::vector<AlphaTexture>& textures);

}  // namespace penumbra
