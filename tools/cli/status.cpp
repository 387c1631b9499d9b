// `penumbra status jobs.jsonl --out DIR [--json]`: each job done (its output carries the id the job has now: its
// scene's files and options as they are, hashed as `run` does), stale (the manifest's id is not the job's now: plan
// again; or its output was made by another job or an older state of it), failed (a bad line, or its latest status
// record a failure) or missing; a summary, the jobs not done, and the exit code: 0 everything done, 65 a job failed
// or its manifest line is stale, 75 only missing jobs or stale outputs (run again).
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>

#include "host/io/atomic_file.h"
#include "tools/cli/claim.h"
#include "tools/cli/commands.h"
#include "tools/cli/job_status.h"
#include "tools/cli/scene_cache.h"
#include "tools/eval/bench_report.h"

namespace penumbra::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct StatusOptions {
  std::string manifest, out, csv;
  bool json = false;
};

struct JobState {
  const ManifestJob* job;
  std::string id, state, error;  // state: done, stale, failed, missing
  const StatusRecord* record = nullptr;
  bool replan = false;  // stale because the manifest's id is not the job's now
};

JobState stateOf(const ManifestJob& job, const std::map<std::string, StatusRecord>& records, SceneCache& scenes,
                 const fs::path& out, const std::string& manifestPath) {
  JobState s{&job, job.id, "failed", job.error};
  if (!job.error.empty()) return s;
  try {
    s.id = jobId(job, scenes.digest(job.options.view));  // as `run` computes it: the scene's files as they are now
  } catch (const std::exception& e) {
    return s.error = job.where + ": " + e.what(), s;
  }
  s.record = findRecord(records, s.id, job.where);
  if (const std::string stale = staleIdReason(job, s.id); !stale.empty()) {
    s.state = "stale", s.replan = true, s.error = job.where + ": " + stale;
    return s;
  }
  const OutputOrigin made = outputOrigin(out / job.output);
  if (made.id == s.id) return s.state = "done", s;
  if (s.record && s.record->state == "failed") return s.error = s.record->error, s;
  if (!made.id.empty()) {
    s.state = "stale";
    const std::string where = fmt::format("{}:{}", manifestPath, job.line);
    s.error = !made.job.empty() && made.job != where
                  ? fmt::format(
                        "{}: {} was made by job {} of another manifest ({}), not this job's {} (run "
                        "--force replaces it)",
                        job.where, job.output, made.id, made.job, s.id)
                  : fmt::format("{}: {} was made by job {}, not this job's {} (run again to render it)", job.where,
                                job.output, made.id, s.id);
    return s;
  }
  if (const std::optional<ClaimOwner> owner = liveClaim(out, job.output, kDefaultClaimLeaseSeconds)) {
    s.state = "running";  // a live run holds its claim
    s.error = fmt::format("{}: being rendered by {} pid {} since {}", job.where, owner->host, owner->pid, owner->time);
    return s;
  }
  s.state = "missing";
  return s;
}

json toJson(const JobState& s) {
  json j = {{"line", s.job->line}, {"output", s.job->output}, {"id", s.id}, {"state", s.state}};
  if (!s.error.empty()) j["error"] = s.error;
  if (s.record) j["record"] = toJson(*s.record);
  return j;
}

// One row per job, for a spreadsheet: its line, output, id, state, error and its latest record's numbers.
std::string csvText(const std::vector<JobState>& states) {
  std::string text = "line,output,id,state,error,seconds,device_ms,device,host,time,warnings\n";
  for (const JobState& s : states) {
    const StatusRecord* r = s.record;
    std::string warnings;
    if (r)
      for (const std::string& w : r->warnings) warnings += (warnings.empty() ? "" : "; ") + w;
    text += fmt::format("{},{},{},{},{},{},{},{},{},{},{}\n", s.job->line, csvField(s.job->output), s.id, s.state,
                        csvField(s.error), r ? fmt::format("{:.3f}", r->seconds) : "",
                        r && r->deviceMs > 0 ? fmt::format("{:.3f}", r->deviceMs) : "", csvField(r ? r->device : ""),
                        csvField(r ? r->host : ""), r ? r->time : "", csvField(warnings));
  }
  return text;
}

void printText(const StatusOptions& o, const std::vector<JobState>& states, const std::map<std::string, size_t>& n) {
  fmt::print("{}: {} jobs: {} done, {} stale, {} failed, {} missing{}\n", o.manifest, states.size(), n.at("done"),
             n.at("stale"), n.at("failed"), n.at("missing"),
             n.at("running") ? fmt::format(", {} running", n.at("running")) : "");
  for (const JobState& s : states) {
    if (s.state == "failed" || s.state == "stale" || s.state == "running") fmt::print("  {:<7} {}\n", s.state, s.error);
    if (s.state == "missing") fmt::print("  missing {} ({})\n", s.job->where, s.job->output);
  }
}

int run(const StatusOptions& o) {
  const std::vector<ManifestJob> jobs = readManifest(o.manifest, o.out);
  const std::map<std::string, StatusRecord> records = latestRecords(o.out);
  SceneCache scenes;
  const std::string manifestPath = fs::absolute(o.manifest).lexically_normal().string();
  std::vector<JobState> states;
  std::map<std::string, size_t> counts{{"done", 0}, {"stale", 0}, {"failed", 0}, {"missing", 0}, {"running", 0}};
  bool replan = false;
  for (const ManifestJob& job : jobs) {
    states.push_back(stateOf(job, records, scenes, o.out, manifestPath));
    ++counts[states.back().state];
    replan |= states.back().replan;
  }
  if (o.json) {
    json report = {{"manifest", o.manifest},       {"out", o.out},
                   {"jobs", states.size()},        {"done", counts["done"]},
                   {"stale", counts["stale"]},     {"failed", counts["failed"]},
                   {"missing", counts["missing"]}, {"running", counts["running"]},
                   {"states", json::array()}};
    for (const JobState& s : states) report["states"].push_back(toJson(s));
    std::cout << report.dump(2) << "\n";
  } else {
    printText(o, states, counts);
  }
  if (!o.csv.empty()) writeFileAtomically(o.csv, csvText(states));  // throws naming the file
  if (counts["failed"] || replan) return kExitPermanent;
  return counts["missing"] || counts["stale"] || counts["running"] ? kExitRetryable : 0;
}

}  // namespace

Command addStatusCommand(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("status", "Which jobs of a manifest are done, stale, failed or missing");
  auto o = std::make_shared<StatusOptions>();
  sub->add_option("manifest", o->manifest, "Manifest (JSON Lines)")->required();
  sub->add_option("--out", o->out, "The folder `penumbra run --out` wrote to")->required();
  sub->add_flag("--json", o->json, "Every job's state as JSON on stdout");
  sub->add_option("--csv", o->csv,
                  "Also write one row per job (line, output, id, state, error, its record's times) here");
  return {sub, [o] { return run(*o); }};
}

}  // namespace penumbra::cli
