// What `run` records and `status` reads: one JSON Lines file of status records per shard under
// DIR/penumbra-status/ (appended and flushed a record at a time, so a killed run keeps what it finished), and the
// job id in a finished output's EXR header (penumbra:job-id), the one proof that a job is done.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "tools/cli/manifest.h"

namespace penumbra::cli {

// sysexits(3): a job that failed for good (bad line, bad scene, a technique refusing its light) and one worth
// running again (interrupted, or not started before --time-limit).
inline constexpr int kExitPermanent = 65;  // EX_DATAERR
inline constexpr int kExitRetryable = 75;  // EX_TEMPFAIL
inline constexpr int kExitStatusLog = 74;  // EX_IOERR: the status log cannot be written (not for lack of space)

inline constexpr const char* kJobIdAttribute = "penumbra:job-id";
// The manifest line that made an output (its absolute path, ":LINE"): another manifest's output is not replaced
// without --force.
inline constexpr const char* kJobWhereAttribute = "penumbra:job";

struct StatusRecord {
  std::string id, where, output;
  std::string state;  // "done", "skipped" (its output was there), "failed"
  int exit = 0;
  double seconds = 0;   // wall time: start to outputs written
  double deviceMs = 0;  // a rendered job's device time (the sum of its passes' profiling events), as bench's
  std::string device, host, time, error;  // time: UTC, ISO 8601 with milliseconds
  std::vector<std::string> warnings;      // the frame's own (a frame that sees nothing, a light inside the scene, ...)
};

nlohmann::json toJson(const StatusRecord& record);

std::filesystem::path statusFolder(const std::filesystem::path& outDir);

class StatusLog {
 public:
  // Appends to DIR/penumbra-status/shard-I-of-N.jsonl (creating the folder). Throws std::runtime_error naming it.
  StatusLog(const std::filesystem::path& outDir, const std::string& shardLabel);
  void append(StatusRecord record);  // fills host and time

 private:
  std::filesystem::path path_;
  std::ofstream out_;
  std::string host_;
};

// Every shard's records, the latest (by time) under its job's id and under its "where" (manifest:line: a line
// without an id whose scene could not be loaded has no id); lines that are not records are skipped.
std::map<std::string, StatusRecord> latestRecords(const std::filesystem::path& outDir);

// The job's latest record: by `id` (when known), else by `where`; null when there is none.
const StatusRecord* findRecord(const std::map<std::string, StatusRecord>& records, const std::string& id,
                               const std::string& where);

// The job id in `exr`'s header, "" when the file is missing or is not a readable EXR.
std::string outputJobId(const std::filesystem::path& exr);

// Who made an output: its job id and manifest line (kJobWhereAttribute), each "" when the header lacks it or the
// file is missing or unreadable.
struct OutputOrigin {
  std::string id, job;
};
OutputOrigin outputOrigin(const std::filesystem::path& exr);

// This machine's name (status records, claims).
std::string hostName();

}  // namespace penumbra::cli
