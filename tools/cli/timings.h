// Formats per-pass device times (OpenCL profiling events) as the table `render` and `bench` print.
#pragma once

#include <fmt/format.h>

#include <string>
#include <vector>

#include "host/cl/profiler.h"

namespace penumbra::cli {

inline std::string formatTimings(const std::vector<PassTime>& passes) {
  std::string text = fmt::format("  {:<36} {:>10} {:>6}\n", "pass (stage/kernel)", "device ms", "calls");
  double total = 0;
  for (const PassTime& pass : passes) {
    text += fmt::format("  {:<36} {:>10.3f} {:>6}\n", pass.name, pass.ms, pass.count);
    total += pass.ms;
  }
  text += fmt::format("  {:<36} {:>10.3f}\n", "total", total);
  return text;
}

}  // namespace penumbra::cli
