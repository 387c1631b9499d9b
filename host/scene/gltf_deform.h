// Morph targets (glTF 2.0 sec. 3.7.2.2) and skins (sec. 3.7.3) applied to one instance of a mesh primitive, on the
// CPU at load time, with the node poses of gltf_animation.h.
#pragma once

#include <map>
#include <vector>

#include "host/scene/gltf_animation.h"
#include "host/scene/gltf_mesh.h"
#include "host/scene/gltf_nodes.h"

namespace penumbra::detail {

// The morph weights of node `node` (one per morph target of its mesh): the animated ones, else the node's, else the
// mesh's, else zeros. Throws SceneError when a weights array does not match the mesh's target count.
std::vector<double> morphWeights(const GltfContext& ctx, int node, const NodePose& pose);

// Whether an instance of node `node` with `weights` differs from the primitive as read: a non-zero weight or a skin.
bool deforms(const GltfContext& ctx, int node, const std::vector<double>& weights);

// Primitive `primitive` of node inst.node's mesh (`prim`, as readPrimitive read it) with its morph targets added by
// `weights` (positions and normals; tangents play no part in shadows), then, when the node has a skin, skinned:
// v' = sum_i w_i J_i IBM_i v over the JOINTS_n / WEIGHTS_n sets, J_i the joint's world matrix (`worlds`, every
// flattened node's) and IBM_i its inverse bind matrix; normals by the inverse transpose of the blended matrix.
// A skinned primitive lies in world space and its node's own matrix no longer applies (sec. 3.7.3.3): returns true
// then. Weights are normalised per vertex; a vertex whose weights sum to 0 keeps the node's world matrix. Throws
// SceneError for targets or skin data that do not match the primitive (counts, joint indices, accessor types) and for
// joints outside the scene.
bool deformPrimitive(const GltfContext& ctx, const NodeInstance& inst, int primitive,
                     const std::vector<double>& weights, const std::map<int, glm::dmat4>& worlds, LocalPrimitive& prim);

}  // namespace penumbra::detail
