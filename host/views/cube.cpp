// Cube faces of a point light: the face rule and frames of kernels/shared/cube.h on the host, the face spot lights
// and the typed wrappers of kernels/cube.cl.
#include "host/views/cube.h"

#include <cmath>
#include <stdexcept>

#include "host/cl/kernel.h"

namespace penumbra {
namespace {

constexpr size_t kCubeGroup = 64;

glm::vec3 unitAxis(int axis, float sign) {
  glm::vec3 v(0.0f);
  v[axis] = sign;
  return v;
}

void checkFace(int face) {
  if (face < 0 || face >= CUBE_FACES) throw std::out_of_range("cube face " + std::to_string(face));
}

cl_float4 point4(const glm::vec3& p) { return {{p.x, p.y, p.z, 1.0f}}; }

}  // namespace

int cubeFaceOf(const glm::vec3& d) { return cube_face(d.x, d.y, d.z); }

std::string cubeFaceName(int face) {
  checkFace(face);
  return std::string(face % 2 == 0 ? "+" : "-") + "XYZ"[face / 2];
}

glm::vec3 cubeForward(int face) {
  checkFace(face);
  return unitAxis(cube_forward_axis(face), cube_forward_sign(face));
}

glm::vec3 cubeUp(int face) {
  checkFace(face);
  return unitAxis(cube_up_axis(face), 1.0f);
}

glm::vec3 cubeRight(int face) {
  checkFace(face);
  return unitAxis(cube_right_axis(face), cube_right_sign(face));
}

Light cubeFaceLight(const Light& point, int face, float tangent) {
  if (point.type != LightType::Point) throw std::invalid_argument("cubeFaceLight: not a point light");
  if (!(tangent >= 1.0f && std::isfinite(tangent)))
    throw std::invalid_argument("cubeFaceLight: window tangent below 1");
  Light spot;
  spot.type = LightType::Spot;
  spot.name = point.name;
  spot.position = point.position;
  // A target farther than every coordinate of the position, so that target - position is a non-zero multiple of the
  // axis in float (its other components exactly 0) and the spot's light eye is the face's frame exactly.
  const glm::vec3 p = glm::abs(point.position);
  spot.target = point.position + cubeForward(face) * (1.0f + p.x + p.y + p.z);
  spot.fovDeg = static_cast<float>(2.0 * glm::degrees(std::atan(static_cast<double>(tangent))));
  spot.radius = point.radius;
  spot.range = point.range;
  return spot;
}

void classifyCubeFaces(Context& ctx, const GBuffer& gbuffer, const glm::vec3& light, Buffer<int32_t>& faces) {
  const size_t count = static_cast<size_t>(gbuffer.width) * static_cast<size_t>(gbuffer.height);
  faces.allocate(ctx, count);
  Kernel kernel(ctx, "kernels/cube.cl", "cube_classify", "cube");
  kernel.args(gbuffer.position, static_cast<uint32_t>(count), point4(light), faces)
      .moves(count * (sizeof(cl_float4) + sizeof(int32_t)))  // read each position, write its face
      .launch(count, kCubeGroup);
}

void maskCubeFace(Context& ctx, const GBuffer& camera, const Buffer<int32_t>& faces, const glm::vec3& light, int face,
                  float tangent, GBuffer& out) {
  checkFace(face);
  const size_t count = static_cast<size_t>(camera.width) * static_cast<size_t>(camera.height);
  if (faces.size() != count) throw std::invalid_argument("maskCubeFace: faces do not match the G-buffer");
  out.width = camera.width, out.height = camera.height;
  out.normal = camera.normal, out.triangleId = camera.triangleId, out.objectId = camera.objectId;
  out.position.allocate(ctx, count);
  out.depth.allocate(ctx, count);
  Kernel kernel(ctx, "kernels/cube.cl", "cube_mask", "cube");
  kernel
      .args(camera.position, camera.depth, faces, static_cast<uint32_t>(camera.width),
            static_cast<uint32_t>(camera.height), point4(light), face, tangent, out.position, out.depth)
      // read position, depth and the face, write position and depth (the 3x3 faces come from cache)
      .moves(count * 2 * (sizeof(cl_float4) + sizeof(float)) + count * sizeof(int32_t))
      .launch(count, kCubeGroup);
}

void selectCubeFace(Context& ctx, const Buffer<int32_t>& faces, const Buffer<float>& faceVisibility, int face,
                    Buffer<float>& visibility) {
  checkFace(face);
  const size_t count = faces.size();
  if (faceVisibility.size() != count || visibility.size() != count)
    throw std::invalid_argument("selectCubeFace: buffer sizes differ");
  Kernel kernel(ctx, "kernels/cube.cl", "cube_select", "cube");
  kernel.args(faces, faceVisibility, static_cast<uint32_t>(count), face, visibility)
      .moves(count * (sizeof(int32_t) + 2 * sizeof(float)))  // bound: read face and face visibility, write visibility
      .launch(count, kCubeGroup);
}

}  // namespace penumbra
