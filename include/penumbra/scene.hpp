// penumbra's C++ API: scenes (pn_scene) and the camera and light values (pn_camera, pn_light) with C++ members.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "penumbra/error.hpp"
#include "penumbra/scene.h"

/// @file
/// penumbra::Scene, penumbra::Camera, penumbra::Light.

namespace penumbra {
inline namespace v0 {

/// A camera, Y up, right-handed (pn_camera); the defaults are pn_camera_init()'s.
struct Camera {
  std::array<float, 3> eye;     ///< Position.
  std::array<float, 3> target;  ///< The point it looks at.
  std::array<float, 3> up;      ///< The preferred up direction.
  bool orthographic;            ///< false: perspective (fovYDeg); true: orthographic (orthoHalfHeight).
  float fovYDeg;                ///< Perspective: vertical field of view, degrees.
  float orthoHalfHeight;        ///< Orthographic: half the view's height, world units.
  float clipNear;               ///< View-space near clip distance (0: none).
  float clipFar;                ///< View-space far clip distance (INFINITY: none).
  int width;                    ///< Image width, pixels.
  int height;                   ///< Image height, pixels.

  /// pn_camera_init()'s camera.
  Camera() : Camera(initial()) {}
  /// The C value as C++.
  explicit Camera(const pn_camera& c)
      : eye{c.eye[0], c.eye[1], c.eye[2]},
        target{c.target[0], c.target[1], c.target[2]},
        up{c.up[0], c.up[1], c.up[2]},
        orthographic(c.orthographic != 0),
        fovYDeg(c.fov_y_deg),
        orthoHalfHeight(c.ortho_half_height),
        clipNear(c.clip_near),
        clipFar(c.clip_far),
        width(c.width),
        height(c.height) {}
  /// "EX,EY,EZ:TX,TY,TZ[:FOVY_DEG]", the CLI's --camera.
  static Camera parse(const std::string& spec) {
    pn_camera c;
    pn_camera_init(&c);  // its size; the call fills the rest
    detail::check(pn_camera_parse(spec.c_str(), &c));
    return Camera(c);
  }
  /// As the C API takes it.
  pn_camera toC() const {
    pn_camera c;
    pn_camera_init(&c);  // its size, and the defaults of fields set below
    for (int i = 0; i < 3; ++i) c.eye[i] = eye[i], c.target[i] = target[i], c.up[i] = up[i];
    c.orthographic = orthographic ? 1 : 0;
    c.fov_y_deg = fovYDeg, c.ortho_half_height = orthoHalfHeight;
    c.clip_near = clipNear, c.clip_far = clipFar;
    c.width = width, c.height = height;
    return c;
  }

 private:
  static pn_camera initial() {
    pn_camera c;
    pn_camera_init(&c);
    return c;
  }
};

/// The type of a light.
enum class LightType { Spot = PN_LIGHT_SPOT, Directional = PN_LIGHT_DIRECTIONAL, Point = PN_LIGHT_POINT };

/// A light (pn_light); the defaults are pn_light_init()'s.
struct Light {
  LightType type;                  ///< Spot, directional or point.
  std::string name;                ///< "" for an unnamed light (EXR layer "light").
  std::array<float, 3> position;   ///< Spot and point: position.
  std::array<float, 3> target;     ///< Spot: the point it aims at.
  float fovDeg;                    ///< Spot: full cone angle, degrees.
  float radius;                    ///< Spot: disk radius; point: sphere radius; 0: a point source.
  float innerFovDeg;               ///< Spot: fully lit inner cone (glTF), degrees; negative: none.
  float range;                     ///< glTF range (the preview fades out towards it); 0: unlimited.
  std::array<float, 3> direction;  ///< Directional: the direction the light travels.
  float angularRadiusDeg;          ///< Directional: sun disk angular radius, degrees.

  /// pn_light_init()'s light.
  Light() : Light(initial()) {}
  /// The C value as C++ (its name copied).
  explicit Light(const pn_light& l)
      : type(static_cast<LightType>(l.type)),
        name(l.name != nullptr ? l.name : ""),
        position{l.position[0], l.position[1], l.position[2]},
        target{l.target[0], l.target[1], l.target[2]},
        fovDeg(l.fov_deg),
        radius(l.radius),
        innerFovDeg(l.inner_fov_deg),
        range(l.range),
        direction{l.direction[0], l.direction[1], l.direction[2]},
        angularRadiusDeg(l.angular_radius_deg) {}
  /// "spot:P:T:FOV[:RADIUS]", "dir:D[:ANGLE]" or "point:P[:RADIUS]", the CLI's --light.
  static Light parse(const std::string& spec) {
    pn_light l;
    pn_light_init(&l);  // its size; the call fills the rest
    detail::check(pn_light_parse(spec.c_str(), &l));
    return Light(l);
  }
  /// As the C API takes it; its name points into this Light.
  pn_light toC() const {
    pn_light l;
    pn_light_init(&l);  // its size, and the defaults of fields set below
    l.type = static_cast<pn_light_type>(type);
    l.name = name.c_str();
    for (int i = 0; i < 3; ++i) l.position[i] = position[i], l.target[i] = target[i], l.direction[i] = direction[i];
    l.fov_deg = fovDeg, l.radius = radius, l.inner_fov_deg = innerFovDeg, l.range = range;
    l.angular_radius_deg = angularRadiusDeg;
    return l;
  }

 private:
  static pn_light initial() {
    pn_light l;
    pn_light_init(&l);
    return l;
  }
};

/// How a scene is loaded.
struct LoadOptions {
  std::optional<double> time;  ///< glTF animations evaluated at this time, seconds; none: the static pose.
  std::string animation;       ///< With time: the one animation to play (index or name); "": all.
};

/// A loaded scene (pn_scene): immutable; copies share it.
class Scene {
 public:
  /// Loads "builtin:NAME[:key=value,...]", a .json scene file or a .gltf/.glb model.
  explicit Scene(const std::string& spec, const LoadOptions& options = {}) {
    pn_scene_load_options o;
    pn_scene_load_options_init(&o);
    o.has_time = options.time.has_value() ? 1 : 0;
    o.time = options.time.value_or(0.0);
    o.animation = options.animation.c_str();
    pn_scene* scene = nullptr;
    detail::check(pn_scene_load(spec.c_str(), &o, &scene));
    handle_ = Handle(scene);
  }

  /// The caller's own triangles (pn_mesh: arrays read during the call only) and lights; no cameras.
  static Scene fromMeshes(const std::vector<pn_mesh>& meshes, const std::vector<Light>& lights = {}) {
    std::vector<pn_light> c;
    for (const Light& l : lights) c.push_back(l.toC());
    pn_scene* scene = nullptr;
    detail::check(pn_scene_create(meshes.data(), meshes.size(), c.data(), c.size(), &scene));
    Scene created;
    created.handle_ = Handle(scene);
    return created;
  }

  /// Triangles after instancing.
  size_t triangleCount() const { return pn_scene_triangle_count(get()); }
  /// The geometry's bounding box, min then max.
  std::pair<std::array<float, 3>, std::array<float, 3>> bounds() const {
    std::array<float, 3> lo{}, hi{};
    detail::check(pn_scene_bounds(get(), lo.data(), hi.data()));
    return {lo, hi};
  }
  /// The cameras the scene names.
  std::vector<Camera> cameras() const {
    std::vector<Camera> out;
    for (size_t i = 0; i < pn_scene_camera_count(get()); ++i) {
      pn_camera c;
      pn_camera_init(&c);  // its size; the call fills the rest
      detail::check(pn_scene_camera(get(), i, &c));
      out.emplace_back(c);
    }
    return out;
  }
  /// The camera a frame uses by default: the scene's first, else a framing view.
  Camera defaultCamera() const {
    pn_camera c;
    pn_camera_init(&c);  // its size; the call fills the rest
    detail::check(pn_scene_default_camera(get(), &c));
    return Camera(c);
  }
  /// The lights the scene names.
  std::vector<Light> lights() const {
    std::vector<Light> out;
    for (size_t i = 0; i < pn_scene_light_count(get()); ++i) {
      pn_light l;
      pn_light_init(&l);  // its size; the call fills the rest
      detail::check(pn_scene_light(get(), i, &l));
      out.emplace_back(l);
    }
    return out;
  }
  /// The light a frame uses when the scene has none.
  Light framingLight() const {
    pn_light l;
    pn_light_init(&l);  // its size; the call fills the rest
    detail::check(pn_scene_framing_light(get(), &l));
    return Light(l);
  }
  /// The C handle (not retained for the caller).
  pn_scene* get() const noexcept { return handle_.get(); }

 private:
  Scene() = default;
  using Handle = detail::Handle<pn_scene, pn_scene_retain, pn_scene_release>;
  Handle handle_;
};

}  // namespace v0
}  // namespace penumbra
