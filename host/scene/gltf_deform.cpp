// Morphing and skinning (glTF 2.0 sec. 3.7.2.2 "Morph Targets", 3.7.3 "Skins"): targets hold displacements per
// accessor vertex, summed with the node's weights in the mesh's own space; a skin then moves each vertex by the
// weighted joint matrices J_i IBM_i into world space.
#include "host/scene/gltf_deform.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <glm/gtc/matrix_inverse.hpp>

#include "host/scene/geometry.h"

namespace penumbra::detail {
namespace {

// The accessor vertex of position i (flat primitives repeat vertices: LocalPrimitive::source).
size_t sourceOf(const LocalPrimitive& prim, size_t i) { return prim.source.empty() ? i : prim.source[i]; }

// Accessor vertices the primitive uses (flat ones: one past the largest source).
size_t accessorVertices(const LocalPrimitive& prim) {
  if (prim.source.empty()) return prim.positions.size();
  return static_cast<size_t>(*std::max_element(prim.source.begin(), prim.source.end())) + 1;
}

std::vector<glm::vec3> targetAttribute(const GltfContext& ctx, const std::string& what, int accessor,
                                       const char* semantic, size_t vertices) {
  std::vector<glm::vec3> d = readVec3(ctx, accessor, semantic);
  if (d.size() < vertices)
    failGltf(ctx, fmt::format("{}: {} has {} elements, the primitive {} vertices", what, semantic, d.size(), vertices));
  return d;
}

void morph(const GltfContext& ctx, const std::string& what, const tinygltf::Primitive& tp,
           const std::vector<double>& weights, LocalPrimitive& prim) {
  const size_t vertices = accessorVertices(prim);
  for (size_t t = 0; t < tp.targets.size(); ++t) {
    const double w = weights[t];
    if (w == 0.0) continue;
    const std::string target = fmt::format("{} target {}", what, t);
    if (const auto it = tp.targets[t].find("POSITION"); it != tp.targets[t].end()) {
      const std::vector<glm::vec3> d = targetAttribute(ctx, target, it->second, "POSITION", vertices);
      for (size_t i = 0; i < prim.positions.size(); ++i)
        prim.positions[i] += static_cast<float>(w) * d[sourceOf(prim, i)];
    }
    if (const auto it = tp.targets[t].find("NORMAL"); it != tp.targets[t].end() && !prim.flat) {
      const std::vector<glm::vec3> d = targetAttribute(ctx, target, it->second, "NORMAL", vertices);
      for (size_t i = 0; i < prim.normals.size(); ++i) prim.normals[i] += static_cast<float>(w) * d[sourceOf(prim, i)];
    }
  }
}

// J_i IBM_i per joint of skin `s`.
std::vector<glm::dmat4> jointMatrices(const GltfContext& ctx, int s, const std::map<int, glm::dmat4>& worlds) {
  if (s < 0 || static_cast<size_t>(s) >= ctx.model.skins.size())
    failGltf(ctx, fmt::format("skin {} does not exist", s));
  const tinygltf::Skin& skin = ctx.model.skins[static_cast<size_t>(s)];
  if (skin.joints.empty()) failGltf(ctx, fmt::format("skin {}: no joints", s));
  std::vector<float> inverse;
  if (skin.inverseBindMatrices >= 0) {
    inverse = readFloats(ctx, skin.inverseBindMatrices, 16, false, "inverseBindMatrices");
    if (inverse.size() < 16 * skin.joints.size())
      failGltf(ctx, fmt::format("skin {}: {} inverse bind matrices for {} joints", s, inverse.size() / 16,
                                skin.joints.size()));
  }
  std::vector<glm::dmat4> out;
  for (size_t j = 0; j < skin.joints.size(); ++j) {
    const auto world = worlds.find(skin.joints[j]);
    if (world == worlds.end())
      failGltf(ctx, fmt::format("skin {}: joint {} (node {}) is not in the scene", s, j, skin.joints[j]));
    glm::dmat4 ibm(1.0);
    if (!inverse.empty())
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) ibm[c][r] = inverse[16 * j + 4 * static_cast<size_t>(c) + static_cast<size_t>(r)];
    out.push_back(world->second * ibm);
  }
  return out;
}

struct SkinSet {
  std::vector<glm::uvec4> joints;
  std::vector<float> weights;  // 4 per vertex
};

// The primitive's JOINTS_n / WEIGHTS_n pairs, checked against its vertices and the skin's joint count.
std::vector<SkinSet> readSkinSets(const GltfContext& ctx, const std::string& what, const tinygltf::Primitive& tp,
                                  size_t vertices, size_t jointCount) {
  std::vector<SkinSet> sets;
  for (int set = 0;; ++set) {
    const auto j = tp.attributes.find(fmt::format("JOINTS_{}", set));
    const auto w = tp.attributes.find(fmt::format("WEIGHTS_{}", set));
    if (j == tp.attributes.end() && w == tp.attributes.end()) break;
    if (j == tp.attributes.end() || w == tp.attributes.end())
      failGltf(ctx, fmt::format("{}: JOINTS_{} and WEIGHTS_{} must come together", what, set, set));
    SkinSet s{readJoints(ctx, j->second, "JOINTS"), readFloats(ctx, w->second, 4, true, "WEIGHTS")};
    if (s.joints.size() < vertices || s.weights.size() < 4 * vertices)
      failGltf(ctx,
               fmt::format("{}: JOINTS_{} / WEIGHTS_{} cover fewer than its {} vertices", what, set, set, vertices));
    for (size_t v = 0; v < vertices; ++v)
      for (int c = 0; c < 4; ++c) {
        const float wt = s.weights[4 * v + static_cast<size_t>(c)];
        if (!std::isfinite(wt) || wt < 0.0f)
          failGltf(ctx, fmt::format("{}: vertex {}: weight {} is negative or not finite", what, v, wt));
        if (wt != 0.0f && s.joints[v][c] >= jointCount)
          failGltf(ctx, fmt::format("{}: vertex {}: joint {} out of range (the skin has {})", what, v, s.joints[v][c],
                                    jointCount));
      }
    sets.push_back(std::move(s));
  }
  if (sets.empty()) failGltf(ctx, fmt::format("{}: skinned but has no JOINTS_0 and WEIGHTS_0", what));
  return sets;
}

void skinVertices(const GltfContext& ctx, const std::string& what, const tinygltf::Primitive& tp, int s,
                  const std::map<int, glm::dmat4>& worlds, LocalPrimitive& prim) {
  const std::vector<glm::dmat4> joints = jointMatrices(ctx, s, worlds);
  const std::vector<SkinSet> sets = readSkinSets(ctx, what, tp, accessorVertices(prim), joints.size());
  for (size_t i = 0; i < prim.positions.size(); ++i) {
    const size_t v = sourceOf(prim, i);
    glm::dmat4 m(0.0);
    double total = 0.0;
    for (const SkinSet& set : sets)
      for (int c = 0; c < 4; ++c) {
        const double wt = set.weights[4 * v + static_cast<size_t>(c)];
        if (wt != 0.0) m += wt * joints[set.joints[v][c]], total += wt;
      }
    // Sec. 3.7.3.3: a vertex's weights sum to one; a small departure is normalised away, a zero sum has no meaning.
    if (!(total > 0.0))
      failGltf(ctx, fmt::format("{}: vertex {}: its skin weights sum to 0 (they must sum to 1)", what, v));
    m /= total;
    prim.positions[i] = glm::vec3(m * glm::dvec4(glm::dvec3(prim.positions[i]), 1.0));
    if (!prim.flat) prim.normals[i] = glm::vec3(glm::inverseTranspose(glm::dmat3(m)) * glm::dvec3(prim.normals[i]));
  }
}

}  // namespace

std::vector<double> morphWeights(const GltfContext& ctx, int node, const NodePose& pose) {
  const tinygltf::Node& n = ctx.model.nodes[static_cast<size_t>(node)];
  if (n.mesh < 0 || static_cast<size_t>(n.mesh) >= ctx.model.meshes.size()) return {};
  const tinygltf::Mesh& mesh = ctx.model.meshes[static_cast<size_t>(n.mesh)];
  const size_t targets = mesh.primitives.empty() ? 0 : mesh.primitives.front().targets.size();
  for (size_t p = 0; p < mesh.primitives.size(); ++p)
    if (mesh.primitives[p].targets.size() != targets)
      failGltf(ctx, fmt::format("mesh {}: primitive {} has {} morph targets, primitive 0 has {}", n.mesh, p,
                                mesh.primitives[p].targets.size(), targets));
  const std::vector<double>& chosen = pose.weights ? *pose.weights : !n.weights.empty() ? n.weights : mesh.weights;
  if (chosen.empty()) return std::vector<double>(targets, 0.0);
  if (chosen.size() != targets)
    failGltf(ctx, fmt::format("node {}: {} morph weights for {} targets", node, chosen.size(), targets));
  for (double w : chosen)
    if (!std::isfinite(w)) failGltf(ctx, fmt::format("node {}: a morph weight is not finite", node));
  return chosen;
}

bool deforms(const GltfContext& ctx, int node, const std::vector<double>& weights) {
  return ctx.model.nodes[static_cast<size_t>(node)].skin >= 0 ||
         std::any_of(weights.begin(), weights.end(), [](double w) { return w != 0.0; });
}

bool deformPrimitive(const GltfContext& ctx, const NodeInstance& inst, int primitive,
                     const std::vector<double>& weights, const std::map<int, glm::dmat4>& worlds,
                     LocalPrimitive& prim) {
  const tinygltf::Node& node = ctx.model.nodes[static_cast<size_t>(inst.node)];
  const tinygltf::Primitive& tp =
      ctx.model.meshes[static_cast<size_t>(node.mesh)].primitives[static_cast<size_t>(primitive)];
  const std::string what = fmt::format("node {} mesh {} primitive {}", inst.node, node.mesh, primitive);
  morph(ctx, what, tp, weights, prim);
  if (node.skin >= 0) skinVertices(ctx, what, tp, node.skin, worlds, prim);
  if (prim.flat)  // the face normals of the moved triangles
    for (const glm::uvec3& t : prim.triangles) {
      const glm::vec3 n = faceNormal(prim.positions[t.x], prim.positions[t.y], prim.positions[t.z]);
      for (int k = 0; k < 3; ++k) prim.normals[t[k]] = n;
    }
  return node.skin >= 0;
}

}  // namespace penumbra::detail
