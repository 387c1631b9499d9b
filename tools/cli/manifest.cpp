// A manifest line becomes `render`'s own argument list (scene first, then --KEY VALUE), parsed by a CLI::App that
// declares exactly render's options (addRenderOptions); the job's key is what the parse gave, normalised: the
// options given, the technique's canonical name and its whole parameter list (defaults included).
#include "tools/cli/manifest.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstring>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "host/cl/context.h"
#include "host/io/bounded_read.h"
#include "host/scene/load.h"
#include "host/version.h"
#include "tools/cli/commands.h"
#include "tools/cli/input_limits.h"

namespace penumbra::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr std::string_view kBuiltin = "builtin:";

std::string scalarText(const std::string& key, const json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_number()) return value.dump();
  throw std::invalid_argument(fmt::format("\"{}\": {} is not a string or a number", key, value.dump()));
}

// `text` under --out: relative, never leaving it.
fs::path underOut(const std::string& key, const std::string& text, const fs::path& outDir) {
  const fs::path path = fs::path(text).lexically_normal();
  if (text.empty() || path.is_absolute() || (!path.empty() && *path.begin() == ".."))
    throw std::invalid_argument(fmt::format("\"{}\": '{}' is not a relative path inside --out", key, text));
  return outDir / path;
}

std::string resolveScene(const std::string& scene, const fs::path& base) {
  if (scene.rfind(kBuiltin, 0) == 0 || fs::path(scene).is_absolute()) return scene;
  return (base / scene).lexically_normal().string();
}

// render's arguments for the job (scene first), and its output and id as written.
std::vector<std::string> jobArguments(const json& object, const JobPaths& paths, const CLI::App& app,
                                      ManifestJob& job) {
  std::vector<std::string> args{""};
  for (const auto& [key, value] : object.items()) {
    if (key == "id") {
      job.id = scalarText(key, value);
    } else if (key == "scene") {
      args[0] = resolveScene(scalarText(key, value), paths.sceneBase);
    } else if (key == "output") {
      job.output = scalarText(key, value);
      args.insert(args.end(), {"--output", underOut(key, job.output, paths.outDir).string()});
    } else if (key == "png") {
      const std::string png = scalarText(key, value);
      args.insert(args.end(), {"--png", png == "none" ? png : underOut(key, png, paths.outDir).string()});
    } else if (key == "device" || key == "quiet") {
      throw std::invalid_argument(fmt::format("\"{}\" is an option of penumbra run, not of a job", key));
    } else if (key.size() < 2 || app.get_option_no_throw("--" + key) == nullptr) {
      throw std::invalid_argument(fmt::format("\"{}\" is not an option of penumbra render", key));
    } else {
      args.insert(args.end(), {"--" + key, scalarText(key, value)});
    }
  }
  if (args[0].empty()) throw std::invalid_argument("no \"scene\"");
  if (job.output.empty()) throw std::invalid_argument("no \"output\"");
  return args;
}

// The options given (but the paths, the EXR's compression and the technique's), the technique's name and every
// parameter's value.
std::string normalisedKey(const CLI::App& app, const TechniqueChoice& choice) {
  json key = json::object();
  for (const CLI::Option* option : app.get_options()) {
    const std::string name = option->get_name();
    if (option->count() == 0 || option->get_group() == "Technique parameters" || name.rfind("--", 0) != 0) continue;
    // Where and how the output is written is not what it holds (the compressions are lossless).
    if (name == "--output" || name == "--png" || name == "--exr-compression" || name == "--technique" ||
        name == "--device")
      continue;
    key[name.substr(2)] = option->results();
  }
  key["technique"] = choice.info->name;
  key["parameters"] = choice.params.describe();
  return key.dump();
}

std::string lowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// "not JSON: syntax error ..." without nlohmann's "[json.exception.parse_error.101] " prefix.
std::string jsonMessage(const json::exception& e) {
  const std::string text = e.what();
  const size_t end = text.find("] ");
  return "not JSON: " + (end == std::string::npos ? text : text.substr(end + 2));
}

// One manifest line as JSON, a key given twice in one object refused (nlohmann would keep the last one silently,
// so `{"technique": "sm", ..., "technique": "pcss"}` rendered pcss).
json parseLine(const std::string& text) {
  std::vector<std::set<std::string>> keys;  // per open object
  return json::parse(text, [&keys](int, json::parse_event_t event, json& value) {
    if (event == json::parse_event_t::object_start) keys.emplace_back();
    if (event == json::parse_event_t::object_end) keys.pop_back();
    if (event == json::parse_event_t::key && !keys.back().insert(value.get<std::string>()).second)
      throw std::invalid_argument(fmt::format("duplicate key \"{}\"", value.get<std::string>()));
    return true;
  });
}

// Registers the files `job` writes in `files`; the error when one of them is another line's (or its own twice).
using ClaimedFiles = std::map<std::string, std::pair<size_t, std::string>>;  // file -> its line and its name there

std::string claimOutputs(const ManifestJob& job, size_t line, ClaimedFiles& files) {
  const ImageOutputPlan plan = planImageOutput(job.options.output);
  const std::string exrName = fs::path(job.output).lexically_normal().string();
  std::vector<std::pair<std::string, std::string>> mine;  // key, name in messages
  for (const auto& [file, name] : {std::pair{plan.exr, exrName}, std::pair{plan.png, std::string()}}) {
    if (!file) continue;
    const std::string key = fs::absolute(*file).lexically_normal().string();
    mine.emplace_back(key, name.empty() ? "preview " + file->string() : "output " + name);
  }
  for (const auto& [key, name] : mine) {
    const auto it = files.find(key);
    if (it == files.end()) continue;
    if (it->second.second == name)  // the same role: "output a.exr is line 1's too"
      return fmt::format("{} is line {}'s too", name, it->second.first);
    return fmt::format("{} is line {}'s {}", name, it->second.first, it->second.second);
  }
  for (const auto& [key, name] : mine) files.emplace(key, std::pair{line, name});
  return {};
}

}  // namespace

ManifestJob parseJob(const json& object, const JobPaths& paths) {
  if (!object.is_object()) throw std::invalid_argument("not a JSON object");
  ManifestJob job;
  CLI::App app{"manifest job"};
  addRenderOptions(&app, job.options);
  std::vector<std::string> args = jobArguments(object, paths, app, job);
  if (lowerExtension(job.output) != ".exr")
    throw std::invalid_argument(
        fmt::format("\"output\": '{}' is not an .exr file (its header holds the job's id)", job.output));
  std::reverse(args.begin(), args.end());  // CLI11 takes a vector last argument first
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    throw std::invalid_argument(e.what());
  }
  planImageOutput(job.options.output);
  job.key = normalisedKey(app, chooseTechnique(job.options));
  return job;
}

std::vector<ManifestJob> readManifest(const fs::path& path, const fs::path& outDir) {
  std::istringstream in;
  try {
    in.str(readBoundedFile(path, kMaxManifestBytes, "the manifest"));
  } catch (const std::runtime_error& e) {
    throw CommandError(kExitNoManifest, e.what());
  }
  const JobPaths paths{path.parent_path(), outDir};
  std::vector<ManifestJob> jobs;
  std::map<std::string, size_t> ids;  // -> line
  // Every file a job writes (its EXR and its PNG preview, under --out) -> the line and the name it has there: no job
  // may write another's file, whichever of the two it is (a preview named like another job's EXR would replace it).
  ClaimedFiles files;
  std::string text;
  for (size_t line = 1; std::getline(in, text); ++line) {
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
    ManifestJob job;
    try {
      job = parseJob(parseLine(text), paths);
    } catch (const json::exception& e) {
      job.error = jsonMessage(e);
    } catch (const std::invalid_argument& e) {
      job.error = e.what();
    }
    job.where = fmt::format("{}:{}", path.string(), line);
    job.line = line, job.index = jobs.size();
    if (job.error.empty()) job.error = claimOutputs(job, line, files);
    if (job.error.empty() && !job.id.empty() && !ids.emplace(job.id, line).second)
      job.error = fmt::format("id {} is line {}'s too", job.id, ids[job.id]);
    if (!job.error.empty()) job.error = job.where + ": " + job.error;
    jobs.push_back(std::move(job));
  }
  if (jobs.empty()) throw CommandError(kExitNoManifest, fmt::format("{}: the manifest holds no job", path.string()));
  return jobs;
}

HashedScene loadHashedScene(const ViewOptions& view) {
  uint64_t hash = fnv1a64("");
  LoadOptions load = loadOptions(view);
  load.onFileRead = [&hash](const fs::path&, std::span<const unsigned char> bytes) {
    hash = fnv1a64(std::to_string(bytes.size()) + ":", hash);
    hash = fnv1a64({reinterpret_cast<const char*>(bytes.data()), bytes.size()}, hash);
  };
  Scene scene = loadScene(view.scene, load);
  const bool builtin = view.scene.rfind(kBuiltin, 0) == 0;
  return {std::move(scene), builtin ? view.scene : fmt::format("files:{:016x}", hash)};
}

std::string jobId(const ManifestJob& job, const std::string& digest) {
  return fmt::format("{:016x}", fnv1a64(job.key + "\n" + digest + "\n" + std::string(version())));
}

std::string staleIdReason(const ManifestJob& job, const std::string& id) {
  if (job.id.empty() || job.id == id) return {};
  return fmt::format(
      "id {} in the manifest, {} for the job now: its scene's files or penumbra's version changed since it was "
      "planned (run penumbra plan again)",
      job.id, id);
}

}  // namespace penumbra::cli
