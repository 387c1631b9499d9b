// Helpers shared by the scene tests (tests/scene_*_test.cpp): test-data paths, "throws SceneError whose
// message contains ...", structural invariants of a flattened Scene, and a closed-mesh check.
#pragma once

#include <cmath>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "host/scene/load_options.h"
#include "host/scene/scene.h"

namespace penumbra::test {

inline constexpr float kUnitTolerance = 1e-4f;  // |length(n) - 1| allowed for stored float normals

inline std::string sceneData(const std::string& name) {
  return std::string(PENUMBRA_TEST_DATA_DIR) + "/scenes/" + name;
}
inline std::string bundledScene(const std::string& name) { return std::string(PENUMBRA_SCENES_DIR) + "/" + name; }

// Load options whose warnings are collected instead of printed.
struct CapturingOptions {
  std::vector<std::string> warnings;
  LoadOptions options;
  CapturingOptions() {
    options.warn = [this](const std::string& w) { warnings.push_back(w); };
  }
  CapturingOptions(const CapturingOptions&) = delete;  // the sink points at this object's warnings
};

// Passes when fn() throws SceneError (or `Error`) whose message contains every one of `parts`.
template <class Error = SceneError, class Fn>
::testing::AssertionResult throwsWith(Fn fn, const std::vector<std::string>& parts) {
  try {
    fn();
  } catch (const Error& e) {
    const std::string msg = e.what();
    for (const std::string& p : parts)
      if (msg.find(p) == std::string::npos)
        return ::testing::AssertionFailure() << "message \"" << msg << "\" lacks \"" << p << "\"";
    return ::testing::AssertionSuccess() << msg;
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure() << "threw another exception type: " << e.what();
  }
  return ::testing::AssertionFailure() << "did not throw";
}

// Sizes agree, indices, object and material ids are in range, positions are finite, normals finite and unit.
inline ::testing::AssertionResult wellFormed(const Scene& s) {
  if (s.normals.size() != s.positions.size() || s.objectIds.size() != s.triangles.size())
    return ::testing::AssertionFailure() << "array sizes disagree";
  if ((!s.materials.empty() && s.materialIds.size() != s.triangles.size()) ||
      (!s.uvs.empty() && s.uvs.size() != s.positions.size()))
    return ::testing::AssertionFailure() << "material ids or texture coordinates disagree with the geometry";
  for (uint32_t id : s.materialIds)
    if (id >= s.materials.size()) return ::testing::AssertionFailure() << "material id " << id << " out of range";
  for (const glm::uvec3& t : s.triangles)
    if (t.x >= s.positions.size() || t.y >= s.positions.size() || t.z >= s.positions.size())
      return ::testing::AssertionFailure() << "index out of range";
  for (uint32_t id : s.objectIds)
    if (id >= s.objectNames.size()) return ::testing::AssertionFailure() << "object id " << id << " out of range";
  for (size_t i = 0; i < s.positions.size(); ++i) {
    const glm::vec3 p = s.positions[i], n = s.normals[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return ::testing::AssertionFailure() << "position " << i << " not finite";
    if (!(std::abs(glm::length(n) - 1.0f) <= kUnitTolerance))
      return ::testing::AssertionFailure() << "normal " << i << " has length " << glm::length(n);
  }
  return ::testing::AssertionSuccess();
}

// Every directed edge (by vertex position) of the object's triangles is matched by exactly one reverse
// edge: the object is a closed, consistently oriented surface.
inline ::testing::AssertionResult closedObject(const Scene& s, uint32_t object) {
  using Key = std::tuple<float, float, float, float, float, float>;
  std::map<Key, int> edges;
  const auto key = [&](uint32_t a, uint32_t b) {
    const glm::vec3 p = s.positions[a], q = s.positions[b];
    return Key{p.x, p.y, p.z, q.x, q.y, q.z};
  };
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    if (s.objectIds[t] != object) continue;
    for (int k = 0; k < 3; ++k) ++edges[key(s.triangles[t][k], s.triangles[t][(k + 1) % 3])];
  }
  if (edges.empty()) return ::testing::AssertionFailure() << "object " << object << " has no triangles";
  for (const auto& [e, count] : edges) {
    const auto reverse =
        edges.find(Key{std::get<3>(e), std::get<4>(e), std::get<5>(e), std::get<0>(e), std::get<1>(e), std::get<2>(e)});
    if (count != 1 || reverse == edges.end() || reverse->second != 1)
      return ::testing::AssertionFailure() << s.objectNames[object] << ": an edge is open or not manifold";
  }
  return ::testing::AssertionSuccess();
}

// Face normal (from the winding) agrees with the vertex normals of each triangle: fronts are
// counter-clockwise. Degenerate triangles are skipped.
inline ::testing::AssertionResult windingMatchesNormals(const Scene& s, float minCos = 0.0f) {
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    const glm::uvec3 i = s.triangles[t];
    const glm::vec3 n = glm::cross(s.positions[i.y] - s.positions[i.x], s.positions[i.z] - s.positions[i.x]);
    if (!(glm::length(n) > 0.0f)) continue;
    const glm::vec3 vertexNormal = s.normals[i.x] + s.normals[i.y] + s.normals[i.z];
    if (!(glm::dot(glm::normalize(n), glm::normalize(vertexNormal)) > minCos))
      return ::testing::AssertionFailure()
             << "triangle " << t << " (" << s.objectNames[s.objectIds[t]] << ") winds against its normals";
  }
  return ::testing::AssertionSuccess();
}

}  // namespace penumbra::test
