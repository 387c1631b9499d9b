// Orbits and keyframed cameras, evaluated in double precision and printed with 9 significant digits so that a
// plan is the same on every machine.
#include "tools/cli/camera_path.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "host/scene/camera.h"

namespace penumbra::cli {
namespace {

using nlohmann::json;
using Vec3 = std::array<double, 3>;

double number(const json& object, const char* key, const char* path, std::optional<double> fallback = {}) {
  if (!object.contains(key)) {
    if (fallback) return *fallback;
    throw std::invalid_argument(fmt::format("camera {}: no \"{}\"", path, key));
  }
  if (!object[key].is_number())
    throw std::invalid_argument(fmt::format("camera {}: \"{}\" is not a number", path, key));
  return object[key].get<double>();
}

Vec3 vec3(const json& object, const char* key, const char* path) {
  const json& v = object.contains(key) ? object[key] : json();
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    throw std::invalid_argument(fmt::format("camera {}: \"{}\" is not [x, y, z]", path, key));
  return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

std::string spec(const Vec3& eye, const Vec3& target, double fov) {
  return fmt::format("{:.9g},{:.9g},{:.9g}:{:.9g},{:.9g},{:.9g}:{:.9g}", eye[0], eye[1], eye[2], target[0], target[1],
                     target[2], fov);
}

std::string orbit(const json& o, long long frame, long long count) {
  if (!o.is_object()) throw std::invalid_argument("camera orbit: not an object");
  const Vec3 target = vec3(o, "target", "orbit");
  const double radius = number(o, "radius", "orbit"), height = number(o, "height", "orbit", 0.0);
  const double fov = number(o, "fov", "orbit", 45.0);
  double from = 0, to = 360;
  if (o.contains("degrees")) {
    const json& d = o["degrees"];
    if (!d.is_array() || d.size() != 2 || !d[0].is_number() || !d[1].is_number())
      throw std::invalid_argument("camera orbit: \"degrees\" is not [from, to]");
    from = d[0].get<double>(), to = d[1].get<double>();
  }
  const double angle = (from + (to - from) * static_cast<double>(frame) / static_cast<double>(count)) * M_PI / 180.0;
  const Vec3 eye{target[0] + radius * std::sin(angle), target[1] + height, target[2] + radius * std::cos(angle)};
  return spec(eye, target, fov);
}

std::string keyframes(const json& keys, long long frame) {
  if (!keys.is_array() || keys.empty()) throw std::invalid_argument("camera keyframes: not a non-empty array");
  size_t next = 0;
  for (size_t i = 0; i < keys.size(); ++i) {
    if (!keys[i].is_object() || !keys[i].contains("frame") || !keys[i]["frame"].is_number_integer())
      throw std::invalid_argument(fmt::format("camera keyframes: key {} has no integer \"frame\"", i));
    if (i > 0 && keys[i]["frame"].get<long long>() <= keys[i - 1]["frame"].get<long long>())
      throw std::invalid_argument(fmt::format("camera keyframes: key {}'s frame is not after key {}'s", i, i - 1));
    if (keys[i]["frame"].get<long long>() <= frame) next = i + 1;
  }
  const json& a = keys[next == 0 ? 0 : next - 1];
  const json& b = keys[std::min(next, keys.size() - 1)];
  const double fa = a["frame"].get<double>(), fb = b["frame"].get<double>();
  const double t = fb > fa ? std::clamp((static_cast<double>(frame) - fa) / (fb - fa), 0.0, 1.0) : 0.0;
  const auto mix = [t](double x, double y) { return x + (y - x) * t; };
  const Vec3 ea = vec3(a, "eye", "keyframes"), eb = vec3(b, "eye", "keyframes");
  const Vec3 ta = vec3(a, "target", "keyframes"), tb = vec3(b, "target", "keyframes");
  const Vec3 eye{mix(ea[0], eb[0]), mix(ea[1], eb[1]), mix(ea[2], eb[2])};
  const Vec3 target{mix(ta[0], tb[0]), mix(ta[1], tb[1]), mix(ta[2], tb[2])};
  return spec(eye, target, mix(number(a, "fov", "keyframes", 45.0), number(b, "fov", "keyframes", 45.0)));
}

}  // namespace

std::string cameraOnPath(const json& path, long long frame, long long frameCount) {
  std::string camera;
  if (path.is_object() && path.size() == 1 && path.contains("orbit"))
    camera = orbit(path["orbit"], frame, frameCount);
  else if (path.is_object() && path.size() == 1 && path.contains("keyframes"))
    camera = keyframes(path["keyframes"], frame);
  else
    throw std::invalid_argument("camera: a path is {\"orbit\": {...}} or {\"keyframes\": [...]}");
  // The camera as `run` will parse it: a plan never writes a job that `run` refuses (an orbit of radius 1e300).
  try {
    parseCamera(camera);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("camera path, frame {}: {}", frame, e.what()));
  }
  return camera;
}

}  // namespace penumbra::cli
