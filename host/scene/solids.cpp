// Solids of a scene (host/scene/solids.h): positions welded by value, triangles grouped by union-find over the welded
// vertices, each group checked for a closed, consistently oriented surface by its directed edges, its outside told by
// the sign of its enclosed volume.
#include "host/scene/solids.h"

#include <cmath>
#include <cstring>
#include <numeric>
#include <unordered_map>

namespace penumbra {
namespace {

// Vertex ids shared by positions equal bit for bit (glTF splits vertices at normal and uv seams).
std::vector<uint32_t> weldedVertices(const std::vector<glm::vec3>& positions) {
  struct Key {
    uint32_t x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct Hash {
    size_t operator()(const Key& k) const { return (size_t{k.x} * 0x9e3779b1u) ^ (size_t{k.y} * 0x85ebca6bu) ^ k.z; }
  };
  std::unordered_map<Key, uint32_t, Hash> ids;
  ids.reserve(positions.size());
  std::vector<uint32_t> welded(positions.size());
  for (size_t i = 0; i < positions.size(); ++i) {
    Key k;
    std::memcpy(&k, &positions[i], sizeof k);
    welded[i] = ids.emplace(k, static_cast<uint32_t>(ids.size())).first->second;
  }
  return welded;
}

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

uint64_t edgeKey(uint32_t from, uint32_t to) { return (uint64_t{from} << 32) | to; }

// A group's enclosed volume relative to its area times its box's diagonal below this: a closed sheet (two faces back
// to back) or a shape too flat to tell which side is out. A sphere has 0.096, a plate of thickness t and side w
// t / (2.8 w).
constexpr double kMinVolumeShare = 1e-4;

struct Group {
  bool solid = true;
  double volume = 0.0, area = 0.0;
  Bounds bounds;
};

}  // namespace

Solids findSolids(const Scene& scene) {
  const size_t count = scene.triangles.size();
  const std::vector<uint32_t> welded = weldedVertices(scene.positions);
  std::vector<uint32_t> parent(scene.positions.size());
  std::iota(parent.begin(), parent.end(), 0u);
  std::unordered_map<uint64_t, uint32_t> edges;
  edges.reserve(3 * count);
  for (const glm::uvec3& t : scene.triangles) {
    const uint32_t v[3] = {welded[t.x], welded[t.y], welded[t.z]};
    parent[findRoot(parent, v[0])] = findRoot(parent, v[1]);
    parent[findRoot(parent, v[1])] = findRoot(parent, v[2]);
    for (int e = 0; e < 3; ++e) ++edges[edgeKey(v[e], v[(e + 1) % 3])];
  }
  std::unordered_map<uint32_t, Group> groups;
  for (size_t i = 0; i < count; ++i) {
    const glm::uvec3 t = scene.triangles[i];
    const uint32_t v[3] = {welded[t.x], welded[t.y], welded[t.z]};
    Group& g = groups[findRoot(parent, v[0])];
    const Material* material = scene.materialOf(i);
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0] || (material != nullptr && material->mayDiscard()))
      g.solid = false;
    for (int e = 0; e < 3; ++e) {
      const auto along = edges.find(edgeKey(v[e], v[(e + 1) % 3])), back = edges.find(edgeKey(v[(e + 1) % 3], v[e]));
      if (along->second != 1 || back == edges.end() || back->second != 1) g.solid = false;
    }
    const glm::dvec3 a(scene.positions[t.x]), b(scene.positions[t.y]), c(scene.positions[t.z]);
    g.volume += glm::dot(a, glm::cross(b, c)) / 6.0;
    g.area += 0.5 * glm::length(glm::cross(b - a, c - a));
    for (const glm::dvec3& p : {a, b, c}) g.bounds.grow(glm::vec3(p));
  }
  Solids solids;
  solids.solidOf.assign(count, Solids::kNone);
  solids.outerPlane.assign(count, glm::vec4(NAN));
  std::unordered_map<uint32_t, int32_t> index;  // group root -> solid
  for (auto& [root, g] : groups) {
    const double diagonal = glm::length(glm::dvec3(g.bounds.max) - glm::dvec3(g.bounds.min));
    if (!g.solid || !(std::abs(g.volume) > kMinVolumeShare * g.area * diagonal)) continue;
    index[root] = static_cast<int32_t>(solids.bounds.size());
    solids.bounds.push_back(g.bounds);
    solids.counterClockwiseOut.push_back(g.volume > 0.0 ? 1 : 0);
  }
  for (size_t i = 0; i < count; ++i) {
    const glm::uvec3 t = scene.triangles[i];
    const uint32_t root = findRoot(parent, welded[t.x]);
    const auto solid = index.find(root);
    if (solid == index.end()) continue;
    solids.solidOf[i] = solid->second;
    ++solids.triangles;
    const glm::dvec3 a(scene.positions[t.x]), b(scene.positions[t.y]), c(scene.positions[t.z]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double length = glm::length(n);
    if (!(length > 0.0)) continue;  // collinear vertices: no plane, never left out
    const glm::dvec3 outer = (groups[root].volume > 0.0 ? 1.0 : -1.0) * n / length;
    solids.outerPlane[i] = glm::vec4(glm::vec3(outer), static_cast<float>(glm::dot(outer, a)));
  }
  return solids;
}

LightExtent lightExtent(const Light& light) {
  LightExtent e;
  e.sun = light.type == LightType::Directional;
  e.centre = light.position;
  e.towardSun = -light.axis();
  e.radius = light.radius;
  e.angularRadius = glm::radians(light.angularRadiusDeg);
  return e;
}

bool facesAwayFromLight(const Solids& solids, size_t t, const LightExtent& light) {
  const int32_t solid = solids.solidOf[t];
  const glm::vec4 plane = solids.outerPlane[t];
  if (solid == Solids::kNone || !std::isfinite(plane.w)) return false;
  const glm::vec3 n(plane);
  // Rounding of the plane (its normal and offset, from float vertices) and of the light's numbers: well below this.
  constexpr float kAngleMargin = 1e-4f;
  if (light.sun) return glm::dot(n, light.towardSun) < -(std::sin(light.angularRadius) + kAngleMargin);
  const Bounds& box = solids.bounds[solid];
  const float margin = 1e-4f * (light.radius + glm::length(light.centre - box.center()) + box.radius());
  const glm::vec3 nearest = glm::clamp(light.centre, box.min, box.max);
  if (glm::length(light.centre - nearest) <= light.radius + margin) return false;  // the light may lie inside
  return glm::dot(n, light.centre) - plane.w < -(light.radius + margin);
}

}  // namespace penumbra
