// `penumbra selftest` (issue 42): the kernels proven on the user's own device. Every filtering stage, the rasterizer
// and every technique run small fixed cases and are compared with the double-precision references of
// tools/selftest/reference/ under the margins of tools/selftest/reference/tolerance.h, the ones the test suite holds
// PoCL to. No Embree, no GoogleTest, no source tree: the checks are compiled into the tool.
#pragma once

#include <functional>
#include <nlohmann/json_fwd.hpp>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "host/cl/context.h"
#include "tools/selftest/reference/tolerance.h"

namespace penumbra::selftest {

// --quick: one or two cases per stage and kind, the defaults' layouts (under a minute on PoCL on two cores);
// --full: every case the suite's kernel tests cover.
enum class Depth { Quick, Full };

// What a check measured: its outputs against their references (several outputs merge into one comparison), and what
// the error is measured in when that is not the output's own unit.
struct Measured {
  Measured(ref::Comparison c = {}, std::string u = {}) : comparison(std::move(c)), unit(std::move(u)) {}
  ref::Comparison comparison;
  std::string unit;
};

// Thrown by a check that does not apply to this device (fp64 tables without cl_khr_fp64, a layout whose local memory
// the device lacks): the row says "skipped" and why, and does not fail the selftest.
class NotApplicable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Check {
  std::string stage;   // "moments", "blur", "sat", "pyramid", "reduce", "raster", "vssm", "technique", "caller"
  std::string name;    // the case, e.g. "vsm_97x61" or "pcss_box_spot"
  bool quick = false;  // part of --quick (every check is part of --full)
  std::function<Measured(Context&)> run;
};

// One row of the report.
struct Row {
  std::string stage, name;
  // "pass", "fail" (outside the margin), "error" (an exception: a build, launch or host error) or "skipped"
  // (NotApplicable)
  std::string status;
  size_t count = 0, mismatches = 0;     // elements compared, elements outside their margin
  double error = 0.0, tolerance = 0.0;  // the worst element's error (the largest share of its margin) and that margin
  std::string unit;
  double deviceMs = 0.0;  // summed OpenCL profiling time of the check's launches and transfers
  double wallMs = 0.0;    // the check's wall time, kernel builds included
  std::string message;    // the first failures, or the exception's message
  std::string buildLog;   // a kernel that did not build on this device: its compiler log
};

// The checks of `depth`, in a fixed order (stages, the rasterizer, VSSM's kernel, the techniques); with `filter` (texts
// separated by commas), only those whose "stage/name" contains one of its texts.
std::vector<Check> checks(Depth depth, const std::string& filter = {});

// Runs one check on `ctx` and never throws: a failed build, launch or host error is a row with status "error".
Row run(Context& ctx, const Check& check);

nlohmann::json toJson(const Row& row);
// The device the checks ran on: what `penumbra devices --json` reports of it (platform, device, driver and OpenCL C
// versions, local memory, extensions, ...), the extensions penumbra uses, the work-group layouts chosen from the
// per-device tables and the overrides in force.
nlohmann::json deviceReport(const Context& ctx);

// The groups of checks, one file each.
void addStageChecks(std::vector<Check>& out);
void addBlurChecks(std::vector<Check>& out);  // blurred moments and ESM's log-space blur (blur_checks.h)
void addRasterChecks(std::vector<Check>& out);
void addVssmChecks(std::vector<Check>& out);  // VSSM's per-pixel kernel (vssm_check.h)
void addTechniqueChecks(std::vector<Check>& out);
void addCallerChecks(std::vector<Check>& out);  // the kernels that read the caller's images (caller_checks.h)

}  // namespace penumbra::selftest
