// JSON parsing and strict reading for scene files and glTF checks (nlohmann::json). Depth is measured
// without recursion, so a hostile file cannot overflow the stack here or in the consumers after us.
#include "host/scene/json_util.h"

#include <cmath>
#include <vector>

#include <fmt/format.h>

namespace penumbra::detail {

std::string pointerTo(const std::string& parent, std::string_view key) {
  std::string out = parent + "/";
  for (char c : key) out += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
  return out;
}

std::string brief(const Json& value) {
  std::string s = value.dump();
  return s.size() > 60 ? s.substr(0, 57) + "..." : s;
}

std::string pointerTo(const std::string& parent, size_t index) { return parent + "/" + std::to_string(index); }

void failAt(const std::string& file, const std::string& pointer, const std::string& message) {
  throw SceneError(fmt::format("{}: {}: {}", file, pointer.empty() ? "(root)" : pointer, message));
}

Json parseJson(const std::string& file, std::string_view text, bool rejectDuplicates, uint64_t maxValues) {
  std::vector<std::set<std::string>> keys;  // per open object
  uint64_t values = 0;
  const Json::parser_callback_t callback = [&](int depth, Json::parse_event_t event, Json& parsed) {
    using E = Json::parse_event_t;
    // Throwing stops the parse before memory or later recursion explode.
    if ((event == E::value || event == E::object_start || event == E::array_start) && ++values > maxValues)
      throw SceneError(fmt::format("{}: more than {} JSON values (LoadOptions::maxJsonValues)", file, maxValues));
    if (depth > kMaxJsonDepth)
      throw SceneError(fmt::format("{}: JSON nested deeper than {} levels", file, kMaxJsonDepth));
    if (event == E::object_start) keys.emplace_back();
    if (event == E::object_end && !keys.empty()) keys.pop_back();
    if (event == E::key && rejectDuplicates && !keys.empty() && !keys.back().insert(parsed.get<std::string>()).second)
      throw SceneError(fmt::format("{}: duplicate key \"{}\"", file, parsed.get<std::string>()));
    return true;
  };
  Json doc;
  try {
    doc = Json::parse(text.begin(), text.end(), callback, true, false);
  } catch (const Json::exception& e) {
    std::string what = e.what();
    if (const size_t end = what.find("] "); what.rfind("[json.exception", 0) == 0 && end != std::string::npos)
      what = what.substr(end + 2);
    throw SceneError(fmt::format("{}: invalid JSON: {}", file, what));
  }
  return doc;
}

ObjectReader::ObjectReader(const Json& value, std::string file, std::string pointer)
    : object_(&value), file_(std::move(file)), pointer_(std::move(pointer)) {
  if (!value.is_object()) failAt(file_, pointer_, "expected an object");
}

const Json* ObjectReader::find(std::string_view key) {
  used_.emplace(key);
  const auto it = object_->find(key);
  return it == object_->end() ? nullptr : &*it;
}

void ObjectReader::fail(std::string_view key, const std::string& message) const {
  failAt(file_, pointer(key), message);
}

double ObjectReader::number(std::string_view key, double lo, double hi, const char* range) {
  const Json* v = find(key);
  if (!v) fail(key, "missing (expected a number in " + std::string(range) + ")");
  return number(key, lo, hi, range, 0.0);
}

double ObjectReader::number(std::string_view key, double lo, double hi, const char* range, double fallback) {
  const Json* v = find(key);
  if (!v) return fallback;
  const double d = v->is_number() ? v->get<double>() : NAN;
  // `range` spells the bounds, e.g. "(0, 180)" or "[0, inf)"; lo/hi are checked with its brackets.
  const bool loOpen = range[0] == '(', hiOpen = std::string_view(range).back() == ')';
  const bool ok = std::isfinite(d) && (loOpen ? d > lo : d >= lo) && (hiOpen ? d < hi : d <= hi);
  if (!ok) fail(key, fmt::format("expected a number in {}, got {}", range, brief(*v)));
  return d;
}

bool ObjectReader::boolean(std::string_view key, bool fallback) {
  const Json* v = find(key);
  if (!v) return fallback;
  if (!v->is_boolean()) fail(key, "expected true or false, got " + brief(*v));
  return v->get<bool>();
}

std::string ObjectReader::string(std::string_view key) {
  const Json* v = find(key);
  if (!v || !v->is_string()) fail(key, v ? "expected a string, got " + brief(*v) : "missing (expected a string)");
  return v->get<std::string>();
}

glm::vec3 ObjectReader::vec3(std::string_view key) {
  const Json* v = find(key);
  if (!v) fail(key, "missing (expected an array of 3 numbers)");
  return glm::vec3(numberArray(*v, 3, file_, pointer(key)));
}

std::optional<glm::vec3> ObjectReader::optionalVec3(std::string_view key) {
  const Json* v = find(key);
  if (!v) return std::nullopt;
  return glm::vec3(numberArray(*v, 3, file_, pointer(key)));
}

void ObjectReader::finish() const {
  for (auto it = object_->begin(); it != object_->end(); ++it)
    if (!used_.contains(it.key())) failAt(file_, pointer(it.key()), "unknown key");
}

glm::dvec4 numberArray(const Json& value, size_t size, const std::string& file, const std::string& pointer) {
  const auto bad = [&] {
    failAt(file, pointer, fmt::format("expected an array of {} finite numbers, got {}", size, brief(value)));
  };
  if (!value.is_array() || value.size() != size) bad();
  glm::dvec4 out(0.0);
  for (size_t i = 0; i < size; ++i) {
    if (!value[i].is_number() || !std::isfinite(value[i].get<double>())) bad();
    out[static_cast<int>(i)] = value[i].get<double>();
  }
  return out;
}

}  // namespace penumbra::detail
