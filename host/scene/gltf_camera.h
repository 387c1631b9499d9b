// glTF cameras (glTF 2.0 sec. 3.10): every camera instance of the default scene as a Camera posed by its node's
// world transform (the lens looks down local -Z, +Y up), with its projection, clip planes and image size.
#pragma once

#include <vector>

#include "host/scene/camera.h"
#include "host/scene/gltf_nodes.h"

namespace penumbra::detail {

// One Camera per node with a `camera`, in `instances`' order (the default scene's depth-first order), gltfIndex
// 0, 1, ... and named by the camera's name, else the node's, else "camera N" (N its index in `cameras`).
// The node's scale moves nothing but the pose: the projection is the file's. Perspective: yfov, clip planes
// znear..zfar (zfar absent: no far clip); orthographic: ymag as the half height, znear..zfar. With aspectRatio
// (perspective) or xmag / ymag (orthographic) the image is 720 pixels high and round(720 * aspect) wide; else
// the default 1280x720 (the viewport's aspect is used, as glTF asks when aspectRatio is absent). Ranges were
// checked by checkGltfJson; throws SceneError for a degenerate (zero-scale) camera transform.
std::vector<Camera> readGltfCameras(const GltfContext& ctx, const std::vector<NodeInstance>& instances);

}  // namespace penumbra::detail
