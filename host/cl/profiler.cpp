// Per-pass device times from OpenCL profiling events.
#include "host/cl/profiler.h"

#include <algorithm>

#include "host/cl/error.h"

namespace penumbra {

void Profiler::record(std::string name, cl::Event event, uint64_t bytes) {
  events_.push_back({std::move(name), std::move(event), bytes});
}

std::vector<PassTime> Profiler::resolve() const {
  std::vector<PassTime> passes;
  for (const auto& [name, event, bytes] : events_) {
    clCheck(event.wait(), "clWaitForEvents", name, "profiler");
    cl_ulong start = 0, end = 0;
    // A caller's queue without CL_QUEUE_PROFILING_ENABLE (Context's interop constructor) has no times: 0 ms.
    const cl_int status = event.getProfilingInfo(CL_PROFILING_COMMAND_START, &start);
    if (status != CL_PROFILING_INFO_NOT_AVAILABLE) {
      clCheck(status, "clGetEventProfilingInfo", name, "profiler");
      clCheck(event.getProfilingInfo(CL_PROFILING_COMMAND_END, &end), "clGetEventProfilingInfo", name, "profiler");
    }
    // A plain reference for the lambda: clang before 16 cannot capture a structured binding.
    const std::string& pass = name;
    auto it = std::find_if(passes.begin(), passes.end(), [&](const PassTime& p) { return p.name == pass; });
    if (it == passes.end()) it = passes.insert(passes.end(), PassTime{name, 0.0, 0});
    it->ms += end >= start ? static_cast<double>(end - start) * 1e-6 : 0.0;
    ++it->count;
    it->bytes += bytes;
  }
  return passes;
}

double Profiler::totalMs() const {
  double total = 0;
  for (const PassTime& pass : resolve()) total += pass.ms;
  return total;
}

}  // namespace penumbra
