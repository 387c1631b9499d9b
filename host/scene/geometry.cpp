// Transforms and normal repair for ranges of a flattened scene. Work is done in double so that large
// world offsets and long transform chains keep float precision at the end.
#include "host/scene/geometry.h"

#include <cmath>
#include <utility>
#include <vector>

namespace penumbra::detail {
namespace {

bool usable(const glm::vec3& n) {
  const float len2 = glm::dot(n, n);
  return len2 > 0.0f && std::isfinite(len2);
}

}  // namespace

glm::dmat3 normalMatrix(const glm::dmat3& m) {
  const glm::dmat3 cofactor(glm::cross(m[1], m[2]), glm::cross(m[2], m[0]), glm::cross(m[0], m[1]));
  return glm::determinant(m) < 0.0 ? -cofactor : cofactor;
}

glm::vec3 faceNormal(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::dvec3 n = glm::cross(glm::dvec3(b) - glm::dvec3(a), glm::dvec3(c) - glm::dvec3(a));
  const double len = glm::length(n);
  return len > 0.0 && std::isfinite(len) ? glm::vec3(n / len) : glm::vec3(0.0f);
}

void transformRange(Scene& scene, const glm::dmat4& m, size_t firstVertex, size_t firstTriangle) {
  const glm::dmat3 linear(m);
  const glm::dmat3 normals = normalMatrix(linear);
  for (size_t i = firstVertex; i < scene.positions.size(); ++i) {
    scene.positions[i] = glm::vec3(m * glm::dvec4(glm::dvec3(scene.positions[i]), 1.0));
    const glm::dvec3 n = normals * glm::dvec3(scene.normals[i]);
    const double len = glm::length(n);
    if (len > 0.0 && std::isfinite(len)) scene.normals[i] = glm::vec3(n / len);
  }
  if (glm::determinant(linear) < 0.0)
    for (size_t t = firstTriangle; t < scene.triangles.size(); ++t)
      std::swap(scene.triangles[t].y, scene.triangles[t].z);
}

size_t repairNormals(Scene& scene, size_t firstVertex, size_t firstTriangle) {
  std::vector<size_t> bad;
  for (size_t i = firstVertex; i < scene.normals.size(); ++i) {
    if (usable(scene.normals[i]))
      scene.normals[i] = glm::normalize(scene.normals[i]);
    else
      bad.push_back(i);
  }
  if (bad.empty()) return 0;
  std::vector<glm::dvec3> sums(scene.positions.size() - firstVertex, glm::dvec3(0.0));
  for (size_t t = firstTriangle; t < scene.triangles.size(); ++t) {
    const glm::uvec3 tri = scene.triangles[t];
    const glm::dvec3 a(scene.positions[tri.x]), b(scene.positions[tri.y]), c(scene.positions[tri.z]);
    const glm::dvec3 areaNormal = glm::cross(b - a, c - a);  // length = twice the area: area weighting
    for (int k = 0; k < 3; ++k)
      if (tri[k] >= firstVertex) sums[tri[k] - firstVertex] += areaNormal;
  }
  for (size_t i : bad) {
    const glm::vec3 n(sums[i - firstVertex]);
    scene.normals[i] = usable(n) ? glm::normalize(n) : glm::vec3(0, 1, 0);
  }
  return bad.size();
}

}  // namespace penumbra::detail
