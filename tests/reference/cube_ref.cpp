// The cube-face rule and the face G-buffer's pixels by definition, in double.
#include "tests/reference/cube_ref.h"

#include <cmath>

namespace penumbra::ref {

int cubeFace(double x, double y, double z) {
  if (std::isnan(x) || std::isnan(y) || std::isnan(z)) return 0;
  const double c[3] = {x, y, z};
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (std::fabs(c[k]) > std::fabs(c[axis])) axis = k;  // strictly larger: a tie keeps the earlier axis
  return 2 * axis + (c[axis] < 0.0 ? 1 : 0);
}

std::vector<int32_t> cubeClassify(const std::vector<cl_float4>& position, const glm::vec3& light) {
  std::vector<int32_t> faces(position.size());
  for (size_t i = 0; i < position.size(); ++i) {
    const cl_float4& p = position[i];
    const float dx = p.s[0] - light.x, dy = p.s[1] - light.y, dz = p.s[2] - light.z;
    faces[i] = p.s[3] == 0.0f ? -1 : cubeFace(dx, dy, dz);
  }
  return faces;
}

std::vector<bool> cubeKept(const std::vector<cl_float4>& position, const std::vector<int32_t>& faces, int width,
                           int height, const glm::vec3& light, int face, double tangent) {
  // The face's frame: forward, right and up as (axis, sign), from the face's look-at (up +Y, +Z for the +-Y faces).
  const int forwardAxis = face / 2;
  const double forwardSign = face % 2 == 0 ? 1.0 : -1.0;
  glm::dvec3 forward(0.0), up(0.0);
  forward[forwardAxis] = forwardSign;
  up[forwardAxis == 1 ? 2 : 1] = 1.0;
  const glm::dvec3 right = glm::cross(forward, up);
  std::vector<bool> kept(position.size(), false);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t i = static_cast<size_t>(y) * width + x;
      if (faces[i] == face) {
        kept[i] = true;
        continue;
      }
      const cl_float4& p = position[i];
      if (p.s[3] == 0.0f) continue;
      const glm::dvec3 d(p.s[0] - light.x, p.s[1] - light.y, p.s[2] - light.z);
      const double w = glm::dot(d, forward);
      if (!(w > 0.0 && std::fabs(glm::dot(d, right)) <= tangent * w && std::fabs(glm::dot(d, up)) <= tangent * w))
        continue;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx >= 0 && yy >= 0 && xx < width && yy < height && faces[static_cast<size_t>(yy) * width + xx] == face)
            kept[i] = true;
        }
    }
  return kept;
}

}  // namespace penumbra::ref
