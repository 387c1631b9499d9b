// glTF animations (glTF 2.0 sec. 3.11) evaluated at one time: per node, the translation, rotation, scale and morph
// weights the animations give it, which replace the node's own when its world matrix is built (gltf_nodes.h) and
// when its mesh is morphed (gltf_deform.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "host/scene/gltf_accessor.h"

namespace penumbra::detail {

struct NodePose {
  std::optional<glm::dvec3> translation, scale;
  std::optional<glm::dquat> rotation;          // unit length
  std::optional<std::vector<double>> weights;  // one per morph target of the node's mesh
};

// One pose per node of the model (every entry empty without options.time): the channels of the animations that
// options.animation selects (empty: every animation, in file order; a later channel on the same node and property
// replaces an earlier one), sampled at options.time seconds, clamped to each sampler's first and last key. STEP,
// LINEAR (slerp for rotations) and CUBICSPLINE (Hermite, sec. 3.11 appendix C) interpolation. Throws SceneError for
// malformed samplers (times not finite and non-decreasing, output counts that do not match), unknown selections and
// channels that name missing nodes or samplers; warns and skips channels of unsupported paths (KHR_animation_pointer).
std::vector<NodePose> evaluateAnimations(const GltfContext& ctx);

}  // namespace penumbra::detail
