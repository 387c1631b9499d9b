// The product is walked as an odometer over the list members (last fastest), then the frames; the output template
// is filled with fmt's dynamic named arguments.
#include "tools/cli/sweep_plan.h"

#include <fmt/args.h>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <deque>
#include <filesystem>
#include <stdexcept>

#include "tools/cli/camera_path.h"

namespace penumbra::cli {
namespace {

using nlohmann::ordered_json;

constexpr long long kMaxJobs = 1000000;  // jobs a sweep may expand to: its lists' product times its frames
constexpr long long kMaxFieldWidth = 64;  // widths and precisions in the output template ({frame:04})
constexpr size_t kMaxOutputName = 4096;   // PATH_MAX

// Refuses a width or precision above kMaxFieldWidth in a replacement field's format spec ("{frame:999999999}" would
// format a gigabyte per job), before anything is formatted.
void checkOutputPattern(const std::string& pattern) {
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '{') continue;
    if (i + 1 < pattern.size() && pattern[i + 1] == '{') {  // "{{": a literal brace
      ++i;
      continue;
    }
    const size_t end = pattern.find('}', i), colon = pattern.find(':', i);
    if (end == std::string::npos || colon == std::string::npos || colon > end) continue;
    for (size_t k = colon + 1; k < end;) {
      if (!std::isdigit(static_cast<unsigned char>(pattern[k]))) {
        ++k;
        continue;
      }
      long long number = 0;
      for (; k < end && std::isdigit(static_cast<unsigned char>(pattern[k])); ++k)
        number = std::min(number * 10 + (pattern[k] - '0'), kMaxFieldWidth + 1);
      if (number > kMaxFieldWidth)
        throw std::invalid_argument(fmt::format("\"output\": '{}': a width or precision above {} in '{}'", pattern,
                                                kMaxFieldWidth, pattern.substr(i, end - i + 1)));
    }
    i = end;
  }
}

std::vector<long long> parseFrames(const ordered_json& frames) {
  long long start = 0, count = 0;
  if (frames.is_number_integer()) {
    count = frames.get<long long>();
  } else if (frames.is_object() && frames.contains("start") && frames["start"].is_number_integer()) {
    start = frames["start"].get<long long>();
    if (frames.contains("end") && frames["end"].is_number_integer())
      count = frames["end"].get<long long>() - start + 1;
    else if (frames.contains("count") && frames["count"].is_number_integer())
      count = frames["count"].get<long long>();
  }
  if (count <= 0 || count > kMaxJobs)
    throw std::invalid_argument(
        "\"frames\": use N, {\"start\": a, \"end\": b} or {\"start\": a, \"count\": n} "
        "(1 to 10^6 frames)");
  std::vector<long long> out(static_cast<size_t>(count));
  for (long long i = 0; i < count; ++i) out[static_cast<size_t>(i)] = start + i;
  return out;
}

double frameTime(const ordered_json& time, long long frame) {
  if (!time.contains("fps") || !time["fps"].is_number() || time["fps"].get<double>() <= 0)
    throw std::invalid_argument("\"time\": a per-frame time is {\"fps\": F, \"start\": S} with F > 0");
  const double start = time.contains("start") && time["start"].is_number() ? time["start"].get<double>() : 0.0;
  return start + static_cast<double>(frame) / time["fps"].get<double>();
}

// The output template filled with the job's values.
std::string outputName(const std::string& pattern, const ordered_json& job, std::optional<long long> frame,
                       size_t index) {
  fmt::dynamic_format_arg_store<fmt::format_context> args;
  std::deque<std::string> names;  // the store keeps pointers to the names
  const auto name = [&](std::string key) -> const char* {
    for (char& c : key) c = c == '-' ? '_' : c;
    return names.emplace_back(std::move(key)).c_str();
  };
  for (const auto& [key, value] : job.items()) {
    if (value.is_number_integer())
      args.push_back(fmt::arg(name(key), value.get<long long>()));
    else if (value.is_number())
      args.push_back(fmt::arg(name(key), value.get<double>()));
    else if (value.is_string())
      args.push_back(fmt::arg(name(key), value.get<std::string>()));
  }
  if (frame) args.push_back(fmt::arg("frame", *frame));
  args.push_back(fmt::arg("index", index));
  const std::string scene = job.value("scene", "");
  args.push_back(fmt::arg("scene_name", std::filesystem::path(scene.substr(scene.rfind(':') + 1)).stem().string()));
  try {
    std::string out = fmt::vformat(pattern, args);
    if (out.size() > kMaxOutputName)
      throw std::invalid_argument(fmt::format("\"output\": '{}' makes a name of {} characters (at most {})", pattern,
                                              out.size(), kMaxOutputName));
    return out;
  } catch (const fmt::format_error& e) {
    throw std::invalid_argument(
        fmt::format("\"output\": '{}': {} (the keys: the sweep's members, frame, index, "
                    "scene_name)",
                    pattern, e.what()));
  }
}

struct Axes {
  std::vector<std::string> keys;           // list members, in order
  std::vector<const ordered_json*> lists;  // their values
  std::vector<long long> frames;           // empty: no frames
};

Axes findAxes(const ordered_json& sweep) {
  Axes axes;
  for (const auto& [key, value] : sweep.items()) {
    if (key == "frames") {
      axes.frames = parseFrames(value);
    } else if (value.is_array()) {
      if (value.empty()) throw std::invalid_argument(fmt::format("\"{}\": an empty list", key));
      axes.keys.push_back(key), axes.lists.push_back(&value);
    } else if (value.is_object() && key != "camera" && key != "time") {
      throw std::invalid_argument(fmt::format("\"{}\": only \"camera\" (a path) and \"time\" take an object", key));
    }
  }
  for (const char* key : {"camera", "time"})
    if (sweep.contains(key) && sweep[key].is_object() && axes.frames.empty())
      throw std::invalid_argument(fmt::format("\"{}\": a per-frame {} needs \"frames\"", key, key));
  if (!sweep.contains("output") || !sweep["output"].is_string())
    throw std::invalid_argument("no \"output\" template (e.g. \"{technique}/frame{frame:04}.exr\")");
  checkOutputPattern(sweep["output"].get<std::string>());
  // The product before any job exists (a 4 x 100^3 list sweep took 240 s and 2.7 GB before it was refused).
  long long jobs = std::max<long long>(1, static_cast<long long>(axes.frames.size()));
  std::string product = axes.frames.empty() ? "" : fmt::format("{} frames", axes.frames.size());
  for (size_t i = 0; i < axes.keys.size(); ++i) {
    jobs = std::min(jobs * static_cast<long long>(axes.lists[i]->size()), kMaxJobs + 1);
    product += fmt::format("{}{} \"{}\"", product.empty() ? "" : " x ", axes.lists[i]->size(), axes.keys[i]);
  }
  if (jobs > kMaxJobs)
    throw std::invalid_argument(fmt::format("the sweep makes more than {} jobs ({})", kMaxJobs, product));
  return axes;
}

ordered_json makeJob(const ordered_json& sweep, const Axes& axes, const std::vector<size_t>& at,
                     std::optional<long long> frame, size_t index) {
  ordered_json job = ordered_json::object();
  for (const auto& [key, value] : sweep.items()) {
    if (key == "frames" || key == "output") continue;
    const auto axis = std::find(axes.keys.begin(), axes.keys.end(), key);
    if (axis != axes.keys.end())
      job[key] = (*axes.lists[static_cast<size_t>(
          axis - axes.keys.begin())])[at[static_cast<size_t>(axis - axes.keys.begin())]];
    else if (key == "camera" && value.is_object())
      job[key] = cameraOnPath(value, *frame, static_cast<long long>(axes.frames.size()));
    else if (key == "time" && value.is_object())
      job[key] = frameTime(value, *frame);
    else
      job[key] = value;
  }
  job["output"] = outputName(sweep["output"].get<std::string>(), job, frame, index);
  return job;
}

}  // namespace

std::vector<ordered_json> expandSweep(const ordered_json& sweep) {
  if (!sweep.is_object()) throw std::invalid_argument("a sweep is a JSON object");
  const Axes axes = findAxes(sweep);
  std::vector<ordered_json> jobs;
  std::vector<size_t> at(axes.keys.size(), 0);
  for (bool more = true; more;) {
    if (axes.frames.empty()) jobs.push_back(makeJob(sweep, axes, at, std::nullopt, jobs.size()));
    for (long long frame : axes.frames) jobs.push_back(makeJob(sweep, axes, at, frame, jobs.size()));
    more = false;
    for (size_t i = at.size(); i-- > 0;) {  // the odometer: the last list member turns fastest
      if (++at[i] < axes.lists[i]->size()) {
        more = true;
        break;
      }
      at[i] = 0;
    }
    if (jobs.size() > 10000000) throw std::invalid_argument("the sweep expands to over 10^7 jobs");
  }
  return jobs;
}

}  // namespace penumbra::cli
