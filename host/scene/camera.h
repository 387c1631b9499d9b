// The pinhole camera (Y up, right-handed, looking from eye to target) and its command-line form.
#pragma once

#include <string>
#include <string_view>

#include <glm/glm.hpp>

namespace penumbra {

struct Camera {
  glm::vec3 eye{0, 1, 5};
  glm::vec3 target{0, 0, 0};
  glm::vec3 up{0, 1, 0};
  float fovYDeg = 45.0f;  // vertical field of view
  int width = 1280, height = 720;

  float aspect() const { return static_cast<float>(width) / static_cast<float>(height); }
  // world -> camera (glm::lookAt, with `up` replaced by chooseUp()); throws std::invalid_argument when
  // eye == target.
  glm::mat4 view() const;
  // OpenGL-style clip space, depth in [-1, 1]; throws std::invalid_argument unless 0 < zNear < zFar,
  // fovYDeg in (0, 180) and the size positive.
  glm::mat4 projection(float zNear, float zFar) const;
  std::string describe() const;  // the command-line form "EX,EY,EZ:TX,TY,TZ:FOVY_DEG", for provenance
};

// An up vector for glm::lookAt along `forward`: `preferred` normalised, or +Z (then +X) when `preferred` is
// (anti)parallel to `forward`, so a camera or light looking straight down never degenerates.
glm::vec3 chooseUp(const glm::vec3& forward, const glm::vec3& preferred = glm::vec3(0, 1, 0));

// "EX,EY,EZ:TX,TY,TZ[:FOVY_DEG]" (size is set separately by --size WxH). Throws std::invalid_argument with a
// message naming the bad part: non-finite numbers, eye == target, fov outside (0, 180).
Camera parseCamera(std::string_view spec);
// "WxH", each 1..16384. Throws std::invalid_argument.
void parseSize(std::string_view spec, int& width, int& height);

}  // namespace penumbra
