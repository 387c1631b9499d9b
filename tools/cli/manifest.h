// Manifests: JSON Lines, one render job per line ({"scene": ..., "technique": ..., "output": "a/b.exr", "map-size":
// 1024, ...}: every `render` option under its long name), read through `render`'s own option declarations so the
// two can never drift. A bad line fails alone, named "jobs.jsonl:3". A job's id hashes the normalised job, the
// content of every file its scene reads and the tool's version.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "tools/cli/render_job.h"

namespace penumbra::cli {

inline constexpr int kExitNoManifest = 66;  // sysexits EX_NOINPUT: the manifest cannot be read or holds no job

struct ManifestJob {
  std::string where;      // "jobs.jsonl:3", the prefix of its messages
  size_t line = 0;        // 1-based line of the manifest
  size_t index = 0;       // k: its place among the manifest's jobs, 0-based (blank lines do not count); shard k mod N
  std::string output;     // as written: relative to --out
  std::string id;         // as written ("" when the line has none)
  std::string error;      // non-empty: the line is bad ("jobs.jsonl:3: ..."); it fails alone
  RenderOptions options;  // as `render` would parse them: -o and --png under --out, the scene path resolved
  std::string key;        // the normalised job without its scene's content (jobId adds that)
};

// Where relative paths of a job lead: the scene relative to the manifest's folder, outputs under --out.
struct JobPaths {
  std::filesystem::path sceneBase, outDir;
};

// One job object through `render`'s options. Throws std::invalid_argument (message without the line prefix) for a
// key that is not a render option (or is run's own: device, quiet), a value that is not a string or a number, a
// missing scene or output, an output outside --out or not .exr, or anything `render` would refuse before loading.
ManifestJob parseJob(const nlohmann::json& object, const JobPaths& paths);

// Every non-blank line of `path`; a bad line (not JSON, not a job, a duplicate output or id) comes back with its
// error set. Throws CommandError (exit kExitNoManifest, 66) naming the file when it cannot be read or holds no job.
std::vector<ManifestJob> readManifest(const std::filesystem::path& path, const std::filesystem::path& outDir);

// A scene loaded with its content digest for the id: a built-in scene's spec, else a hash of every file the load
// reads, in order (one load gives both; scene_cache.h keeps them).
struct HashedScene {
  Scene scene;
  std::string digest;
};
HashedScene loadHashedScene(const ViewOptions& view);

// 16 hex digits: the job's key, the scene digest and penumbra's version, hashed.
std::string jobId(const ManifestJob& job, const std::string& digest);

// Why the line's id is stale against `id`, the one the job has now ("" when they agree or the line has none): run
// refuses such a line, dry runs and status report it.
std::string staleIdReason(const ManifestJob& job, const std::string& id);

}  // namespace penumbra::cli
