// JSON helpers for the glTF checks and scene files: parsing with errors that name the file and position,
// JSON pointers for messages, and a strict object reader that refuses unknown keys.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <string_view>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "host/scene/load_options.h"

namespace penumbra::detail {

using Json = nlohmann::json;

std::string pointerTo(const std::string& parent, std::string_view key);  // RFC 6901 escaping
std::string pointerTo(const std::string& parent, size_t index);
std::string brief(const Json& value);  // value.dump(), cut to about 60 characters for messages
// Throws SceneError("FILE: POINTER: MESSAGE"); the root pointer "" is shown as "(root)".
[[noreturn]] void failAt(const std::string& file, const std::string& pointer, const std::string& message);

// What parsing a document will hold in memory, estimated by the SAX pass as it goes, so that a document past the
// budget is refused before any DOM is built: bytesPerValue for every JSON value (a DOM's node), and elementBytes(name)
// more for each element of the root object's array `name` (the struct a consumer keeps for it).
struct ParseBudget {
  uint64_t maxBytes = 0;  // 0: no budget
  uint64_t bytesPerValue = 0;
  std::function<uint64_t(std::string_view)> elementBytes;
  std::string option;  // the setting that raises the budget, named in the message
};

// Parses `text`; throws SceneError naming the file and the error's position. Nesting deeper than
// kMaxJsonDepth is refused (later consumers recurse), so are more than `maxValues` values (memory), a document whose
// estimate passes `budget` (when given), and duplicate keys when `rejectDuplicates`.
inline constexpr int kMaxJsonDepth = 64;
Json parseJson(const std::string& file, std::string_view text, bool rejectDuplicates, uint64_t maxValues,
               const ParseBudget* budget = nullptr);

// Reads one JSON object field by field; finish() refuses every key that was never asked for, so typos
// are never silent. Numbers must be finite; every error names the file and the field's pointer.
class ObjectReader {
 public:
  ObjectReader(const Json& value, std::string file, std::string pointer);
  const Json* find(std::string_view key);  // marks the key as known; nullptr when absent
  bool has(std::string_view key) const { return object_->contains(key); }
  std::string pointer(std::string_view key) const { return pointerTo(pointer_, key); }
  [[noreturn]] void fail(std::string_view key, const std::string& message) const;

  double number(std::string_view key, double lo, double hi, const char* range);  // required
  double number(std::string_view key, double lo, double hi, const char* range, double fallback);
  bool boolean(std::string_view key, bool fallback);
  std::string string(std::string_view key);  // required
  glm::vec3 vec3(std::string_view key);      // required, 3 finite numbers
  std::optional<glm::vec3> optionalVec3(std::string_view key);
  void finish() const;

  const std::string& file() const { return file_; }

 private:
  const Json* object_;
  std::string file_, pointer_;
  std::set<std::string, std::less<>> used_;
};

// A finite number array of exactly `size` elements at `pointer`, or an error naming it.
glm::dvec4 numberArray(const Json& value, size_t size, const std::string& file, const std::string& pointer);

}  // namespace penumbra::detail
