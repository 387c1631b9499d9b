// `penumbra run jobs.jsonl --out DIR [--shard auto|I/N] ...`: renders a manifest's jobs (or one shard's) in one
// process on one OpenCL context (kernels built once), the scenes and their Renderers kept between jobs (buffers
// reused). Outputs are written through temporary files and carry the job id; a job whose output already carries it
// is skipped. Each outcome is a status record (job_status.h). Exit 0 all done, 65 a job failed for good, 75 stopped
// early (SIGTERM/SIGINT, --time-limit, a write the storage refused: ENOSPC, EDQUOT, EIO): run again; 74 the status
// log cannot be written for another reason.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <optional>
#include <set>

#include <CLI/CLI.hpp>

#include "host/cl/error.h"
#include "host/io/atomic_file.h"
#include "tools/cli/claim.h"
#include "tools/cli/commands.h"
#include "tools/cli/job_status.h"
#include "tools/cli/output_writer.h"
#include "tools/cli/progress.h"
#include "tools/cli/scene_cache.h"
#include "tools/cli/shard.h"
#include "tools/cli/stop_signal.h"

namespace penumbra::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct RunOptions {
  std::string manifest, out, shard, device, timeLimit, claimLease;  // claimLease "": kDefaultClaimLeaseSeconds
  std::optional<size_t> shardCount;
  bool skipExisting = true, onlyFailed = false, quiet = false, dryRun = false, force = false;
  size_t maxFailures = 0;  // 0: no limit
  double leaseSeconds = 0;   // claimLease, parsed
  std::string manifestPath;  // the manifest's absolute path: outputs name the line that made them
};

// What one process does: the device opened at the first render, the scenes kept, the tallies.
struct Batch {
  Batch(const RunOptions& o, const Shard& shard, double limit, size_t jobs)
      : options(o),
        log(o.out, shard.label()),
        timeLimit(limit),
        total(jobs),
        label(shard.label()),
        progress(jobs, !o.quiet, "penumbra run") {}
  const RunOptions& options;
  StatusLog log;
  SceneCache scenes;
  std::unique_ptr<Context> ctx;
  std::string device;    // the context's device name, once opened
  double timeLimit = 0;  // seconds, 0: none
  size_t rendered = 0, skipped = 0, failed = 0, claimed = 0;  // claimed: left to the live run that holds them
  double longestJob = 0;                // seconds: the estimate --time-limit plans with
  OutputWriter writer;                  // the last rendered job's outputs, written while the next one renders
  std::optional<StatusRecord> writing;  // that job's record, appended once its outputs are written
  std::optional<Claim> writingClaim;    // and its claim, released once they are
  Clock::time_point writingSince;       // when that job started
  std::string storageError;             // a write the storage refused (full, quota, I/O): the shard stops
  size_t total;                         // the shard's jobs
  std::string label;                    // the shard's
  Progress progress;                    // a bar on a terminal, else a line every 5 % or 30 s
  Clock::time_point started = Clock::now(), lastLine = Clock::now();
  size_t lastLineDone = 0;
};

// Jobs done of the shard's, failures, the rate and the time left at it: redrawn on a terminal, else a line at every
// 5 % and at least every 30 s while jobs finish.
void reportProgress(Batch& batch) {
  const size_t done = batch.rendered + batch.skipped + batch.failed;
  const Clock::time_point now = Clock::now();
  const double elapsed = std::chrono::duration<double>(now - batch.started).count();
  const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0;
  const double left = rate > 0 ? static_cast<double>(batch.total - std::min(done, batch.total)) / rate : 0;
  const std::string what = fmt::format("{}/{} jobs ({} failed), {:.2f} jobs/s, about {:.0f} s left", done, batch.total,
                                       batch.failed, rate, std::ceil(left));
  if (batch.progress.terminal()) return batch.progress.update(done, what);
  if (batch.options.quiet) return;
  const size_t step = std::max<size_t>(batch.total / 20, 1);
  if (done == batch.total || done >= batch.lastLineDone + step || now - batch.lastLine >= std::chrono::seconds(30)) {
    fmt::print(stderr, "penumbra run: shard {}: {}\n", batch.label, what);
    batch.lastLine = now, batch.lastLineDone = done;
  }
}

// A rendered job's outputs, for the writer.
struct Rendered {
  ImageOutputPlan output;
  Image image;
  std::optional<Claim> claim;
};

// "90", "90s", "15m", "2h", "1:30:00" (H:MM:SS) or "30:00" (M:SS): seconds.
double parseDuration(const std::string& text, const char* option = "--time-limit") {
  double total = 0;
  size_t pos = 0;
  const auto fail = [&] {
    return std::invalid_argument(fmt::format("{} {}: use 90s, 15m, 2h or H:MM:SS", option, text));
  };
  try {
    if (text.find(':') != std::string::npos) {  // [H:]M:SS, every field a non-negative number, M and S below 60
      for (size_t start = 0, field = 0; start <= text.size(); ++field) {
        const size_t colon = std::min(text.find(':', start), text.size());
        const double value = std::stod(text.substr(start, colon - start), &pos);
        if (pos != colon - start || !std::isfinite(value) || value < 0 || (field > 0 && value >= 60)) throw fail();
        total = total * 60 + value;
        start = colon + 1;
      }
      if (!(total > 0)) throw fail();
      return total;
    }
    total = std::stod(text, &pos);
    if (!std::isfinite(total)) throw fail();
  } catch (const std::logic_error&) {
    throw fail();
  }
  const std::string unit = text.substr(pos);
  const double scale = unit.empty() || unit == "s" ? 1 : unit == "m" ? 60 : unit == "h" ? 3600 : 0;
  if (scale == 0 || total <= 0) throw fail();
  return total * scale;
}

// The shard's jobs, those of one scene together (first appearance order) so each scene is loaded once.
std::vector<const ManifestJob*> shardJobs(const std::vector<ManifestJob>& jobs, const Shard& shard,
                                          const RunOptions& o) {
  const std::map<std::string, StatusRecord> records = o.onlyFailed ? latestRecords(o.out) : decltype(records){};
  std::vector<const ManifestJob*> mine;
  std::map<std::string, size_t> sceneOrder;
  for (const ManifestJob& job : jobs) {
    if (!shard.owns(job.index)) continue;
    if (o.onlyFailed && job.error.empty()) {  // a bad line fails every time: it counts as failed
      const StatusRecord* record = findRecord(records, job.id, job.where);
      if (record == nullptr || record->state != "failed") continue;
    }
    mine.push_back(&job);
    sceneOrder.emplace(job.error.empty() ? sceneKey(job.options.view) : "", sceneOrder.size());
  }
  std::stable_sort(mine.begin(), mine.end(), [&](const ManifestJob* a, const ManifestJob* b) {
    const auto order = [&](const ManifestJob* j) {
      return sceneOrder[j->error.empty() ? sceneKey(j->options.view) : ""];
    };
    return order(a) < order(b);
  });
  return mine;
}

// Temporary files ("<name>.tmp-<hex>", PendingFile) that a run killed while writing left beside the shard's outputs:
// one scan per output folder, whatever the number of jobs; other shards' files are never touched.
void removeStaleTemporaries(const std::vector<const ManifestJob*>& jobs, const RunOptions& o) {
  std::map<fs::path, std::set<std::string>> outputs;  // folder -> names of the shard's outputs there
  for (const ManifestJob* job : jobs) {
    if (!job->error.empty()) continue;
    if (claimIsLive(o.out, job->output, o.leaseSeconds)) continue;  // its owner runs: the temporaries are its own
    const ImageOutputPlan plan = planImageOutput(job->options.output);
    for (const std::optional<fs::path>& path : {plan.exr, plan.png})
      if (path) outputs[path->parent_path()].insert(path->filename().string());
  }
  std::error_code error;
  for (const auto& [folder, names] : outputs)
    for (const fs::directory_entry& entry : fs::directory_iterator(folder.empty() ? "." : folder, error)) {
      const std::string name = entry.path().filename().string();
      const size_t tmp = name.rfind(".tmp-");
      if (tmp != std::string::npos && names.count(name.substr(0, tmp)) != 0) fs::remove(entry.path(), error);
    }
}

// Renders one job into `rendered` (or finds it done); a failure of the job alone comes back as the record's error.
StatusRecord runJob(Batch& batch, const ManifestJob& job, std::optional<Rendered>& rendered) {
  StatusRecord record;
  record.id = job.id, record.where = job.where, record.output = job.output;
  record.state = "failed", record.exit = kExitPermanent;
  if (!job.error.empty()) return record.error = job.error, record;
  try {
    const std::string id = jobId(job, batch.scenes.digest(job.options.view));
    if (const std::string stale = staleIdReason(job, id); !stale.empty()) throw std::runtime_error(stale);
    record.id = id, record.state = "done", record.exit = 0;
    ImageOutputPlan output = planImageOutput(job.options.output);
    const std::string where = fmt::format("{}:{}", batch.options.manifestPath, job.line);
    const OutputOrigin origin = outputOrigin(*output.exr);
    if (batch.options.skipExisting && origin.id == id) return record.state = "skipped", record;
    // Another manifest's line made it (not an older plan of this one): replaced only with --force.
    if (!batch.options.force && !origin.job.empty() && origin.job != where)
      throw std::runtime_error(fmt::format("{} was made by job {} ({}); this is job {} ({}): --force replaces it",
                                           job.output, origin.id, origin.job, id, where));
    ClaimOwner holder;
    std::optional<Claim> claim = Claim::take(batch.options.out, job.output, where, batch.options.leaseSeconds, holder);
    if (!claim) {  // a live run renders it: left to that run
      record.state = "claimed";
      record.error = fmt::format("{}: claimed by {} pid {} since {} (its job {})", job.where, holder.host, holder.pid,
                                 holder.time, holder.job);
      return record;
    }
    if (batch.options.skipExisting && outputJobId(*output.exr) == id)  // finished while we looked
      return record.state = "skipped", record;
    SceneCache::Entry& scene = batch.scenes.get(job.options.view);
    const FramePlan plan = planFrame(job.options, chooseTechnique(job.options), scene.scene);
    if (!batch.ctx) {
      batch.ctx = std::make_unique<Context>(batch.options.device);
      batch.device = batch.ctx->info().name;
    }
    RenderResult result = renderFrame(batch.scenes.renderer(scene, *batch.ctx), job.options, scene.scene, plan,
                                      FrameDownload::Image, false);
    for (const std::string& warning : result.warnings)  // named by their job, and kept in its record
      fmt::print(stderr, "penumbra: warning: {}: {}\n", job.where, warning);
    record.warnings = std::move(result.warnings);
    result.image.attributes()[kJobIdAttribute] = id;
    result.image.attributes()[kJobWhereAttribute] = where;
    for (const PassTime& pass : result.passes) record.deviceMs += pass.ms;
    rendered = Rendered{std::move(output), std::move(result.image), std::move(claim)};
  } catch (const NoDeviceError&) {
    throw;  // no job can run: the whole run stops (exit 69)
  } catch (const std::exception& e) {
    record.state = "failed", record.exit = kExitPermanent, record.error = job.where + ": " + e.what();
  }
  return record;
}

// The job's outcome counted, reported and recorded.
void finishJob(Batch& batch, StatusRecord record, Clock::time_point since) {
  record.seconds = std::chrono::duration<double>(Clock::now() - since).count();
  record.device = batch.device;
  if (record.state == "done") batch.longestJob = std::max(batch.longestJob, record.seconds);
  (record.state == "done"      ? batch.rendered
   : record.state == "skipped" ? batch.skipped
   : record.state == "claimed" ? batch.claimed
                               : batch.failed)++;
  if (record.state == "claimed") {
    if (!batch.options.quiet) fmt::print(stderr, "penumbra: {}\n", record.error);
  } else if (!record.error.empty()) {
    batch.progress.finish();  // the message on its own line, not inside the bar
    fmt::print(stderr, "penumbra: {}\n", record.error);
  }
  batch.log.append(std::move(record));
  reportProgress(batch);
}

// The write in flight, waited for and recorded (a failed write fails its job).
void settleWrite(Batch& batch) {
  if (!batch.writing) return;
  StatusRecord record = std::move(*batch.writing);
  batch.writing.reset();
  const std::optional<Claim> claim = std::move(batch.writingClaim);  // released when this returns
  batch.writingClaim.reset();
  if (const OutputWriter::Outcome written = batch.writer.finish(); !written.error.empty()) {
    record.state = "failed", record.exit = kExitPermanent, record.error = record.where + ": " + written.error;
    // No space, a quota, an I/O error: not the job's fault, and every job after it would fail alike.
    if (isStorageError(written.errorNumber)) record.exit = kExitRetryable, batch.storageError = written.error;
  }
  finishJob(batch, std::move(record), batch.writingSince);
}

enum class Stop { None, Signal, TimeLimit, Failures, Storage };

// Runs the jobs until done, a stop signal, the deadline or too many failures; counts the jobs left. Job k renders
// while job k-1's outputs are written.
Stop renderJobs(Batch& batch, const std::vector<const ManifestJob*>& jobs, const StopSignals& stop, size_t& left) {
  const Clock::time_point start = Clock::now();
  for (size_t i = 0; i < jobs.size(); ++i) {
    left = jobs.size() - i;
    const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    if (stop.requested()) return Stop::Signal;
    if (batch.timeLimit > 0 && elapsed + batch.longestJob > batch.timeLimit) return Stop::TimeLimit;
    if (batch.options.maxFailures > 0 && batch.failed >= batch.options.maxFailures) return Stop::Failures;
    if (!batch.storageError.empty()) return Stop::Storage;
    const Clock::time_point since = Clock::now();
    std::optional<Rendered> rendered;
    StatusRecord record = runJob(batch, *jobs[i], rendered);
    if (!rendered) {
      finishJob(batch, std::move(record), since);
      continue;
    }
    settleWrite(batch);
    batch.writer.start(std::move(rendered->output), std::move(rendered->image));
    batch.writing = std::move(record), batch.writingSince = since;
    batch.writingClaim = std::move(rendered->claim);
  }
  left = 0;
  return Stop::None;
}

Stop runJobs(Batch& batch, const std::vector<const ManifestJob*>& jobs, const StopSignals& stop, size_t& left) {
  const Stop result = renderJobs(batch, jobs, stop, left);
  settleWrite(batch);
  return result == Stop::None && !batch.storageError.empty() ? Stop::Storage : result;
}

// What `run` checks of a job before it needs a device, for --dry-run: its line, its scene (found and parsed), its id
// against the one it has now, its output path and its frame (size, camera, light, technique); "" when it would run.
std::string checkJob(SceneCache& scenes, const ManifestJob& job) {
  if (!job.error.empty()) return job.error;
  try {
    const std::string id = jobId(job, scenes.digest(job.options.view));
    if (const std::string stale = staleIdReason(job, id); !stale.empty()) return job.where + ": " + stale;
    planImageOutput(job.options.output);
    SceneCache::Entry& scene = scenes.get(job.options.view);
    planFrame(job.options, chooseTechnique(job.options), scene.scene);
    return {};
  } catch (const std::exception& e) {
    return job.where + ": " + e.what();
  }
}

int run(RunOptions o) {
  const Shard shard = parseShard(o.shard, o.shardCount, [](const char* name) { return std::getenv(name); });
  const double timeLimit = o.timeLimit.empty() ? 0 : parseDuration(o.timeLimit);  // usage errors before any work
  o.leaseSeconds = o.claimLease.empty() ? kDefaultClaimLeaseSeconds : parseDuration(o.claimLease, "--claim-lease");
  o.manifestPath = fs::absolute(o.manifest).lexically_normal().string();
  const std::vector<ManifestJob> jobs = readManifest(o.manifest, o.out);
  const std::vector<const ManifestJob*> mine = shardJobs(jobs, shard, o);
  if (o.dryRun) {  // every job checked as run would before rendering; the bad ones named, exit 65
    SceneCache scenes;
    size_t bad = 0;
    for (const ManifestJob* job : mine) {
      const std::string error = checkJob(scenes, *job);
      const std::string_view why =
          std::string_view(error).substr(error.rfind(job->where + ": ", 0) == 0 ? job->where.size() + 2 : 0);
      fmt::print("{} {}\n", job->where, error.empty() ? job->output : fmt::format("refused: {}", why));
      bad += !error.empty();
    }
    if (bad > 0)
      fmt::print(stderr, "penumbra run --dry-run: shard {}: {} of {} jobs would fail\n", shard.label(), bad,
                 mine.size());
    return bad > 0 ? kExitPermanent : 0;
  }
  removeStaleTemporaries(mine, o);
  const StopSignals signals;
  Batch batch(o, shard, timeLimit, mine.size());
  size_t left = 0;
  const Stop stop = runJobs(batch, mine, signals, left);
  batch.progress.finish();
  const std::string why = stop == Stop::Signal      ? fmt::format(", {} left ({})", left, signals.name())
                          : stop == Stop::TimeLimit ? fmt::format(", {} left (--time-limit {})", left, o.timeLimit)
                          : stop == Stop::Failures  ? fmt::format(", {} left (--max-failures {})", left, o.maxFailures)
                          : stop == Stop::Storage
                              ? fmt::format(", {} left (the storage refused a write: {})", left, batch.storageError)
                              : "";
  if (!o.quiet || stop != Stop::None || batch.failed)
    fmt::print(stderr, "penumbra run: shard {}: {} jobs: {} rendered, {} skipped, {} failed{}{}\n", shard.label(),
               mine.size(), batch.rendered, batch.skipped, batch.failed,
               batch.claimed ? fmt::format(", {} claimed by other runs", batch.claimed) : "", why);
  if (stop == Stop::Signal || stop == Stop::TimeLimit || stop == Stop::Storage) return kExitRetryable;
  return batch.failed ? kExitPermanent : 0;
}

}  // namespace

Command addRunCommand(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("run", "Render a manifest's jobs (or one shard's) in one process, resumably");
  auto o = std::make_shared<RunOptions>();
  sub->add_option("manifest", o->manifest, "Manifest: JSON Lines, one job per line (penumbra plan writes one)")
      ->required();
  sub->add_option("--out", o->out,
                  "Folder the jobs' outputs are relative to; status records go to its "
                  "penumbra-status/")
      ->required();
  sub->add_option("--shard", o->shard,
                  "I/N: the jobs k with k mod N = I; auto: I and N from SLURM_ARRAY_TASK_ID/_COUNT (_MIN, _STEP), "
                  "JOB_COMPLETION_INDEX or AWS_BATCH_JOB_ARRAY_INDEX");
  sub->add_option("--shard-count", o->shardCount, "N for --shard auto where the environment has no count");
  sub->add_flag("--skip-existing,!--no-skip-existing", o->skipExisting,
                "Skip a job whose output carries its id (default; --no-skip-existing renders everything)");
  sub->add_option("--max-failures", o->maxFailures, "Stop after K failed jobs (0: never)")
      ->check(CLI::Range(size_t{0}, size_t{1} << 40))
      ->capture_default_str();
  sub->add_flag("--only-failed", o->onlyFailed, "Only the jobs whose last status record is a failure");
  sub->add_option("--time-limit", o->timeLimit,
                  "Start no job that might not finish within this wall time (90s, 15m, 2h, H:MM:SS); exit 75 with "
                  "jobs left");
  sub->add_option("--device", o->device, "OpenCL device: auto, cpu, gpu, a name substring, or P:D")
      ->envname("PENUMBRA_DEVICE");
  sub->add_flag("--dry-run", o->dryRun,
                "Check the shard's jobs as run would (scene, id, size, camera, technique) and print them "
                "(manifest:line output, or 'refused: why'), in the order it takes them; render nothing; exit 65 when "
                "a job would fail");
  sub->add_flag("-q,--quiet", o->quiet, "No summary line unless jobs failed or were left");
  sub->add_flag("--force", o->force, "Replace an output that another manifest's job made (refused otherwise)");
  sub->add_option("--claim-lease", o->claimLease,
                  fmt::format("How long another host's claim on a job holds (90s, 15m, 2h, H:MM:SS; default {}h); "
                              "this host's hold while their process runs",
                              kDefaultClaimLeaseSeconds / 3600));
  return {sub, [o] { return run(*o); }};
}

}  // namespace penumbra::cli
