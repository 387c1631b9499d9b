// The camera (Y up, right-handed, looking from eye to target): a pinhole or an orthographic projection, with the
// near/far planes a glTF file may give, and its command-line form.
#pragma once

#include <cmath>
#include <string>
#include <string_view>

#include <glm/glm.hpp>

namespace penumbra {

enum class ProjectionKind { kPerspective, kOrthographic };

struct Camera {
  glm::vec3 eye{0, 1, 5};
  glm::vec3 target{0, 0, 0};
  glm::vec3 up{0, 1, 0};
  ProjectionKind kind = ProjectionKind::kPerspective;
  float fovYDeg = 45.0f;         // perspective: vertical field of view
  float orthoHalfHeight = 1.0f;  // orthographic: half the view's height in world units (glTF ymag); the half width
                                 // is orthoHalfHeight * aspect(), so pixels stay square whatever the size
  // Depth range the file asks for (glTF znear/zfar, view-space distances): the view is clipped to it, inside the
  // range fitted to the scene. 0 / infinity: no clipping beyond the fit.
  float clipNear = 0.0f, clipFar = INFINITY;
  int width = 1280, height = 720;
  // glTF cameras: the camera's name, else its node's, else "camera N"; gltfIndex is its position among the
  // scene's glTF cameras (what --camera gltf:INDEX selects). -1 and empty for every other camera.
  std::string name;
  int gltfIndex = -1;

  bool orthographic() const { return kind == ProjectionKind::kOrthographic; }
  float aspect() const { return static_cast<float>(width) / static_cast<float>(height); }
  glm::vec3 forward() const { return glm::normalize(target - eye); }
  // Half the view's width and height at view depth d (-z_eye): tan(fov/2) d for a pinhole, constant for ortho.
  glm::vec2 halfExtentAt(float depth) const;
  // world -> camera (glm::lookAt, with `up` replaced by chooseUp()); throws std::invalid_argument when
  // eye == target.
  glm::mat4 view() const;
  // OpenGL-style clip space, depth in [-1, 1] (glm::perspective or glm::ortho); throws std::invalid_argument
  // unless 0 < zNear < zFar (0 <= zNear for ortho), fovYDeg in (0, 180) or orthoHalfHeight > 0, and the size
  // positive.
  glm::mat4 projection(float zNear, float zFar) const;
  // The command-line form "EX,EY,EZ:TX,TY,TZ:FOVY_DEG" for a perspective camera, with ":ortho=HALF_HEIGHT" in
  // place of the fov for an orthographic one and ":up=..", ":near=..", ":far=.." where they differ from the
  // defaults, for provenance.
  std::string describe() const;
  // "gltf:0 \"Main\" (perspective)" for a glTF camera, "" for any other.
  std::string label() const;
};

// An up vector for glm::lookAt along `forward`: `preferred` normalised, or +Z (then +X) when `preferred` is
// (anti)parallel to `forward`, so a camera or light looking straight down never degenerates.
glm::vec3 chooseUp(const glm::vec3& forward, const glm::vec3& preferred = glm::vec3(0, 1, 0));

// "EX,EY,EZ:TX,TY,TZ[:FOVY_DEG]" (size is set separately by --size WxH). Throws std::invalid_argument with a
// message naming the bad part: non-finite numbers, eye == target, fov outside (0, 180).
Camera parseCamera(std::string_view spec);
// "WxH", each 1..kMaxImageSide (host/scene/limits.h). Throws std::invalid_argument.
void parseSize(std::string_view spec, int& width, int& height);

}  // namespace penumbra
