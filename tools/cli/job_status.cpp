// Status records as JSON Lines; host names from gethostname(2), times from the system clock in UTC.
#include "tools/cli/job_status.h"

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <climits>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "host/io/atomic_file.h"
#include "host/io/bounded_read.h"
#include "host/io/exr.h"
#include "tools/cli/commands.h"
#include "tools/cli/input_limits.h"

namespace penumbra::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string utcNow() {
  const auto now = std::chrono::system_clock::now();
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  return fmt::format("{:%Y-%m-%dT%H:%M:%S}.{:03}Z", fmt::gmtime(std::chrono::system_clock::to_time_t(now)), ms);
}

StatusRecord fromJson(const json& j) {
  StatusRecord r;
  r.id = j.at("id"), r.where = j.value("where", ""), r.output = j.value("output", ""), r.state = j.at("state");
  r.exit = j.value("exit", 0), r.seconds = j.value("seconds", 0.0), r.deviceMs = j.value("device_ms", 0.0),
  r.device = j.value("device", "");
  r.host = j.value("host", ""), r.time = j.value("time", ""), r.error = j.value("error", "");
  r.warnings = j.value("warnings", std::vector<std::string>{});
  return r;
}

}  // namespace

json toJson(const StatusRecord& r) {
  json j = {{"id", r.id},           {"where", r.where},   {"output", r.output}, {"state", r.state}, {"exit", r.exit},
            {"seconds", r.seconds}, {"device", r.device}, {"host", r.host},     {"time", r.time}};
  if (r.deviceMs > 0) j["device_ms"] = r.deviceMs;
  if (!r.error.empty()) j["error"] = r.error;
  if (!r.warnings.empty()) j["warnings"] = r.warnings;
  return j;
}

fs::path statusFolder(const fs::path& outDir) { return outDir / "penumbra-status"; }

std::string hostName() {
  char name[HOST_NAME_MAX + 1] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}

namespace {

// The log cannot take a record: exit 75 when the storage is at fault (full, a quota, I/O: run again), else 74.
[[noreturn]] void failAppend(const fs::path& path, int error) {
  throw CommandError(isStorageError(error) ? kExitRetryable : kExitStatusLog,
                     fmt::format("{}: cannot append status records: {}", path.string(),
                                 error != 0 ? std::strerror(error) : "stream error"));
}

}  // namespace

StatusLog::StatusLog(const fs::path& outDir, const std::string& shardLabel)
    : path_(statusFolder(outDir) / fmt::format("shard-{}.jsonl", shardLabel)), host_(hostName()) {
  std::error_code error;
  fs::create_directories(path_.parent_path(), error);
  // A record torn by a crash mid-append ends without a newline: the next record starts on a line of its own.
  bool torn = false;
  if (std::ifstream last(path_, std::ios::binary | std::ios::ate); last && last.tellg() > 0) {
    last.seekg(-1, std::ios::end);
    torn = last.get() != '\n';
  }
  errno = 0;
  out_.open(path_, std::ios::app);
  if (torn) out_ << '\n' << std::flush;
  if (!out_) failAppend(path_, errno);
}

void StatusLog::append(StatusRecord record) {
  record.host = host_, record.time = utcNow();
  errno = 0;
  out_ << toJson(record).dump() << '\n' << std::flush;
  if (!out_) failAppend(path_, errno);
}

std::map<std::string, StatusRecord> latestRecords(const fs::path& outDir) {
  std::map<std::string, StatusRecord> latest;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(statusFolder(outDir), error)) {
    if (entry.path().extension() != ".jsonl") continue;
    std::istringstream in(readBoundedFile(entry.path(), kMaxStatusLogBytes, "the status log"));
    for (std::string line; std::getline(in, line);) {
      // A line cut short by a kill is not a record; one that a record was appended to without a newline (logs
      // written before the writer ended torn lines) still holds that record after the fragment.
      for (size_t start = 0; start != std::string::npos; start = line.find("{\"", start + 1)) {
        try {
          const StatusRecord record = fromJson(json::parse(std::string_view(line).substr(start)));
          for (const std::string& key : {record.id, record.where}) {
            if (key.empty()) continue;
            auto [it, fresh] = latest.emplace(key, record);
            if (!fresh && it->second.time <= record.time) it->second = record;
          }
          break;
        } catch (const json::exception&) {
        }
      }
    }
  }
  return latest;
}

const StatusRecord* findRecord(const std::map<std::string, StatusRecord>& records, const std::string& id,
                               const std::string& where) {
  auto it = records.find(id.empty() ? where : id);
  if (it == records.end() && !id.empty()) it = records.find(where);
  return it == records.end() ? nullptr : &it->second;
}

OutputOrigin outputOrigin(const fs::path& exr) {
  std::error_code error;
  if (!fs::is_regular_file(exr, error)) return {};
  try {
    const ExrInfo info = readExrInfo(exr);
    const auto attribute = [&](const char* name) {
      const auto it = info.attributes.find(name);
      return it == info.attributes.end() ? std::string() : it->second;
    };
    return {attribute(kJobIdAttribute), attribute(kJobWhereAttribute)};
  } catch (const std::exception&) {
    return {};
  }
}

std::string outputJobId(const fs::path& exr) { return outputOrigin(exr).id; }

}  // namespace penumbra::cli
