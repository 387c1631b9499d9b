// The cube-face rule and the face G-buffer's pixels by definition, in double.
#include "tools/selftest/reference/cube_ref.h"

#include <cmath>
#include <limits>
#include <random>

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

std::vector<glm::vec3> adversarialDirections() {
  std::vector<glm::vec3> d;
  const float one = 1.0f, next = std::nextafter(1.0f, 2.0f), tiny = std::numeric_limits<float>::denorm_min();
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float values[] = {0.0f, -0.0f, one, -one, next, -next, 3.0f, tiny, -tiny, 1e38f, -1e38f, inf, -inf, nan};
  for (float x : values)
    for (float y : values)
      for (float z : values) d.push_back({x, y, z});
  return d;
}

std::vector<glm::vec3> randomDirections(size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  std::uniform_int_distribution<int> pick(0, 3);
  std::vector<glm::vec3> d;
  for (size_t i = 0; i < count; ++i) {
    glm::vec3 v(normal(rng), normal(rng), normal(rng));
    // Every few, two or three components of equal magnitude (a direction on a face edge or corner).
    const int tie = pick(rng);
    if (tie == 1) v.y = std::copysign(v.x, v.y);
    if (tie == 2) v.z = std::copysign(v.y, v.z), v.x = std::copysign(v.y, v.x);
    d.push_back(v * std::exp2(static_cast<float>(static_cast<int>(i % 41) - 20)));  // magnitudes 2^-20 .. 2^20
  }
  return d;
}

std::vector<cl_float4> positionsAround(const glm::vec3& light, const std::vector<glm::vec3>& directions) {
  std::vector<cl_float4> p;
  for (size_t i = 0; i < directions.size(); ++i) {
    const glm::vec3 q = light + directions[i];
    p.push_back({{q.x, q.y, q.z, i % 7 == 3 ? 0.0f : 1.0f}});
  }
  return p;
}

}  // namespace penumbra::ref
