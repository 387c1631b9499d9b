// The glTF node hierarchy: checked to be a forest (every child in range, at most one parent, no cycles)
// before any traversal, then flattened iteratively into world matrices.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "host/scene/gltf_accessor.h"
#include "host/scene/gltf_animation.h"

namespace penumbra::detail {

struct NodeInstance {
  int node;
  glm::dmat4 world;  // glTF world space: parent chain applied, never recentred
};

// Every node reachable from the default scene (or scene 0, or all root nodes when there is no scene),
// depth first, with its world matrix; a node's animated translation, rotation or scale in `poses` (one per node,
// evaluateAnimations) replaces its own. Throws SceneError for cycles, nodes with two parents, scene roots that are
// not roots, malformed or non-finite matrices/TRS, and non-affine matrices.
std::vector<NodeInstance> flattenNodes(const GltfContext& ctx, const std::vector<NodePose>& poses);

}  // namespace penumbra::detail
