// The built-in scenes. Each is built in world units (metres) on a ground at y = 0 with the light above,
// and picks a camera that shows the shadow it exists for; `cards` carries its own alpha texture (no file needed).
// Parameters are checked against a table, so the help text, ranges and defaults live in one place.
#include "host/scene/procedural.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "host/scene/procedural_mesh.h"
#include "host/scene/spec_parse.h"

namespace penumbra {
namespace {

using detail::addBox;
using detail::addHorizontalQuad;
using detail::addObject;

struct Args {
  const ProceduralInfo& info;
  const ProceduralParams& given;
  double operator()(std::string_view key) const {
    if (auto it = given.find(key); it != given.end()) return it->second;
    for (const ProceduralParam& p : info.params)
      if (p.name == key) return p.defaultValue;
    return 0.0;  // unreachable: builders only ask for their own parameters
  }
};

Camera camera(glm::vec3 eye, glm::vec3 target, float fovY = 45.0f) {
  Camera c;
  c.eye = eye, c.target = target, c.fovYDeg = fovY;
  return c;
}

Light spot(glm::vec3 position, glm::vec3 target, float fovDeg, float radius) {
  Light l;
  l.type = LightType::Spot, l.position = position, l.target = target, l.fovDeg = fovDeg, l.radius = radius;
  return l;
}

Light sun(glm::vec3 direction, float angularRadiusDeg) {
  Light l;
  l.type = LightType::Directional, l.direction = glm::normalize(direction), l.angularRadiusDeg = angularRadiusDeg;
  return l;
}

void ground(Scene& s, float halfX, float z0, float z1) {
  addHorizontalQuad(s, addObject(s, "ground"), -halfX, halfX, z0, z1, 0.0f);
}

Scene box(const Args& a) {
  Scene s;
  const auto size = static_cast<float>(a("size")), half = static_cast<float>(a("ground")) / 2;
  ground(s, half, -half, half);
  addBox(s, addObject(s, "box"), {-size / 2, 0, -size / 2}, {size / 2, size, size / 2});
  s.cameras.push_back(camera(glm::vec3(3, 2.5f, 4) * size, {0, 0.3f * size, 0}));
  s.lights.push_back(spot(glm::vec3(-2, 5, -1) * size, {0, 0, 0}, 60, 0.25f * size));
  return s;
}

Scene stackedPlanes(const Args& a) {
  Scene s;
  const auto gap = static_cast<float>(a("gap"));
  ground(s, 5, -5, 5);
  addHorizontalQuad(s, addObject(s, "plane-mid"), -1.5f, 1.5f, -1.5f, 1.5f, gap);
  addHorizontalQuad(s, addObject(s, "plane-high"), -0.5f, 0.5f, -0.5f, 0.5f, 2 * gap);
  s.cameras.push_back(camera({5, 2 + 2 * gap, 6}, {0, 0.5f * gap, 0}));
  s.lights.push_back(spot({0.3f, 2 * gap + 4, 0.2f}, {0, 0, 0}, 90, 0.3f));
  return s;
}

Scene poles(const Args& a) {
  Scene s;
  const int rows = static_cast<int>(a("rows")), columns = static_cast<int>(a("columns"));
  const auto spacing = static_cast<float>(a("spacing")), height = static_cast<float>(a("height"));
  const auto t = static_cast<float>(a("thickness")) / 2;
  const float halfX = 0.5f * static_cast<float>(columns) * spacing + 2;
  ground(s, halfX, -static_cast<float>(rows) * spacing - 5, 5);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c) {
      const float x = (static_cast<float>(c) - 0.5f * static_cast<float>(columns - 1)) * spacing;
      const float z = -static_cast<float>(r) * spacing;
      addBox(s, addObject(s, fmt::format("pole-{}-{}", r, c)), {x - t, 0, z - t}, {x + t, height, z + t});
    }
  s.cameras.push_back(camera({1, 1.7f, 4}, {0, 0.8f, -10}, 50));
  s.lights.push_back(sun({0.6f, -1, -0.3f}, 1.0f));
  return s;
}

Scene staircase(const Args& a) {
  Scene s;
  const int steps = static_cast<int>(a("steps"));
  const auto rise = static_cast<float>(a("rise")), run = static_cast<float>(a("run"));
  const auto halfW = static_cast<float>(a("width")) / 2;
  const float x0 = -0.5f * static_cast<float>(steps) * run, top = static_cast<float>(steps) * rise;
  ground(s, 4 - x0, x0 - 4, 4 - x0);
  for (int i = 0; i < steps; ++i) {
    const float x = x0 + static_cast<float>(i) * run;
    addBox(s, addObject(s, fmt::format("step-{}", i)), {x, 0, -halfW},
           {x + run, static_cast<float>(i + 1) * rise, halfW});
  }
  const float plateY = top + static_cast<float>(a("plate_gap"));
  addHorizontalQuad(s, addObject(s, "plate"), 0.3f * x0, -0.3f * x0, -0.4f * halfW, 0.4f * halfW, plateY);
  s.cameras.push_back(camera({4, plateY + 2, 4.5f}, {0, 0.5f * top, 0}));
  s.lights.push_back(spot({0.2f, plateY + 4, 0.3f}, {0, 0, 0}, 70, 0.4f));
  return s;
}

Scene singleTriangle(const Args&) {
  Scene s;
  detail::addTriangle(s, addObject(s, "triangle"), {-1, 0, 0}, {1, 0, 0}, {0, 1.5f, 0});
  s.cameras.push_back(camera({0, 0.75f, 3}, {0, 0.75f, 0}));
  s.lights.push_back(spot({0.5f, 4, 2.5f}, {0, 0.5f, 0}, 60, 0.1f));
  return s;
}

Scene plane(const Args& a) {
  Scene s;
  const auto half = static_cast<float>(a("size")) / 2;
  ground(s, half, -half, half);
  s.cameras.push_back(camera({0, 0.4f * half + 1, 0.6f * half + 1}, {0, 0, 0}));
  s.lights.push_back(sun({0.3f, -1, 0.2f}, 0.5f));
  return s;
}

// `holes` x `holes` round holes of radius 0.3 cells in a `size`^2 alpha texture: alpha 0.5 exactly on each circle,
// rising linearly to 1 (0) half a texel outside (inside) it, so its LINEAR-filtered 0.5 contour is the circle.
std::vector<uint8_t> holeTexture(int size, int holes) {
  std::vector<uint8_t> texels(static_cast<size_t>(size) * size);
  const double cell = static_cast<double>(size) / holes;  // texels per hole
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const double x = std::fmod((i + 0.5) / cell, 1.0) - 0.5, y = std::fmod((j + 0.5) / cell, 1.0) - 0.5;
      const double outside = (std::sqrt(x * x + y * y) - 0.3) * cell;  // texels beyond the rim
      texels[static_cast<size_t>(j) * size + i] =
          static_cast<uint8_t>(std::lround(255.0 * std::clamp(0.5 + outside, 0.0, 1.0)));
    }
  return texels;
}

// Alpha-tested cards: `count` 2x2 horizontal cards at `height` in a row along x, each with `holes` x `holes` round
// holes (one alpha texture spanning each card once, MASK at 0.5, LINEAR, REPEAT, double-sided) over a ground.
Scene cards(const Args& a) {
  Scene s;
  const int count = static_cast<int>(a("count")), holes = static_cast<int>(a("holes"));
  const int size = static_cast<int>(a("texels"));
  const auto height = static_cast<float>(a("height"));
  const float span = 2.6f * static_cast<float>(count);
  ground(s, 0.5f * span + 2, -3, 3);
  Material mask;
  mask.name = "holes";
  mask.alphaMode = AlphaMode::kMask;
  mask.alphaTexture = 0;
  s.alphaTextures.push_back(
      {fmt::format("builtin {}x{} holes", holes, holes), static_cast<uint32_t>(size), static_cast<uint32_t>(size), 0});
  s.alphaTexels = holeTexture(size, holes);
  s.materials = {plainMaterial(), mask};
  s.materialIds.assign(s.triangles.size(), 0);
  for (int i = 0; i < count; ++i) {
    const float x = (static_cast<float>(i) - 0.5f * static_cast<float>(count - 1)) * 2.6f;
    detail::addTexturedQuad(s, addObject(s, fmt::format("card-{}", i)), 1, {x - 1, height, -1}, {x - 1, height, 1},
                            {x + 1, height, 1}, {x + 1, height, -1});
  }
  s.cameras.push_back(camera({0.4f * span, height + 3.5f, 0.8f * span + 3}, {0, 0.3f * height, 0}));
  s.lights.push_back(spot({0.3f, height + 4, 0.2f}, {0, 0, 0}, 100, 0.05f));
  return s;
}

using Builder = Scene (*)(const Args&);
const std::vector<Builder> kBuilders = {box, stackedPlanes, poles, staircase, singleTriangle, plane, cards};

}  // namespace

const std::vector<ProceduralInfo>& proceduralScenes() {
  static const std::vector<ProceduralInfo> kScenes = {
      {"box",
       "a box resting on a ground plane (contact shadows)",
       {{"size", 1, 0.01, 100, false, "box edge length"}, {"ground", 10, 0.1, 1000, false, "ground edge length"}}},
      {"stacked-planes",
       "three horizontal planes stacked above each other (VSM light bleeding)",
       {{"gap", 1, 0.01, 100, false, "vertical distance between the planes"}}},
      {"poles",
       "a field of thin vertical poles over a long ground (long depth range)",
       {{"rows", 20, 1, 1000, true, "poles along -Z"},
        {"columns", 5, 1, 1000, true, "poles along X"},
        {"spacing", 2, 0.01, 100, false, "distance between poles"},
        {"height", 3, 0.01, 100, false, "pole height"},
        {"thickness", 0.1, 0.001, 10, false, "pole width"}}},
      {"staircase",
       "a staircase under a flat plate (non-planar receiver)",
       {{"steps", 5, 1, 100, true, "number of steps"},
        {"rise", 0.25, 0.01, 10, false, "step height"},
        {"run", 0.5, 0.01, 10, false, "step depth"},
        {"width", 2, 0.01, 100, false, "stair width"},
        {"plate_gap", 0.75, 0.01, 100, false, "plate height above the top step"}}},
      {"single-triangle", "one triangle facing +Z", {}},
      {"plane", "just a ground plane under a sun (everything lit)", {{"size", 10, 0.1, 1000, false, "edge length"}}},
      {"cards",
       "alpha-tested cards with round holes above a ground plane (holed shadows; the ground seen through the holes)",
       {{"count", 3, 1, 16, true, "cards in a row along X"},
        {"holes", 3, 1, 32, true, "holes per card side"},
        {"texels", 64, 4, 2048, true, "alpha texture size per side"},
        {"height", 1.5, 0.05, 100, false, "card height above the ground"}}},
  };
  return kScenes;
}

namespace {

// The index of `name` in proceduralScenes() with `params` checked against its parameters. Throws SceneError.
size_t checkedScene(std::string_view name, const ProceduralParams& params) {
  const auto& scenes = proceduralScenes();
  for (size_t i = 0; i < scenes.size(); ++i) {
    if (scenes[i].name != name) continue;
    for (const auto& [key, value] : params) {
      const std::string& wanted = key;  // clang before 16 cannot capture a structured binding
      const auto p = std::find_if(scenes[i].params.begin(), scenes[i].params.end(),
                                  [&](const auto& q) { return q.name == wanted; });
      if (p == scenes[i].params.end()) throw SceneError(fmt::format("builtin:{}: unknown parameter \"{}\"", name, key));
      if (!(value >= p->min && value <= p->max) || (p->integer && value != std::floor(value)))
        throw SceneError(fmt::format("builtin:{}: {} = {} is outside {}..{}{}", name, key, value, p->min, p->max,
                                     p->integer ? " (integers only)" : ""));
    }
    return i;
  }
  std::string names;
  for (const auto& s : scenes) names += (names.empty() ? "" : ", ") + s.name;
  throw SceneError(fmt::format("builtin:{}: unknown built-in scene (available: {})", name, names));
}

}  // namespace

Scene makeProcedural(std::string_view name, const ProceduralParams& params) {
  const size_t i = checkedScene(name, params);
  return kBuilders[i](Args{proceduralScenes()[i], params});
}

uint64_t proceduralTriangleCount(std::string_view name, const ProceduralParams& params) {
  const size_t i = checkedScene(name, params);
  const Args a{proceduralScenes()[i], params};
  if (name == "poles")  // up to a million poles: counted, not built
    return uint64_t{12} * static_cast<uint64_t>(a("rows")) * static_cast<uint64_t>(a("columns")) + 2;
  return kBuilders[i](a).triangles.size();  // the others stay small (their parameters' ranges bound them)
}

Scene makeProceduralFromSpec(std::string_view spec) {
  const size_t colon = spec.find(':');
  ProceduralParams params;
  if (colon != std::string_view::npos) {
    for (std::string_view item : detail::splitParts(spec.substr(colon + 1), ',')) {
      const size_t eq = item.find('=');
      if (eq == std::string_view::npos || eq == 0)
        throw SceneError(fmt::format("builtin:{}: expected key=value, got \"{}\"", spec, item));
      double value = 0.0;
      try {
        value = detail::parseFiniteFloat(item.substr(eq + 1), item.substr(0, eq));
      } catch (const std::invalid_argument& e) {
        throw SceneError(fmt::format("builtin:{}: {}", spec, e.what()));
      }
      if (!params.emplace(std::string(item.substr(0, eq)), value).second)
        throw SceneError(fmt::format("builtin:{}: parameter \"{}\" given twice", spec, item.substr(0, eq)));
    }
  }
  return makeProcedural(spec.substr(0, colon), params);
}

}  // namespace penumbra
