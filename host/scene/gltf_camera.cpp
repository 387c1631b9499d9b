// glTF camera import: pose from the node's world matrix (eye at its origin, target one unit-or-more down -Z, up
// its +Y), projection and clip planes from the camera object, and the image size from its aspect ratio.
#include "host/scene/gltf_camera.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "host/scene/limits.h"

namespace penumbra::detail {
namespace {

constexpr int kDefaultHeight = 720;  // the image height a file's aspect ratio is applied to

void sizeFromAspect(Camera& camera, double aspect) {
  if (!(aspect > 0.0) || !std::isfinite(aspect)) return;
  camera.height = kDefaultHeight;
  camera.width = static_cast<int>(std::lround(kDefaultHeight * aspect));
  if (camera.width > kMaxImageSide) {  // a very wide view: the widest image of that aspect instead
    camera.width = kMaxImageSide;
    camera.height = static_cast<int>(std::lround(kMaxImageSide / aspect));
  }
  camera.width = std::clamp(camera.width, 1, kMaxImageSide);
  camera.height = std::clamp(camera.height, 1, kMaxImageSide);
}

void setPose(const GltfContext& ctx, int node, const glm::dmat4& world, Camera& camera) {
  const glm::dvec3 eye(world[3]);
  const glm::dvec3 back(world[2]), up(world[1]);  // local +Z and +Y in world space
  const double backLen = glm::length(back), upLen = glm::length(up);
  if (!(backLen > 0.0 && upLen > 0.0) || !std::isfinite(backLen) || !std::isfinite(upLen) ||
      glm::length(glm::cross(back / backLen, up / upLen)) < 1e-6)
    failGltf(ctx, fmt::format("node {}: the camera's transform is degenerate (zero scale?)", node));
  // The target's distance keeps target - eye accurate in float far from the origin.
  const double reach = std::max(1.0, glm::length(eye));
  camera.eye = glm::vec3(eye);
  camera.target = glm::vec3(eye - back / backLen * reach);
  camera.up = glm::vec3(up / upLen);
}

Camera readCamera(const GltfContext& ctx, const NodeInstance& inst, int index) {
  const tinygltf::Node& node = ctx.model.nodes[static_cast<size_t>(inst.node)];
  const tinygltf::Camera& c = ctx.model.cameras[static_cast<size_t>(index)];
  Camera camera;
  setPose(ctx, inst.node, inst.world, camera);
  camera.name = !c.name.empty() ? c.name : !node.name.empty() ? node.name : fmt::format("camera {}", index);
  if (c.type == "orthographic") {
    camera.kind = ProjectionKind::kOrthographic;
    // Sec. 5.14: xmag and ymag SHOULD NOT be negative (a negative one mirrors the view); the view is drawn
    // unmirrored, with a warning, since a shadow's visibility does not depend on the image's orientation.
    if (c.orthographic.xmag < 0.0 || c.orthographic.ymag < 0.0)
      emitWarning(ctx.options, fmt::format("{}: camera {}: negative xmag or ymag ({}, {}): drawn unmirrored", ctx.file,
                                           index, c.orthographic.xmag, c.orthographic.ymag));
    camera.orthoHalfHeight = static_cast<float>(std::abs(c.orthographic.ymag));
    camera.clipNear = static_cast<float>(c.orthographic.znear);
    camera.clipFar = static_cast<float>(c.orthographic.zfar);
    sizeFromAspect(camera, std::abs(c.orthographic.xmag / c.orthographic.ymag));
  } else {
    camera.fovYDeg = static_cast<float>(glm::degrees(c.perspective.yfov));
    camera.clipNear = static_cast<float>(c.perspective.znear);
    camera.clipFar = c.perspective.zfar > 0.0 ? static_cast<float>(c.perspective.zfar) : INFINITY;  // 0: absent
    sizeFromAspect(camera, c.perspective.aspectRatio);  // 0: absent, the viewport's
  }
  if (!(camera.fovYDeg > 0.0f && camera.fovYDeg < 180.0f) || !(camera.orthoHalfHeight > 0.0f) ||
      !std::isfinite(camera.orthoHalfHeight) || !(camera.clipNear < camera.clipFar))
    failGltf(ctx, fmt::format("camera {}: out of range in single precision", index));
  return camera;
}

}  // namespace

std::vector<Camera> readGltfCameras(const GltfContext& ctx, const std::vector<NodeInstance>& instances) {
  std::vector<Camera> cameras;
  for (const NodeInstance& inst : instances) {
    const int index = ctx.model.nodes[static_cast<size_t>(inst.node)].camera;
    if (index < 0) continue;
    if (static_cast<size_t>(index) >= ctx.model.cameras.size())
      failGltf(ctx, fmt::format("node {}: camera {} does not exist", inst.node, index));
    cameras.push_back(readCamera(ctx, inst, index));
    cameras.back().gltfIndex = static_cast<int>(cameras.size() - 1);
  }
  return cameras;
}

}  // namespace penumbra::detail
