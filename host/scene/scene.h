// A scene flattened for rendering: world-space triangles (glTF world space, never recentred or rescaled),
// per-vertex normals and a per-triangle object id, the materials' alpha masks and sidedness, plus the cameras and
// lights a scene file names.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "host/scene/camera.h"
#include "host/scene/light.h"
#include "host/scene/material.h"

namespace penumbra {

struct Bounds {
  glm::vec3 min{std::numeric_limits<float>::infinity()};
  glm::vec3 max{-std::numeric_limits<float>::infinity()};

  bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
  void grow(const glm::vec3& p) { min = glm::min(min, p), max = glm::max(max, p); }
  void grow(const Bounds& b) { min = glm::min(min, b.min), max = glm::max(max, b.max); }
  glm::vec3 center() const { return 0.5f * (min + max); }
  float radius() const { return 0.5f * glm::length(max - min); }  // of the bounding sphere around center()
  // These bounds, or the unit cube around the origin when empty: views of an empty scene stay finite.
  Bounds orUnit() const { return empty() ? Bounds{glm::vec3(-1.0f), glm::vec3(1.0f)} : *this; }
};

struct Scene {
  std::vector<glm::vec3> positions;   // world space
  std::vector<glm::vec3> normals;     // world space, unit length, one per position
  std::vector<glm::uvec3> triangles;  // indices into positions, counter-clockwise front faces
  std::vector<uint32_t> objectIds;    // one per triangle: index into objectNames
  std::vector<std::string> objectNames;  // one per object (mesh primitive instance, or procedural part)
  // Materials (host/scene/material.h). Empty: every triangle opaque and double-sided (no material ids). Otherwise
  // one id per triangle.
  std::vector<Material> materials;
  std::vector<uint32_t> materialIds;
  // One texture coordinate per position (the set its material's texture reads) when a material needs them
  // (Material::needsUvs), else empty: opaque scenes carry none.
  std::vector<glm::vec2> uvs;
  std::vector<AlphaTexture> alphaTextures;  // decoded alpha textures, each once
  std::vector<uint8_t> alphaTexels;         // all of them, one byte per texel (AlphaTexture::offset)
  // The default first: a scene file's, a built-in scene's, or a glTF file's (Camera::gltfIndex >= 0, the default
  // scene's camera instances in order). May be empty.
  std::vector<Camera> cameras;
  std::vector<Light> lights;          // from a scene file; may be empty

  size_t triangleCount() const { return triangles.size(); }
  Bounds bounds() const;
  // The radius of the sphere around bounds(); 0 for a scene without triangles. The shadow rays' offset floor
  // (kernels/shared/shadow_ray.h, tools/reference/tracer.cpp).
  float boundingRadius() const;
  // The material of triangle t (nullptr: opaque, double-sided: a scene without materials).
  const Material* materialOf(size_t t) const { return materials.empty() ? nullptr : &materials[materialIds[t]]; }
  bool anyMayDiscard() const;  // some material can discard fragments (Material::mayDiscard)
  // Appends another scene's geometry (object ids, material ids and textures renumbered after ours), cameras (glTF
  // indices renumbered after ours) and lights. A part without materials gets an opaque double-sided one.
  void append(const Scene& other);
};

// The glTF camera `key` names: its index among the scene's glTF cameras ("0", "1", ...) or its name (the first of
// that name). Throws std::invalid_argument: `no glTF camera "KEY" (the scene's glTF cameras: 0 "Main"
// (perspective), ...)`, or "(the scene has no glTF cameras)".
const Camera& findGltfCamera(const Scene& scene, std::string_view key);

// One line on the materials its triangles use, as far as shadows care, for the tools' summaries and the EXR header:
// "3 materials (1 MASK, 1 BLEND as MASK, 1 single-sided), 2 alpha textures, 1.5 MiB of alpha texels"; "" for a
// scene without materials.
std::string describeMaterials(const Scene& scene);

// Moves the cameras by an affine transform (eye and target as points, up as a direction); the projection is
// left as it is (a scale moves a camera, it does not zoom it).
void transformCameras(Scene& scene, const glm::mat4& transform);

// Applies an affine transform to the geometry (positions; normals by the inverse-transpose, renormalised;
// winding flipped when the transform mirrors). Cameras and lights are left alone.
void transformGeometry(Scene& scene, const glm::mat4& transform);

}  // namespace penumbra
