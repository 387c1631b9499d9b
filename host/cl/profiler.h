// Collects named OpenCL events (one per launch or transfer) and turns them into per-pass device times
// from CL_PROFILING_COMMAND_START/END. Plan-then-record: every launch has a name that shows up here.
#pragma once

#include <CL/opencl.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace penumbra {

struct PassTime {
  std::string name;    // "stage/kernel", e.g. "raster/raster_fine"
  double ms = 0;       // summed device time of all events with that name
  int count = 0;       // number of events summed
  uint64_t bytes = 0;  // summed minimum bytes the launches must move (their hints; 0: no hint given)
};

class Profiler {
 public:
  // `bytes`: the least the command must read plus write in device memory (0: unknown); see Kernel::moves.
  void record(std::string name, cl::Event event, uint64_t bytes = 0);
  // Waits for all recorded events and returns their times by name, in first-recorded order (0 ms for events of a
  // queue without profiling).
  std::vector<PassTime> resolve() const;
  double totalMs() const;
  void clear() { events_.clear(); }
  // Appends `other`'s events (an inner ProfilerScope's).
  void absorb(const Profiler& other) { events_.insert(events_.end(), other.events_.begin(), other.events_.end()); }
  bool empty() const { return events_.empty(); }

 private:
  struct Entry {
    std::string name;
    cl::Event event;
    uint64_t bytes;
  };
  std::vector<Entry> events_;
};

// Attaches a profiler to a context for the lifetime of the scope (also when an exception leaves it). Scopes nest: the
// profiler attached before is attached again at the end and also receives the inner scope's events, so a caller timing
// a whole step (`penumbra selftest` around a Renderer, which times its own frame) sees every launch of it.
template <class Ctx>
class ProfilerScope {
 public:
  ProfilerScope(Ctx& ctx, Profiler& profiler) : ctx_(ctx), profiler_(profiler), previous_(ctx.profiler()) {
    ctx_.setProfiler(&profiler);
  }
  ~ProfilerScope() {
    ctx_.setProfiler(previous_);
    if (previous_ != nullptr) previous_->absorb(profiler_);
  }
  ProfilerScope(const ProfilerScope&) = delete;
  ProfilerScope& operator=(const ProfilerScope&) = delete;

 private:
  Ctx& ctx_;
  Profiler& profiler_;
  Profiler* previous_;
};

}  // namespace penumbra
