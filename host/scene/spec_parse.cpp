// Strict number parsing for the command-line forms (std::from_chars: no locale, no leading spaces, no
// silent truncation at the first bad character).
#include "host/scene/spec_parse.h"

#include <charconv>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "host/scene/limits.h"

namespace penumbra::detail {

std::vector<std::string_view> splitParts(std::string_view text, char sep) {
  std::vector<std::string_view> parts;
  size_t start = 0;
  for (;;) {
    const size_t end = text.find(sep, start);
    parts.push_back(text.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start));
    if (end == std::string_view::npos) return parts;
    start = end + 1;
  }
}

float parseFiniteFloat(std::string_view text, std::string_view what) {
  float value = 0.0f;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec == std::errc::result_out_of_range && ptr == end && !text.empty()) {  // a number, but not a float's
    double wide = 0.0;
    std::from_chars(text.data(), end, wide);
    if (std::fabs(wide) > 1.0)
      throw std::invalid_argument(fmt::format("{}: {} is beyond the largest float (3.4e+38)", what, text));
    return 0.0f;  // below the smallest float: as close to 0 as float gets
  }
  if (text.empty() || ec != std::errc() || ptr != end)
    throw std::invalid_argument(fmt::format("{}: expected a number, got \"{}\"", what, text));
  if (!std::isfinite(value)) throw std::invalid_argument(fmt::format("{}: {} is not a finite number", what, text));
  return value;
}

long long parseInteger(std::string_view text, std::string_view what) {
  long long value = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ec != std::errc() || ptr != end)
    throw std::invalid_argument(fmt::format("{}: expected an integer, got \"{}\"", what, text));
  return value;
}

glm::vec3 parseVec3(std::string_view text, std::string_view what) {
  const auto parts = splitParts(text, ',');
  if (parts.size() != 3)
    throw std::invalid_argument(fmt::format("{}: expected 3 comma-separated numbers, got \"{}\"", what, text));
  static constexpr const char* kAxis[3] = {"x", "y", "z"};
  glm::vec3 v;
  for (int i = 0; i < 3; ++i) {
    v[i] = parseFiniteFloat(parts[i], fmt::format("{} {}", what, kAxis[i]));
    if (!inCoordinateRange(v[i]))
      throw std::invalid_argument(fmt::format("{} {}: {} is outside +-{:g} (the renderer's coordinate range)", what,
                                              kAxis[i], parts[i], kMaxCoordinate));
  }
  return v;
}

std::string formatFloat(float value) {
  char buffer[32];
  const auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return ec == std::errc() ? std::string(buffer, ptr) : fmt::format("{}", value);
}

std::string formatVec3(const glm::vec3& v) {
  return formatFloat(v.x) + "," + formatFloat(v.y) + "," + formatFloat(v.z);
}

}  // namespace penumbra::detail
