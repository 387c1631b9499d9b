// `penumbra plan SWEEP.json -o jobs.jsonl`: a sweep (sweep_plan.h) expanded into a manifest, every job checked by
// `render`'s own options (manifest.h parseJob) and given its id (the normalised job, its scene's files and the
// tool's version). Scene paths relative to the sweep file come out relative to the manifest. Written atomically.
#include <fmt/format.h>

#include <fstream>
#include <memory>
#include <sstream>

#include <CLI/CLI.hpp>

#include "host/io/atomic_file.h"
#include "host/io/bounded_read.h"
#include "tools/cli/commands.h"
#include "tools/cli/input_limits.h"
#include "tools/cli/scene_cache.h"
#include "tools/cli/sweep_plan.h"

namespace penumbra::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using nlohmann::ordered_json;

struct PlanOptions {
  std::string sweep, output = "jobs.jsonl";
  bool quiet = false;
};

ordered_json readSweep(const std::string& path) {
  const std::string text = readBoundedFile(path, kMaxSweepBytes, "the sweep");
  try {
    return ordered_json::parse(text);
  } catch (const json::exception& e) {
    const std::string message = e.what();
    throw std::runtime_error(fmt::format("{}: not JSON: {}", path, message.substr(message.find("] ") + 2)));
  }
}

// A scene file named relative to the sweep, renamed relative to the manifest's folder.
json rebaseScene(const json& scene, const fs::path& from, const fs::path& to) {
  if (!scene.is_string()) return scene;
  const std::string text = scene.get<std::string>();
  if (text.rfind("builtin:", 0) == 0 || fs::path(text).is_absolute()) return scene;
  const fs::path target = fs::absolute(from / text).lexically_normal();
  return target.lexically_proximate(fs::absolute(to).lexically_normal()).string();
}

void rebaseScenes(ordered_json& sweep, const fs::path& from, const fs::path& to) {
  if (!sweep.is_object() || !sweep.contains("scene")) return;
  ordered_json& scene = sweep["scene"];
  if (scene.is_array())
    for (ordered_json& s : scene) s = rebaseScene(s, from, to);
  else
    scene = rebaseScene(scene, from, to);
}

// The manifest's lines: each job validated, with its id first.
std::string manifestText(const std::vector<ordered_json>& jobs, const PlanOptions& o, const fs::path& manifestDir) {
  SceneCache scenes;
  std::map<std::string, size_t> outputs, ids;
  std::ostringstream text;
  for (size_t i = 0; i < jobs.size(); ++i) {
    const std::string output = jobs[i].value("output", "");
    const std::string where = fmt::format("{}: job {} ({})", o.sweep, i, output);
    std::string id;
    try {
      const ManifestJob job = parseJob(json::parse(jobs[i].dump()), {manifestDir, "."});
      id = jobId(job, scenes.digest(job.options.view));
    } catch (const std::exception& e) {
      throw std::runtime_error(fmt::format("{}: {}", where, e.what()));
    }
    if (const auto [it, fresh] = outputs.emplace(output, i); !fresh)
      throw std::runtime_error(
          fmt::format("{}: the output of job {} too (put {{frame}} or a key in \"output\")", where, it->second));
    if (const auto [it, fresh] = ids.emplace(id, i); !fresh)
      throw std::runtime_error(fmt::format("{}: renders the same image as job {}", where, it->second));
    ordered_json line = {{"id", id}};
    line.update(jobs[i]);
    text << line.dump() << '\n';
  }
  return text.str();
}

int run(const PlanOptions& o) {
  ordered_json sweep = readSweep(o.sweep);
  // A bare file name's folder is the working directory ("": fs::absolute refuses it).
  const auto folderOf = [](const std::string& file) {
    const fs::path parent = fs::path(file).parent_path();
    return parent.empty() ? fs::path(".") : parent;
  };
  const fs::path manifestDir = folderOf(o.output);
  rebaseScenes(sweep, folderOf(o.sweep), manifestDir);
  std::vector<ordered_json> jobs;
  try {
    jobs = expandSweep(sweep);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(fmt::format("{}: {}", o.sweep, e.what()));
  }
  const std::string text = manifestText(jobs, o, manifestDir);
  if (!manifestDir.empty()) fs::create_directories(manifestDir);
  writeFileAtomically(o.output, text);
  if (!o.quiet) fmt::print("wrote {} jobs to {}\n", jobs.size(), o.output);
  return 0;
}

}  // namespace

Command addPlanCommand(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("plan", "Expand a sweep (lists, frames, camera paths) into a manifest");
  auto o = std::make_shared<PlanOptions>();
  sub->add_option("sweep", o->sweep, "Sweep: a JSON object (see docs/batch.md)")->required();
  sub->add_option("-o,--output", o->output, "Manifest to write (JSON Lines)")->capture_default_str();
  sub->add_flag("-q,--quiet", o->quiet, "Print nothing on success");
  return {sub, [o] { return run(*o); }};
}

}  // namespace penumbra::cli
