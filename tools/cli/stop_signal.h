// SIGTERM and SIGINT (scancel, preemption, eviction, Ctrl-C) while `penumbra run` works: the first asks it to stop
// after the current job; a second one ends the process at once (outputs are written through temporary files, so
// even then no partial file is left under a final name).
#pragma once

namespace penumbra::cli {

class StopSignals {
 public:
  StopSignals();   // installs the handlers
  ~StopSignals();  // restores the previous ones
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  bool requested() const;
  const char* name() const;  // "SIGTERM", "SIGINT", or "" before any
};

}  // namespace penumbra::cli
