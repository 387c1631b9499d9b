// The materials of a glTF file as shadows see them (host/scene/material.h; glTF 2.0 sec. 3.9, 3.8): alphaMode,
// alphaCutoff, baseColorFactor's alpha, baseColorTexture with its texCoord set, KHR_texture_transform and sampler,
// and doubleSided; the default material for primitives without one; the alpha textures of the alpha-tested
// materials the scene uses, each image decoded once (gltf_images.h).
#pragma once

#include <cstdint>
#include <set>
#include <vector>

#include "host/scene/gltf_accessor.h"
#include "host/scene/gltf_images.h"
#include "host/scene/material.h"

namespace penumbra::detail {

struct GltfMaterials {
  std::vector<Material> materials;  // the file's, in order, then glTF's default material (opaque, single-sided)
  std::vector<AlphaTexture> textures;
  std::vector<uint8_t> texels;
  uint32_t defaultMaterial = 0;  // index of the default material, for primitives without one
  bool needsUvs() const;         // some material needs texture coordinates (Material::needsUvs)
};

// Reads every material; decodes the textures of the alpha-tested ones in `used` (material indices the scene's
// primitives use). BLEND materials get LoadOptions::blendCutoff. Throws SceneError naming the file and the material
// for a texture without an image source and for every image error of decodeImageAlpha.
GltfMaterials readMaterials(const GltfContext& ctx, const ImageSources& sources, const std::set<int>& used);

}  // namespace penumbra::detail
