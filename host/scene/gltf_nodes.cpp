// Node hierarchy checks and flattening. The hierarchy is validated as a forest first (parent links, then
// reachability from parentless nodes: anything unreachable hangs off a cycle), so the traversal after it
// is a plain iterative depth-first walk that visits each node once.
#include "host/scene/gltf_nodes.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "host/scene/limits.h"

namespace penumbra::detail {
namespace {

constexpr double kAffineTolerance = 1e-6;  // the bottom row of a node matrix must be (0, 0, 0, 1)

bool allFinite(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

void checkProperty(const GltfContext& ctx, int index, const char* name, const std::vector<double>& v, size_t size) {
  if (!v.empty() && v.size() != size)
    failGltf(ctx, fmt::format("node {}: {} has {} numbers, expected {}", index, name, v.size(), size));
  if (!allFinite(v)) failGltf(ctx, fmt::format("node {}: {} contains a non-finite value", index, name));
}

glm::dmat4 localMatrix(const GltfContext& ctx, int index, const tinygltf::Node& n, const NodePose& pose) {
  checkProperty(ctx, index, "matrix", n.matrix, 16);
  checkProperty(ctx, index, "translation", n.translation, 3);
  checkProperty(ctx, index, "rotation", n.rotation, 4);
  checkProperty(ctx, index, "scale", n.scale, 3);
  if (!n.matrix.empty()) {  // never animated (evaluateAnimations refuses channels on it)
    if (!n.translation.empty() || !n.rotation.empty() || !n.scale.empty())
      emitWarning(ctx.options, fmt::format("{}: node {}: has both matrix and TRS; using the matrix", ctx.file, index));
    const glm::dmat4 m = glm::make_mat4(n.matrix.data());  // glTF matrices are column-major, as glm's
    const glm::dvec4 bottom(m[0][3], m[1][3], m[2][3], m[3][3]);
    if (glm::length(bottom - glm::dvec4(0, 0, 0, 1)) > kAffineTolerance)
      failGltf(ctx, fmt::format("node {}: matrix is not affine (bottom row {}, {}, {}, {})", index, bottom.x, bottom.y,
                                bottom.z, bottom.w));
    return m;
  }
  glm::dmat4 m(1.0);
  if (pose.translation)
    m = glm::translate(m, *pose.translation);
  else if (!n.translation.empty())
    m = glm::translate(m, glm::make_vec3(n.translation.data()));
  if (pose.rotation || !n.rotation.empty()) {
    // glTF stores x, y, z, w
    const glm::dquat q =
        pose.rotation ? *pose.rotation : glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
    const double len = glm::length(q);
    if (!(len > 0.0) || !std::isfinite(len))
      failGltf(ctx, fmt::format("node {}: rotation is a zero or non-finite quaternion{}", index,
                                pose.rotation ? " (animated)" : ""));
    m *= glm::mat4_cast(q / len);
  }
  if (pose.scale)
    m = glm::scale(m, *pose.scale);
  else if (!n.scale.empty())
    m = glm::scale(m, glm::make_vec3(n.scale.data()));
  return m;
}

// Parent of every node (-1 for roots); throws for out-of-range children, self-children and two parents.
std::vector<int> parentLinks(const GltfContext& ctx) {
  const auto& nodes = ctx.model.nodes;
  std::vector<int> parent(nodes.size(), -1);
  for (size_t i = 0; i < nodes.size(); ++i) {
    for (int c : nodes[i].children) {
      if (c < 0 || static_cast<size_t>(c) >= nodes.size())
        failGltf(ctx, fmt::format("node {}: child {} does not exist", i, c));
      if (static_cast<size_t>(c) == i) failGltf(ctx, fmt::format("node {}: is its own child (cycle)", i));
      if (parent[static_cast<size_t>(c)] != -1)
        failGltf(ctx,
                 fmt::format("node {}: has two parents (node {} and node {})", c, parent[static_cast<size_t>(c)], i));
      parent[static_cast<size_t>(c)] = static_cast<int>(i);
    }
  }
  return parent;
}

// Throws when some node cannot be reached from a parentless node: it lies on, or hangs off, a cycle.
void checkAcyclic(const GltfContext& ctx, const std::vector<int>& parent) {
  const auto& nodes = ctx.model.nodes;
  std::vector<char> reached(nodes.size(), 0);
  std::vector<size_t> stack;
  for (size_t i = 0; i < nodes.size(); ++i)
    if (parent[i] == -1) stack.push_back(i);
  while (!stack.empty()) {
    const size_t i = stack.back();
    stack.pop_back();
    reached[i] = 1;
    for (int c : nodes[i].children) stack.push_back(static_cast<size_t>(c));
  }
  const auto it = std::find(reached.begin(), reached.end(), 0);
  if (it == reached.end()) return;
  int onCycle = static_cast<int>(it - reached.begin());
  for (size_t step = 0; step < nodes.size(); ++step) onCycle = parent[static_cast<size_t>(onCycle)];
  std::vector<int> cycle{onCycle};
  for (int p = parent[static_cast<size_t>(onCycle)]; p != onCycle; p = parent[static_cast<size_t>(p)])
    cycle.push_back(p);
  std::string text;
  for (auto c = cycle.rbegin(); c != cycle.rend(); ++c) text += fmt::format("node {} -> ", *c);
  failGltf(ctx, fmt::format("node hierarchy has a cycle: {}node {}", text, cycle.back()));
}

std::vector<int> sceneRoots(const GltfContext& ctx, const std::vector<int>& parent) {
  const tinygltf::Model& m = ctx.model;
  std::vector<int> roots;
  if (m.defaultScene >= 0 || !m.scenes.empty()) {
    const int s = std::max(m.defaultScene, 0);
    if (static_cast<size_t>(s) >= m.scenes.size()) failGltf(ctx, fmt::format("scene {} does not exist", s));
    roots = m.scenes[static_cast<size_t>(s)].nodes;
    std::vector<char> listed(m.nodes.size(), 0);
    for (int r : roots) {
      if (r < 0 || static_cast<size_t>(r) >= m.nodes.size())
        failGltf(ctx, fmt::format("scene {}: node {} does not exist", s, r));
      if (parent[static_cast<size_t>(r)] != -1)
        failGltf(ctx, fmt::format("scene {}: node {} is listed as a root but is a child of node {}", s, r,
                                  parent[static_cast<size_t>(r)]));
      if (listed[static_cast<size_t>(r)]++) failGltf(ctx, fmt::format("scene {}: node {} is listed twice", s, r));
    }
    return roots;
  }
  for (size_t i = 0; i < m.nodes.size(); ++i)
    if (parent[i] == -1) roots.push_back(static_cast<int>(i));
  return roots;
}

}  // namespace

std::vector<NodeInstance> flattenNodes(const GltfContext& ctx, const std::vector<NodePose>& poses) {
  const std::vector<int> parent = parentLinks(ctx);
  checkAcyclic(ctx, parent);
  std::vector<NodeInstance> out, stack;
  for (int r : sceneRoots(ctx, parent)) stack.push_back({r, glm::dmat4(1.0)});
  std::reverse(stack.begin(), stack.end());  // visit roots in the scene's order
  while (!stack.empty()) {
    const NodeInstance top = stack.back();
    stack.pop_back();
    const tinygltf::Node& node = ctx.model.nodes[static_cast<size_t>(top.node)];
    const glm::dmat4 world = top.world * localMatrix(ctx, top.node, node, poses[static_cast<size_t>(top.node)]);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(world[c][r])) failGltf(ctx, fmt::format("node {}: world transform overflows", top.node));
    if (!inCoordinateRange(world[3].x, world[3].y, world[3].z))
      failGltf(ctx, fmt::format("node {}: world translation ({}, {}, {}) is outside +-{:g} (the renderer's coordinate "
                                "range)",
                                top.node, world[3].x, world[3].y, world[3].z, kMaxCoordinate));
    out.push_back({top.node, world});
    for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) stack.push_back({*c, world});
  }
  return out;
}

}  // namespace penumbra::detail
