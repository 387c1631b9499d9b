// `penumbra bench SCENE --techniques LIST [--sweep PARAM=a,b,c]...`: every technique x parameter setting x light
// of the frame (each light alone, with the command line's techniques) rendered
// `--warmup` + `--runs` times with one Renderer (the technique's buffers kept, so the runs measure the steady state;
// with --interleave, round-robin over the settings with one Renderer each);
// per pass the median device time (OpenCL profiling events) beside its bandwidth floor (the pass's least bytes moved
// / the device's measured copy bandwidth), and the accuracy of the last run against a reference (given, or traced
// with Embree once and cached next to the output). Writes CSV (and JSON); progress on stderr.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string_view>

#include <CLI/CLI.hpp>

#include "tools/eval/bandwidth.h"
#include "host/cl/context.h"
#include "tools/eval/bench_report.h"
#include "tools/eval/bench_stats.h"
#include "tools/eval/sweep.h"
#include "host/io/atomic_file.h"
#include "host/io/exr.h"
#include "host/pipeline/frame_image.h"
#include "host/pipeline/memory_plan.h"
#include "host/pipeline/renderer.h"
#include "host/scene/light_names.h"
#include "host/scene/load.h"
#include "tools/cli/bench_jobs.h"
#include "tools/cli/bench_reference.h"
#include "tools/cli/bench_sequence.h"
#include "tools/cli/commands.h"
#include "tools/cli/progress.h"
#include "tools/cli/stop_signal.h"
#include "tools/cli/technique_options.h"
#include "tools/cli/view_options.h"
#include "tools/reference/reference.h"

namespace penumbra::cli {
namespace {

using Job = BenchJob;

// The tracer as a peer: an spp that is not 4k^2 under an area light is a usage error before any work; measured
// against a ground truth of no more samples than its own, it measures noise against noise (a warning).
void checkPeerSamples(const BenchOptions& o, const std::vector<Job>& jobs, const std::vector<Light>& lights) {
  if (std::none_of(lights.begin(), lights.end(), [](const Light& l) { return l.isArea(); })) return;
  for (const Job& job : jobs) {
    if (!isReferenceTechnique(*job.technique)) continue;
    try {
      reference::SampleLayout::fromSpp(job.params.getInt("spp"));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("--techniques reference: {}", e.what()));
    }
    if (!o.noReference && o.reference.empty() && job.params.getInt("spp") >= o.spp)
      fmt::print(stderr,
                 "bench: reference {} has no fewer samples than the ground truth (--spp {}): its error is "
                 "mostly the ground truth's own noise\n",
                 job.setting.label, o.spp);
  }
}

// What identifies a traced reference: a cached one is reused only when this matches its header.
std::string referenceKey(const BenchOptions& o, const Camera& camera, const std::vector<Light>& lights) {
  std::string forms;
  bool area = false;
  for (const Light& light : lights) {
    forms += (forms.empty() ? "" : ";") + lightLayer(light) + "=" + light.describe();
    area = area || light.isArea();
  }
  if (lights.size() == 1) forms = lights[0].describe();  // the single-light key as before: caches stay valid
  // A BLEND cutoff other than the default changes the scene: part of the key (absent otherwise, as before).
  const std::string blend =
      o.view.blendCutoff == LoadOptions{}.blendCutoff ? "" : fmt::format(" blend-cutoff={}", o.view.blendCutoff);
  return fmt::format("scene={} camera={} size={}x{} light={} spp={}{}", sceneProvenance(o.view),
                     cameraProvenance(camera), camera.width, camera.height, forms, area ? o.spp : 1, blend);
}

// The given reference, or the cached trace next to the output, or a fresh trace written there.
std::optional<Image> loadReference(const BenchOptions& o, Context& ctx, const Scene& scene, const Camera& camera,
                                   const std::vector<Light>& lights, std::string& path) {
  if (o.noReference) return std::nullopt;
  if (!o.reference.empty()) {
    path = o.reference;
    Image ref = readExr(path);
    if (ref.width() != camera.width || ref.height() != camera.height)
      throw std::runtime_error(fmt::format("{} is {}x{}, the bench renders {}x{}", path, ref.width(), ref.height(),
                                           camera.width, camera.height));
    return ref;
  }
  path = std::filesystem::path(o.output).replace_extension(".reference.exr").string();
  const std::string key = referenceKey(o, camera, lights);
  if (std::filesystem::exists(path)) {
    Image cached = readExr(path);
    auto it = cached.attributes().find("penumbra:bench-key");
    if (it != cached.attributes().end() && it->second == key) {
      if (!o.quiet) fmt::print(stderr, "bench: reusing the reference {}\n", path);
      return cached;
    }
  }
  for (const Light& light : lights)
    if (light.isArea()) reference::SampleLayout::fromSpp(o.spp);  // a bad --spp is a usage error
  if (!o.quiet) fmt::print(stderr, "bench: tracing the reference ({} spp) into {}\n", o.spp, path);
  reference::TraceSettings trace;
  trace.spp = o.spp;
  reference::ReferenceResult result = reference::renderReference(ctx, scene, camera, lights, trace);
  result.image.attributes()["penumbra:scene"] = sceneProvenance(o.view);
  result.image.attributes()["penumbra:bench-key"] = key;
  if (std::filesystem::path(path).has_parent_path())
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  writeExr(path, result.image);
  return std::move(result.image);
}

// Host wall times of one setting's frames: every timed run's and the first frame's.
struct WallTimes {
  std::vector<double> runs;
  std::optional<double> first;
};

void addRows(const BenchOptions& o, const Job& job, const Light& light, const RunSummary& summary, double bandwidth,
             const std::optional<ErrorMetrics>& metrics, const WallTimes& walls, std::vector<BenchRow>& rows) {
  BenchRow base{o.view.scene,
                job.technique->name,
                job.setting.label,
                job.params.describe(),
                {},
                0,
                0,
                0,
                {},
                {},
                lightLayer(light),
                {},
                {}};
  for (const PassSummary& pass : summary.passes) {
    BenchRow row = base;
    row.pass = pass.name, row.calls = pass.calls, row.ms = pass.ms, row.bytes = pass.bytes;
    row.floorMs = bandwidthFloorMs(pass.bytes, bandwidth);
    rows.push_back(std::move(row));
  }
  BenchRow total = base;
  total.pass = kTotalPass, total.ms = summary.totalMs, total.bytes = summary.totalBytes;
  for (const PassSummary& pass : summary.passes) total.calls += pass.calls;
  total.floorMs = bandwidthFloorMs(summary.totalBytes, bandwidth);
  total.metrics = metrics;
  if (!walls.runs.empty()) total.wallMs = median(walls.runs);
  total.firstWallMs = walls.first;
  rows.push_back(std::move(total));
}

void writeOutputs(const BenchOptions& o, const BenchMeta& meta, const std::vector<BenchRow>& rows) {
  for (const std::string& file : {o.output, o.json}) {
    if (file.empty()) continue;
    const std::filesystem::path path = file;
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    std::ostringstream text;
    if (file == o.output)
      writeBenchCsv(text, meta, rows);
    else
      text << benchJson(meta, rows).dump(2) << "\n";
    writeFileAtomically(path, text.str());  // throws naming the file (a full disk, a refused path)
  }
}

void printSummary(const BenchMeta& meta, const std::vector<BenchRow>& rows) {
  fmt::print("{}: {}x{}, median of {} runs after {} warm-up; copy bandwidth {:.2f} GB/s\n", meta.device, meta.width,
             meta.height, meta.runs, meta.warmup, meta.copyBytesPerSecond * 1e-9);
  fmt::print("  {:<8} {:<28} {:<10} {:>10} {:>10} {:>8} {:>10} {:>10} {:>9} {:>9} {:>9} {:>9} {:>9}\n", "technique",
             "setting", "light", "ms", "floor ms", "B/pixel", "wall ms", "1st wall", "mae", "pen. mae", "leak",
             "false sh.", "umbra");
  for (const BenchRow& r : rows) {
    if (r.pass != kTotalPass) continue;
    const auto metric = [&](double ErrorMetrics::*m) {
      return r.metrics ? fmt::format("{:.5f}", (*r.metrics).*m) : std::string("-");
    };
    const std::optional<double> perPixel = bytesPerPixel(meta, r);
    const auto wall = [](const std::optional<double>& ms) { return ms ? fmt::format("{:.1f}", *ms) : std::string("-"); };
    fmt::print("  {:<8} {:<28} {:<10} {:>10.3f} {:>10} {:>8} {:>10} {:>10} {:>9} {:>9} {:>9} {:>9} {:>9}\n",
               r.technique, r.setting, r.light, r.ms, r.floorMs ? fmt::format("{:.3f}", *r.floorMs) : "-",
               perPixel ? fmt::format("{:.0f}", *perPixel) : "-",
               wall(r.wallMs), wall(r.firstWallMs),
               metric(&ErrorMetrics::mae), metric(&ErrorMetrics::penumbraMae), metric(&ErrorMetrics::leak),
               metric(&ErrorMetrics::falseShadow), metric(&ErrorMetrics::umbraLight));
  }
}

int run(const BenchOptions& o) {
  const std::vector<Job> jobs = planBenchJobs(o);
  const std::optional<uint64_t> limit = memoryLimit(o.view);  // a bad value is a usage error before any work
  if (o.frames > 0) {
    for (const Job& job : jobs)
      if (isReferenceTechnique(*job.technique))
        throw std::invalid_argument("--techniques reference does not apply with --frames (each frame's reference is "
                                    "already traced)");
    return runSequenceBench(o, jobs);
  }
  const Scene scene = loadViewScene(o.view);
  const Camera camera = resolveCamera(o.view, scene);
  const std::vector<Light> lights = resolveLights(o.view, scene);
  for (const Job& job : jobs)  // before any work
    for (const Light& light : lights) refuseUnsupportedLight(light, *job.technique);
  checkPeerSamples(o, jobs, lights);
  if (!o.quiet)
    for (const Light& light : lights) fmt::print(stderr, "bench: {}\n", describeLightChoice(o.view, scene, {light}));
  Context ctx(o.device);

  BenchMeta meta;
  meta.device = fmt::format("{} ({}, {})", ctx.info().name, ctx.info().platformName, ctx.info().driverVersion);
  meta.width = camera.width, meta.height = camera.height, meta.runs = o.runs, meta.warmup = o.warmup;
  const std::optional<Image> ref = loadReference(o, ctx, scene, camera, lights, meta.reference);
  CompareSpec spec;
  if (o.noMask) spec.mask.clear();
  meta.masked = ref && !o.noMask && ref->find(spec.mask) != nullptr;
  const CopyBandwidth copy = measureCopyBandwidth(ctx);
  meta.copyBytesPerSecond = copy.bytesPerSecond;
  if (!o.quiet)
    fmt::print(stderr, "bench: copy bandwidth {:.2f} GB/s ({} MiB clEnqueueCopyBuffer, median {:.3f} ms)\n",
               copy.bytesPerSecond * 1e-9, copy.bufferBytes >> 20, copy.medianMs);

  // One cell per setting and light. Interleaved, every round renders each cell once, each with its own Renderer
  // (so each stays in its steady state), and a drift of the machine's speed during the run reaches every cell
  // alike; otherwise a cell's runs follow one another on one shared Renderer.
  struct Cell {
    const Job* job = nullptr;
    const Light* light = nullptr;
    std::string label;
    std::unique_ptr<Renderer> own;
    std::unique_ptr<reference::ReferenceRaster> peer;  // the reference's rasterizer, kept across its frames
    std::vector<std::vector<PassTime>> runs;
    WallTimes walls;
    RenderResult last;
    bool failed = false;
  };
  Renderer shared(ctx, scene);
  shared.setMemoryLimit(limit);
  std::vector<Cell> cells;
  for (const Job& job : jobs)
    for (const Light& light : lights) {  // each light alone, its own frames: per-light times and accuracy
      Cell& cell = cells.emplace_back();
      cell.job = &job, cell.light = &light;
      cell.label = fmt::format("{} {}{}", job.technique->name, job.setting.label,
                               lights.size() > 1 ? " light " + lightLayer(light) : "");
      if (o.interleave && cells.size() > 1 && !isReferenceTechnique(*job.technique))
        cell.own = std::make_unique<Renderer>(ctx, scene);
      if (cell.own) cell.own->setMemoryLimit(limit);
    }
  Progress progress(cells.size() * static_cast<size_t>(o.warmup + o.runs), !o.quiet);
  std::vector<std::string> failed;
  // SIGINT / SIGTERM: the frame in flight ends, the rows of every setting with a timed run are written, and the exit
  // code says which signal it was (130, 143); a second signal ends the process at once.
  const StopSignals stop;
  // Interleaved, every setting's renderer holds its buffers between rounds: they share the device's memory (or
  // --memory-limit), so each frame's plan must fit beside what the others' last plans hold (every technique at 8192²
  // at once took 23.7 GB of a 23 GiB machine before this budget). The first cell renders on `shared`.
  const uint64_t budget = limit ? std::min(*limit, ctx.info().globalMemBytes) : ctx.info().globalMemBytes;
  auto rendererOf = [&](Cell& cell) -> Renderer& { return cell.own ? *cell.own : shared; };
  auto heldByOthers = [&](const Cell& self, size_t* holders) {
    uint64_t held = 0;
    for (Cell& other : cells) {
      if (&other == &self || other.failed || isReferenceTechnique(*other.job->technique)) continue;
      const uint64_t bytes = rendererOf(other).plannedDeviceBytes();
      if (bytes > 0) held += bytes, ++*holders;
    }
    return held;
  };
  auto frame = [&](Cell& cell, int i) {
    if (cell.failed || stop.requested()) return;
    size_t holders = 0;
    uint64_t held = 0;
    try {
      const bool peer = isReferenceTechnique(*cell.job->technique);
      Renderer& renderer = rendererOf(cell);
      if (o.interleave && !peer) {
        held = heldByOthers(cell, &holders);
        renderer.setMemoryLimit(budget > held ? budget - held : 0);
      }
      const auto start = std::chrono::steady_clock::now();
      if (peer && !cell.peer) cell.peer = std::make_unique<reference::ReferenceRaster>(ctx, scene);
      cell.last = peer ? traceFrame(*cell.peer, camera, *cell.light, cell.job->params)
                       : benchFrame(renderer, camera, *cell.light, *cell.job);
      const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      if (!cell.walls.first) cell.walls.first = wall;
      if (i >= o.warmup) cell.runs.push_back(cell.last.passes), cell.walls.runs.push_back(wall);
    } catch (const std::exception& e) {  // one failing setting must not lose the others' measurements
      const bool crowded = holders > 0 && dynamic_cast<const MemoryError*>(&e) != nullptr;
      fmt::print(stderr, "bench: {} failed: {}{}\n", cell.label, e.what(),
                 crowded ? fmt::format(" (beside {} of {} held by {} other interleaved setting{}: fewer settings a "
                                       "run, or no --interleave)",
                                       formatBytes(held), formatBytes(budget), holders, holders == 1 ? "" : "s")
                         : "");
      failed.push_back(cell.label);
      cell.failed = true;
      cell.own.reset();
      cell.peer.reset();
    }
    progress.advance();
  };
  std::vector<BenchRow> rows;
  auto finish = [&](Cell& cell) {  // the cell's rows; its last image is freed
    if (cell.failed || cell.runs.empty()) return;  // a stop before its first timed run: nothing measured
    std::optional<ErrorMetrics> metrics;
    if (ref) metrics = compareImages(cell.last.image, *ref, lightSpec(spec, *cell.light, lights.size()));
    addRows(o, *cell.job, *cell.light, summariseRuns(cell.runs), copy.bytesPerSecond, metrics, cell.walls, rows);
    cell.last = {};
    cell.own.reset();
    cell.peer.reset();
  };
  if (o.interleave) {
    progress.announce(fmt::format("{} settings interleaved", cells.size()));
    for (int i = 0; i < o.warmup + o.runs && !stop.requested(); ++i)
      for (Cell& cell : cells) frame(cell, i);
    for (Cell& cell : cells) finish(cell);
  } else {
    for (Cell& cell : cells) {
      if (stop.requested()) break;
      progress.announce(cell.label);
      for (int i = 0; i < o.warmup + o.runs; ++i) frame(cell, i);
      finish(cell);
    }
  }
  progress.finish();
  writeOutputs(o, meta, rows);
  if (stop.requested()) {
    size_t measured = 0;
    for (const BenchRow& r : rows) measured += r.pass == kTotalPass;
    fmt::print(stderr, "bench: stopped by {}: wrote the {} of {} settings measured so far to {}\n", stop.name(),
               measured, cells.size(), o.output);
    return std::string_view(stop.name()) == "SIGINT" ? 130 : 143;
  }
  if (!o.quiet) {
    printSummary(meta, rows);
    fmt::print("wrote {}{}\n", o.output, o.json.empty() ? "" : " and " + o.json);
  }
  if (!failed.empty()) {
    fmt::print(stderr, "bench: {} of {} settings failed (left out of the results): {}\n", failed.size(),
               jobs.size() * lights.size(), fmt::join(failed, ", "));
    return 1;
  }
  return 0;
}

}  // namespace

Command addBenchCommand(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("bench", "Per-pass device times, bandwidth floors and accuracy per technique");
  auto o = std::make_shared<BenchOptions>();
  addViewOptions(sub, o->view);
  sub->add_option("--techniques", o->techniques, "Comma-separated techniques, or all")->capture_default_str();
  sub->add_option("--sweep", o->sweeps, "PARAM=a,b,c: one setting per value, for every technique with PARAM")
      ->take_all()
      ->allow_extra_args(false);
  sub->add_option("--runs", o->runs, "Timed runs per setting (the median is reported)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  sub->add_option("--warmup", o->warmup, "Untimed runs first")->check(CLI::Range(0, 100))->capture_default_str();
  sub->add_flag("--interleave", o->interleave,
                "Round-robin: each round renders every setting once (one Renderer each), so a drift in the machine's "
                "speed reaches all settings alike; for comparing settings' times");
  CLI::Option* path = sub->add_option("--camera-path", o->cameraPath,
                                      "A sequence: {\"orbit\": {...}} or {\"keyframes\": [...]} (docs/batch.md), or "
                                      "@FILE; with --frames, reports the temporal stability (shimmer) per setting");
  sub->add_option("--frames", o->frames, "The camera path's frames")->check(CLI::Range(2, 100000))->needs(path);
  path->needs("--frames")->excludes("--camera");
  sub->add_option("--reference", o->reference, "Reference EXR (penumbra reference) for the accuracy metrics");
  sub->add_option("--spp", o->spp, "Without --reference: trace one at this many samples per pixel, cached beside -o")
      ->capture_default_str();
  sub->add_flag("--no-reference", o->noReference, "Skip the accuracy metrics");
  sub->add_flag("--no-mask", o->noMask, "Count every covered pixel, ignoring the reference's lit.Y mask");
  sub->add_option("--device", o->device, "OpenCL device: auto, cpu, gpu, a name substring, or P:D")
      ->envname("PENUMBRA_DEVICE");
  sub->add_option("-o,--output", o->output, "Output CSV")->capture_default_str();
  sub->add_option("--json", o->json, "Also write the rows as JSON here");
  sub->add_flag("-q,--quiet", o->quiet, "No progress and no summary");
  sub->get_option("--reference")->excludes("--no-reference");
  addTechniqueOptions(sub, o->params);
  return {sub, [o] { return run(*o); }};
}

}  // namespace penumbra::cli
