// Light names: the channel-safe rule (ASCII letters, digits, '_' and '-'), uniqueness by numbered suffixes, and
// the lookup behind `--light gltf:INDEX|NAME`.
#include "host/scene/light_names.h"

#include <algorithm>
#include <charconv>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

namespace penumbra {
namespace {

bool channelSafe(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
}

const char* typeName(LightType type) {
  switch (type) {
    case LightType::Spot:
      return "spot";
    case LightType::Directional:
      return "dir";
    case LightType::Point:
      return "point";
  }
  return "?";
}

}  // namespace

std::string channelSafeName(std::string_view name) {
  std::string out(name.substr(0, kMaxLightNameLength));
  for (char& c : out)
    if (!channelSafe(c)) c = '_';
  return out;
}

void nameLights(std::vector<Light>& lights) {
  std::set<std::string> taken;
  for (size_t i = 0; i < lights.size(); ++i) {
    std::string base = channelSafeName(lights[i].name);
    if (base.empty()) base = fmt::format("light{}", i);
    std::string name = base;
    for (int suffix = 2; taken.count(name); ++suffix) {
      const std::string tail = fmt::format("-{}", suffix);
      name = base.substr(0, kMaxLightNameLength - tail.size()) + tail;
    }
    taken.insert(name);
    lights[i].name = std::move(name);
  }
}

std::string listLights(const std::vector<Light>& lights) {
  std::string text;
  for (size_t i = 0; i < lights.size(); ++i)
    text += fmt::format("{}{} \"{}\" ({})", i ? ", " : "", i, lights[i].name, typeName(lights[i].type));
  return text.empty() ? "none" : text;
}

size_t findLight(const std::vector<Light>& lights, std::string_view key) {
  size_t index = 0;
  const auto [end, error] = std::from_chars(key.data(), key.data() + key.size(), index);
  const bool numeric = !key.empty() && error == std::errc() && end == key.data() + key.size();
  if (numeric && index < lights.size()) return index;
  if (!numeric) {
    const auto it = std::find_if(lights.begin(), lights.end(), [&](const Light& l) { return l.name == key; });
    if (it != lights.end()) return static_cast<size_t>(it - lights.begin());
  }
  const std::string what = numeric ? fmt::format("no light {}", key) : fmt::format("no light named \"{}\"", key);
  throw std::invalid_argument(
      fmt::format("--light gltf:{}: {} (the scene's lights: {})", key, what, listLights(lights)));
}

std::string lightLayer(const Light& light) { return light.name.empty() ? std::string(kUnnamedLightLayer) : light.name; }

std::string lightChannel(std::string_view prefix, std::string_view layer) {
  return fmt::format("{}.{}.Y", prefix, layer);
}

}  // namespace penumbra
