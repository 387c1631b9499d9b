// The selftest's driver: the check list, one check run with its device time and its failures caught, the report's
// rows and the device report.
#include "tools/selftest/selftest.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <nlohmann/json.hpp>

#include "host/cl/device.h"
#include "host/cl/error.h"
#include "host/cl/profiler.h"
#include "host/stages/blur.h"
#include "host/stages/pyramid.h"
#include "host/stages/sat.h"
#include "raster/plan.h"

namespace penumbra::selftest {

std::vector<Check> checks(Depth depth, const std::string& filter) {
  std::vector<Check> all;
  addStageChecks(all);
  addBlurChecks(all);
  addRasterChecks(all);
  addVssmChecks(all);
  addTechniqueChecks(all);
  addCallerChecks(all);
  std::vector<std::string> wanted;  // the filter's comma-separated parts
  for (size_t start = 0; start <= filter.size();) {
    const size_t comma = std::min(filter.find(',', start), filter.size());
    if (comma > start) wanted.push_back(filter.substr(start, comma - start));
    start = comma + 1;
  }
  std::vector<Check> out;
  for (Check& check : all) {
    if (depth == Depth::Quick && !check.quick) continue;
    const std::string id = check.stage + "/" + check.name;
    if (!wanted.empty() && std::none_of(wanted.begin(), wanted.end(),
                                        [&](const std::string& w) { return id.find(w) != std::string::npos; }))
      continue;
    out.push_back(std::move(check));
  }
  return out;
}

Row run(Context& ctx, const Check& check) {
  Row row;
  row.stage = check.stage, row.name = check.name, row.status = "error";
  Profiler profiler;
  const auto start = std::chrono::steady_clock::now();
  try {
    ProfilerScope scope(ctx, profiler);
    const Measured measured = check.run(ctx);
    ctx.finish();
    const ref::Comparison& c = measured.comparison;
    row.status = c.pass() ? "pass" : "fail";
    row.count = c.count, row.mismatches = c.mismatches;
    row.error = c.worstError, row.tolerance = c.worstAllowed;
    row.unit = measured.unit;
    if (!c.pass()) row.message = fmt::format("{} of {} outside the margin{}", c.mismatches, c.count, c.report);
  } catch (const NotApplicable& e) {
    row.status = "skipped";
    row.message = e.what();
  } catch (const BuildError& e) {
    row.message = e.what();
    row.buildLog = e.log();
  } catch (const std::exception& e) {
    row.message = e.what();
  }
  try {
    ctx.finish();  // what a failed check left in flight, before its buffers go
    row.deviceMs = profiler.totalMs();
  } catch (const std::exception& e) {
    if (row.message.empty()) row.message = e.what();
    row.status = "error";
  }
  row.wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return row;
}

namespace {

// JSON has no infinity: an infinite error (a NaN or infinity where the reference has none) is written as null.
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace

nlohmann::json toJson(const Row& row) {
  nlohmann::json out = {{"stage", row.stage},
                        {"case", row.name},
                        {"status", row.status},
                        {"elements", row.count},
                        {"mismatches", row.mismatches},
                        {"max_error", number(row.error)},
                        {"tolerance", number(row.tolerance)},
                        {"device_ms", row.deviceMs},
                        {"wall_ms", row.wallMs}};
  if (!row.unit.empty()) out["unit"] = row.unit;
  if (!row.message.empty()) out["message"] = row.message;
  if (!row.buildLog.empty()) out["build_log"] = row.buildLog;
  return out;
}

nlohmann::json deviceReport(const Context& ctx) {
  const DeviceInfo& d = ctx.info();
  nlohmann::json used = nlohmann::json::array();
  for (const char* name : {"cl_khr_fp64", "cl_khr_fp16", "cl_khr_int64_base_atomics", "cl_khr_subgroups"})
    if (d.hasExtension(name)) used.push_back(name);
  const raster::WorkGroups raster = raster::workGroupsFor(d);
  const ImageShape map{2048, 2048, 2};
  const char* overrideLayouts = std::getenv("PENUMBRA_LAYOUTS");
  const char* overrideLocal = std::getenv("PENUMBRA_LOCAL_MEM_LIMIT");
  // Everything `penumbra devices --json` says of it, and what the selftest adds.
  nlohmann::json report = toJson(d);
  report["extensions_used"] = used;
  report["work_group_layouts"] = {
      {"table", d.layouts.empty() ? (d.cpuLayouts() ? "cpu (the device's own)" : "gpu (the device's own)")
                                  : d.layouts + " (forced)"},
      {"raster",
       {{"setup", raster.setup},
        {"bin", raster.bin},
        {"gbuffer", raster.gbuffer},
        {"fine", raster.fine == 0 ? "a group per tile" : fmt::format("{} tiles per group", raster.fine)},
        {"coarse", raster.coarse == 0 ? "a group per bin" : fmt::format("{} bins per group", raster.coarse)},
        {"bin_run", raster.binRun}}},
      {"blur", resolveBlurLayout(BlurLayout::Auto, d, map, 6) == BlurLayout::Runs ? "runs" : "tiles"},
      {"sat", resolveSatAlgorithm(SatAlgorithm::Auto, d) == SatAlgorithm::Lines ? "lines" : "tiled"},
      {"pyramid", describePyramidTuning(d)}};
  report["overrides"] = {
      {"PENUMBRA_LAYOUTS", overrideLayouts ? nlohmann::json(overrideLayouts) : nlohmann::json(nullptr)},
      {"PENUMBRA_LOCAL_MEM_LIMIT", overrideLocal ? nlohmann::json(overrideLocal) : nlohmann::json(nullptr)}};
  return report;
}

}  // namespace penumbra::selftest
