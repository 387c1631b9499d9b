// `penumbra selftest [--device SPEC] [--quick | --full] [--filter TEXT] [--json FILE] [--list]`: every stage, the
// rasterizer and every technique checked on the user's device against the double-precision references, one row per
// check (tools/selftest/). Exit 0 only when every check passed (skipped checks do not fail it), 1 otherwise, 69 when
// there is no OpenCL device.
#include "tools/selftest/selftest.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "host/io/atomic_file.h"
#include "host/version.h"
#include "tools/cli/commands.h"
#include "tools/selftest/kernels/probes.h"

namespace penumbra::cli {
namespace {

struct SelftestOptions {
  std::string device, json, filter;
  bool quick = false, full = false, list = false;
};

std::string errorText(const selftest::Row& row) {
  if (row.status == "skipped" || row.status == "error") return "";
  const auto number = [](double v) { return std::isfinite(v) ? fmt::format("{:.3g}", v) : std::string("inf"); };
  return fmt::format("{} <= {}{}", number(row.error), number(row.tolerance), row.unit.empty() ? "" : " " + row.unit);
}

int runSelftest(const SelftestOptions& o) {
  const selftest::Depth depth = o.full ? selftest::Depth::Full : selftest::Depth::Quick;
  const std::vector<selftest::Check> checks = selftest::checks(depth, o.filter);
  if (o.list) {
    for (const selftest::Check& c : checks) fmt::print("{}/{}\n", c.stage, c.name);
    return 0;
  }
  if (checks.empty()) throw std::invalid_argument(fmt::format("selftest: no check matches '{}'", o.filter));
  Context ctx(o.device);
  withProbeKernels(ctx);  // the checks' entry points into the library's kernels (SAT boxes, VSSM receivers, ...)
  fmt::print("penumbra {} selftest ({}, {} checks) on {} ({}, driver {})\n", version(), o.full ? "full" : "quick",
             checks.size(), ctx.info().name, ctx.info().platformName, ctx.info().driverVersion);
  const auto start = std::chrono::steady_clock::now();
  std::vector<selftest::Row> rows;
  size_t passed = 0, skipped = 0, errors = 0;
  for (const selftest::Check& check : checks) {
    rows.push_back(selftest::run(ctx, check));
    const selftest::Row& r = rows.back();
    passed += r.status == "pass", skipped += r.status == "skipped", errors += r.status == "error";
    fmt::print("[{:>4}/{}] {:<9} {:<40} {:<7} {:<30} {:>9.3f} ms\n", rows.size(), checks.size(), r.stage, r.name,
               r.status, errorText(r), r.deviceMs);
    if (r.status != "pass" && !r.message.empty()) fmt::print("           {}\n", r.message);
    std::fflush(stdout);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const size_t failed = rows.size() - passed - skipped;
  fmt::print("selftest: {} of {} checks passed, {} skipped, {} failed{} on {} ({:.1f} s)\n", passed, rows.size(),
             skipped, failed, errors != 0 ? fmt::format(" ({} of them errors)", errors) : "", ctx.info().name, seconds);
  if (!o.json.empty()) {
    nlohmann::json list = nlohmann::json::array();
    for (const selftest::Row& r : rows) list.push_back(selftest::toJson(r));
    const nlohmann::json report = {{"penumbra", version()}, {"depth", o.full ? "full" : "quick"},
                                   {"filter", o.filter},    {"device", selftest::deviceReport(ctx)},
                                   {"seconds", seconds},    {"passed", passed},
                                   {"skipped", skipped},    {"failed", failed},
                                   {"errors", errors},      {"checks", list}};
    const std::filesystem::path path = o.json;
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    writeFileAtomically(path, report.dump(2) + "\n");  // throws naming the file (a full disk, a refused path)
  }
  return failed == 0 ? 0 : 1;
}

}  // namespace

Command addSelftestCommand(CLI::App& app) {
  CLI::App* sub = app.add_subcommand(
      "selftest", "Check every stage, the rasterizer and every technique on a device against the references");
  auto o = std::make_shared<SelftestOptions>();
  sub->add_option("--device", o->device, "OpenCL device (auto, cpu, gpu, a name, or P:D; default PENUMBRA_DEVICE)");
  auto* quick = sub->add_flag("--quick", o->quick, "One or two cases per stage and technique (the default)");
  sub->add_flag("--full", o->full, "Every case in which the test suite holds a device's output to a reference")
      ->excludes(quick);
  sub->add_option("--filter", o->filter, "Only the checks whose STAGE/CASE contains this text (several: a,b,...)");
  sub->add_option("--json", o->json, "Also write the rows and the device report as JSON here");
  sub->add_flag("--list", o->list, "List the checks that would run, and exit");
  return {sub, [o] { return runSelftest(*o); }};
}

}  // namespace penumbra::cli
