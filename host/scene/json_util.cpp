// JSON parsing and strict reading for scene files and glTF checks (nlohmann::json). Limits are checked by a SAX pass
// before the DOM is built (linear time, no recursion), so a hostile file can neither overflow the stack here or in
// the consumers after us nor take quadratic time.
#include "host/scene/json_util.h"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "host/scene/limits.h"

namespace penumbra::detail {

std::string pointerTo(const std::string& parent, std::string_view key) {
  std::string out = parent + "/";
  for (char c : visible(key)) out += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
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

namespace {

// A SAX pass that checks the limits before any DOM exists: depth, value count and duplicate keys, in time and
// memory linear in the text (nlohmann's callback parser rescans the parent of every closed object: quadratic).
class LimitChecker : public nlohmann::json_sax<Json> {
 public:
  LimitChecker(const std::string& file, bool rejectDuplicates, uint64_t maxValues, const ParseBudget* budget)
      : file_(file), rejectDuplicates_(rejectDuplicates), maxValues_(maxValues), budget_(budget) {}

  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override {
    if (rejectDuplicates_) keys_.emplace_back();
    return open();
  }
  bool key(string_t& key) override {
    if (rejectDuplicates_ && !keys_.back().insert(key).second)
      throw SceneError(fmt::format("{}: duplicate key \"{}\"", file_, key));
    if (depth_ == 1) rootKey_ = key;
    return true;
  }
  bool end_object() override {
    if (rejectDuplicates_) keys_.pop_back();
    --depth_;
    return true;
  }
  bool start_array(std::size_t) override {
    const bool root = depth_ == 1 && rootIsObject_;
    if (depth_ == 0) rootIsObject_ = false;
    open();
    if (root && budget_ && budget_->elementBytes) array_ = rootKey_, elementBytes_ = budget_->elementBytes(rootKey_);
    return true;
  }
  bool end_array() override {
    if (--depth_ == 1) elementBytes_ = 0;
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    throw SceneError(fmt::format("{}: invalid JSON: {}", file_, withoutId(e.what())));
  }

  // "[json.exception.parse_error.101] parse error at ..." without the bracketed id.
  static std::string withoutId(std::string what) {
    if (const size_t end = what.find("] "); what.rfind("[json.exception", 0) == 0 && end != std::string::npos)
      what = what.substr(end + 2);
    return what;
  }

 private:
  // Every value counts, containers included; one inside more than kMaxJsonDepth open containers is refused.
  bool value() {
    if (++values_ > maxValues_)
      throw SceneError(fmt::format("{}: more than {} JSON values (LoadOptions::maxJsonValues)", file_, maxValues_));
    if (depth_ > kMaxJsonDepth)
      throw SceneError(fmt::format("{}: JSON nested deeper than {} levels", file_, kMaxJsonDepth));
    if (budget_ && budget_->maxBytes > 0) spend();
    return true;
  }
  bool open() {
    value();
    ++depth_;
    return true;
  }
  // The estimate grows by every value and, in a root array, by each element's struct; past the budget the parse
  // stops, naming the array with the most elements.
  void spend() {
    bytes_ += budget_->bytesPerValue;
    if (depth_ == 2 && elementBytes_ > 0) {
      bytes_ += elementBytes_;
      const uint64_t n = ++elements_[array_];
      if (n > largest_.second) largest_ = {array_, n};
    }
    if (bytes_ <= budget_->maxBytes) return;
    const std::string largest =
        largest_.second > 0 ? fmt::format(", {} elements of \"{}\"", largest_.second, largest_.first) : "";
    throw SceneError(
        fmt::format("{}: parsing it would hold more than {} MiB ({} JSON values{} so far); the limit is {}", file_,
                    budget_->maxBytes >> 20, values_, largest, budget_->option));
  }

  const std::string& file_;
  const bool rejectDuplicates_;
  const uint64_t maxValues_;
  const ParseBudget* budget_;
  uint64_t values_ = 0, bytes_ = 0, elementBytes_ = 0;
  int depth_ = 0;
  bool rootIsObject_ = true;  // until the root opens as something else
  std::string rootKey_, array_;
  std::map<std::string, uint64_t, std::less<>> elements_;
  std::pair<std::string, uint64_t> largest_;
  std::vector<std::set<std::string, std::less<>>> keys_;  // per open object; only when rejecting duplicates
};

}  // namespace

Json parseJson(const std::string& file, std::string_view text, bool rejectDuplicates, uint64_t maxValues,
               const ParseBudget* budget) {
  LimitChecker checker(file, rejectDuplicates, maxValues, budget);
  Json::sax_parse(text.begin(), text.end(), &checker);  // throws SceneError on any problem
  try {
    return Json::parse(text.begin(), text.end());  // no callback: linear; the text is known to be valid
  } catch (const Json::exception& e) {
    throw SceneError(fmt::format("{}: invalid JSON: {}", file, LimitChecker::withoutId(e.what())));
  }
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
  if (!has(key)) fail(key, "missing (expected an array of 3 numbers)");
  return *optionalVec3(key);
}

std::optional<glm::vec3> ObjectReader::optionalVec3(std::string_view key) {
  const Json* v = find(key);
  if (!v) return std::nullopt;
  const glm::dvec4 d = numberArray(*v, 3, file_, pointer(key));
  if (!inCoordinateRange(d.x, d.y, d.z))
    fail(key, fmt::format("{} is outside +-{:g} (the renderer's coordinate range)", brief(*v), kMaxCoordinate));
  return glm::vec3(d);
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
