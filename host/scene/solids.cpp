// Solids of a scene (host/scene/solids.h): positions welded by value (sorted), triangles grouped by union-find over
// the welded vertices, each group checked for a closed, consistently oriented surface by its directed edges (sorted
// keys), its outside told by the sign of its enclosed volume.
#include "host/scene/solids.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>

namespace penumbra {
namespace {

// Vertex ids shared by positions equal bit for bit (glTF splits vertices at normal and uv seams): the positions
// sorted by their bits, one id per run of equal ones; `count` receives how many there are.
std::vector<uint32_t> weldedVertices(const std::vector<glm::vec3>& positions, uint32_t& count) {
  using Bits = std::array<uint32_t, 3>;
  std::vector<Bits> bits(positions.size());
  for (size_t i = 0; i < positions.size(); ++i) std::memcpy(bits[i].data(), &positions[i], sizeof(Bits));
  std::vector<uint32_t> order(positions.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return bits[a] < bits[b]; });
  std::vector<uint32_t> welded(positions.size());
  uint32_t id = 0;
  for (size_t k = 0; k < order.size(); ++k) {
    if (k > 0 && bits[order[k]] != bits[order[k - 1]]) ++id;
    welded[order[k]] = id;
  }
  count = positions.empty() ? 0 : id + 1;
  return welded;
}

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

// An edge as one sortable key: its two welded vertices, the lower first, and in bit 0 whether the triangle runs it from
// the higher (vertex ids below 2^31).
uint64_t edgeKey(uint32_t from, uint32_t to) {
  const uint64_t lo = std::min(from, to), hi = std::max(from, to);
  return (lo << 32 | hi << 1) | (from > to ? 1u : 0u);
}
constexpr uint32_t kMaxWelded = 1u << 31;

// A group's enclosed volume relative to its area times its box's diagonal below this: a closed sheet (two faces back
// to back) or a shape too flat to tell which side is out. A sphere has 0.096, a plate of thickness t and side w
// t / (2.8 w).
constexpr double kMinVolumeShare = 1e-4;

struct Group {
  bool solid = true;
  double volume = 0.0, area = 0.0;
  Bounds bounds;
  int32_t index = Solids::kNone;  // its solid, once it is one
};

}  // namespace

Solids findSolids(const Scene& scene) {
  const size_t count = scene.triangles.size();
  Solids solids;
  solids.solidOf.assign(count, Solids::kNone);
  solids.outerPlane.assign(count, glm::vec4(NAN));
  if (scene.positions.size() >= kMaxWelded) return solids;  // edge keys hold vertex ids below 2^31
  for (const glm::uvec3& t : scene.triangles)               // no solids; the rasterizer's upload names the bad index
    if (t.x >= scene.positions.size() || t.y >= scene.positions.size() || t.z >= scene.positions.size()) return solids;
  uint32_t vertices = 0;
  const std::vector<uint32_t> welded = weldedVertices(scene.positions, vertices);
  std::vector<uint32_t> parent(vertices);
  std::iota(parent.begin(), parent.end(), 0u);
  std::vector<uint64_t> keys;
  keys.reserve(3 * count);
  for (const glm::uvec3& t : scene.triangles) {
    const uint32_t v[3] = {welded[t.x], welded[t.y], welded[t.z]};
    parent[findRoot(parent, v[0])] = findRoot(parent, v[1]);
    parent[findRoot(parent, v[1])] = findRoot(parent, v[2]);
    for (int e = 0; e < 3; ++e) keys.push_back(edgeKey(v[e], v[(e + 1) % 3]));
  }
  std::vector<uint32_t> groupOf(vertices, 0xffffffffu);  // dense group ids, by way of each vertex's root
  uint32_t groupCount = 0;
  for (uint32_t v = 0; v < vertices; ++v) {
    const uint32_t root = findRoot(parent, v);
    if (groupOf[root] == 0xffffffffu) groupOf[root] = groupCount++;
    groupOf[v] = groupOf[root];
  }
  std::vector<Group> groups(groupCount);
  // A closed, consistently oriented surface runs every edge exactly twice, once each way: sorted, each edge's keys are
  // a pair whose bit 0 differs. Any other run opens the group.
  std::sort(keys.begin(), keys.end());
  for (size_t k = 0; k < keys.size();) {
    size_t end = k + 1;
    while (end < keys.size() && keys[end] >> 1 == keys[k] >> 1) ++end;
    if (end - k != 2 || (keys[k] & 1u) == (keys[k + 1] & 1u)) groups[groupOf[keys[k] >> 32]].solid = false;
    k = end;
  }
  for (size_t i = 0; i < count; ++i) {
    const glm::uvec3 t = scene.triangles[i];
    const uint32_t v[3] = {welded[t.x], welded[t.y], welded[t.z]};
    Group& g = groups[groupOf[v[0]]];
    const Material* material = scene.materialOf(i);
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0] || (material != nullptr && material->mayDiscard()))
      g.solid = false;
    const glm::dvec3 a(scene.positions[t.x]), b(scene.positions[t.y]), c(scene.positions[t.z]);
    g.volume += glm::dot(a, glm::cross(b, c)) / 6.0;
    g.area += 0.5 * glm::length(glm::cross(b - a, c - a));
    for (const glm::dvec3& p : {a, b, c}) g.bounds.grow(glm::vec3(p));
  }
  for (Group& g : groups) {
    const double diagonal = glm::length(glm::dvec3(g.bounds.max) - glm::dvec3(g.bounds.min));
    if (g.bounds.empty() || !g.solid || !(std::abs(g.volume) > kMinVolumeShare * g.area * diagonal)) continue;
    g.index = static_cast<int32_t>(solids.bounds.size());
    solids.bounds.push_back(g.bounds);
    solids.counterClockwiseOut.push_back(g.volume > 0.0 ? 1 : 0);
  }
  for (size_t i = 0; i < count; ++i) {
    const glm::uvec3 t = scene.triangles[i];
    const Group& g = groups[groupOf[welded[t.x]]];
    if (g.index == Solids::kNone) continue;
    solids.solidOf[i] = g.index;
    ++solids.triangles;
    const glm::dvec3 a(scene.positions[t.x]), b(scene.positions[t.y]), c(scene.positions[t.z]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double length = glm::length(n);
    if (!(length > 0.0)) continue;  // collinear vertices: no plane, never left out
    const glm::dvec3 outer = (g.volume > 0.0 ? 1.0 : -1.0) * n / length;
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
