// Material reading. The schema (gltf_schema.cpp) has checked every value's type and range, so this file maps them:
// sampler filters to the base level's (magFilter, else minFilter's within-level filter, else LINEAR), wraps to
// kernels/shared/alpha.h's, KHR_texture_transform to a UvTransform with its texCoord override.
#include "host/scene/gltf_materials.h"

#include <algorithm>
#include <map>

#include <fmt/format.h>

namespace penumbra::detail {
namespace {

int wrapMode(int gltf) {
  switch (gltf) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
      return ALPHA_WRAP_CLAMP;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
      return ALPHA_WRAP_MIRROR;
    default:
      return ALPHA_WRAP_REPEAT;
  }
}

// No mip levels are built: a mipmapped minFilter samples the base level with its within-level filter (the first
// word of NEAREST_MIPMAP_LINEAR), and magFilter, the filter for a texture seen close up, wins when both are given.
int filterMode(const tinygltf::Sampler& s) {
  const int f = s.magFilter >= 0 ? s.magFilter : s.minFilter;
  const bool nearest = f == TINYGLTF_TEXTURE_FILTER_NEAREST || f == TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST ||
                       f == TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR;
  return nearest ? ALPHA_FILTER_NEAREST : ALPHA_FILTER_LINEAR;
}

glm::vec2 vec2Of(const tinygltf::Value& v, glm::vec2 fallback) {
  if (!v.IsArray() || v.ArrayLen() != 2) return fallback;
  return {static_cast<float>(v.Get(0).GetNumberAsDouble()), static_cast<float>(v.Get(1).GetNumberAsDouble())};
}

// KHR_texture_transform on the base-colour textureInfo: the transform and the texCoord set it reads.
void readTransform(const tinygltf::TextureInfo& info, Material& m) {
  m.texCoord = info.texCoord;
  const auto it = info.extensions.find("KHR_texture_transform");
  if (it == info.extensions.end() || !it->second.IsObject()) return;
  const tinygltf::Value& x = it->second;
  if (x.Has("offset")) m.uvTransform.offset = vec2Of(x.Get("offset"), glm::vec2(0.0f));
  if (x.Has("rotation")) m.uvTransform.rotation = static_cast<float>(x.Get("rotation").GetNumberAsDouble());
  if (x.Has("scale")) m.uvTransform.scale = vec2Of(x.Get("scale"), glm::vec2(1.0f));
  if (x.Has("texCoord")) m.texCoord = x.Get("texCoord").GetNumberAsInt();
}

Material readMaterial(const GltfContext& ctx, int index) {
  const tinygltf::Material& g = ctx.model.materials[static_cast<size_t>(index)];
  Material m;
  m.name = g.name.empty() ? fmt::format("material {}", index) : g.name;
  m.alphaMode = g.alphaMode == "MASK" ? AlphaMode::kMask : g.alphaMode == "BLEND" ? AlphaMode::kBlend : AlphaMode::kOpaque;
  m.alphaCutoff = m.alphaMode == AlphaMode::kBlend ? ctx.options.blendCutoff : static_cast<float>(g.alphaCutoff);
  const std::vector<double>& factor = g.pbrMetallicRoughness.baseColorFactor;
  m.baseAlpha = factor.size() == 4 ? static_cast<float>(factor[3]) : 1.0f;
  m.doubleSided = g.doubleSided;
  const tinygltf::TextureInfo& info = g.pbrMetallicRoughness.baseColorTexture;
  if (info.index < 0) return m;
  readTransform(info, m);
  const tinygltf::Texture& texture = ctx.model.textures.at(static_cast<size_t>(info.index));
  if (texture.sampler >= 0) {
    const tinygltf::Sampler& s = ctx.model.samplers.at(static_cast<size_t>(texture.sampler));
    m.wrapS = wrapMode(s.wrapS), m.wrapT = wrapMode(s.wrapT), m.filter = filterMode(s);
  }
  return m;
}

}  // namespace

bool GltfMaterials::needsUvs() const {
  return std::any_of(materials.begin(), materials.end(), [](const Material& m) { return m.needsUvs(); });
}

GltfMaterials readMaterials(const GltfContext& ctx, const ImageSources& sources, const std::set<int>& used) {
  GltfMaterials out;
  std::map<int, int> decoded;  // image -> alpha texture (-1: the image has no alpha)
  for (int i = 0; i < static_cast<int>(ctx.model.materials.size()); ++i) {
    Material m = readMaterial(ctx, i);
    const int textureIndex = ctx.model.materials[static_cast<size_t>(i)].pbrMetallicRoughness.baseColorTexture.index;
    if (m.alphaTested() && textureIndex >= 0 && used.count(i) != 0) {
      const int image = ctx.model.textures.at(static_cast<size_t>(textureIndex)).source;
      if (image < 0)
        failGltf(ctx, fmt::format("material {} (\"{}\"): texture {} has no image source (textures only given by "
                                  "extensions such as EXT_texture_webp or KHR_texture_basisu are not supported)",
                                  i, m.name, textureIndex));
      auto it = decoded.find(image);
      if (it == decoded.end()) {
        DecodedAlpha alpha = decodeImageAlpha(ctx, sources, image);
        int texture = -1;
        if (alpha.hasAlpha) {
          texture = static_cast<int>(out.textures.size());
          out.textures.push_back({imageLabel(ctx, image), alpha.width, alpha.height, out.texels.size()});
          out.texels.insert(out.texels.end(), alpha.texels.begin(), alpha.texels.end());
        }
        it = decoded.emplace(image, texture).first;
      }
      m.alphaTexture = it->second;
    }
    out.materials.push_back(std::move(m));
  }
  out.defaultMaterial = static_cast<uint32_t>(out.materials.size());
  Material fallback;  // glTF 2.0 sec. 3.9.6: the default material is opaque and single-sided
  fallback.name = "(default material)";
  fallback.doubleSided = false;
  out.materials.push_back(fallback);
  return out;
}

}  // namespace penumbra::detail
