// A job's outputs written on a thread of their own while the next job renders, so a batch run's throughput is the
// renderer's, not the renderer's plus EXR compression (on a GPU the device renders while a core compresses). One write
// in flight at most: a run holds two frames at most.
#pragma once

#include <future>
#include <string>

#include "host/io/image.h"
#include "tools/cli/image_output.h"

namespace penumbra::cli {

class OutputWriter {
 public:
  OutputWriter() = default;
  ~OutputWriter();  // waits for the write in flight
  OutputWriter(const OutputWriter&) = delete;
  OutputWriter& operator=(const OutputWriter&) = delete;

  // Starts writing (writeImageOutput) on a thread; the previous write must have been collected with finish().
  void start(ImageOutputPlan plan, Image image);
  // How the write in flight ended: its error message ("" when it succeeded, or there was none) and errno when the
  // system refused it (OutputError), 0 otherwise.
  struct Outcome {
    std::string error;
    int errorNumber = 0;
  };
  // Waits for the write in flight.
  Outcome finish();

 private:
  std::future<void> pending_;
};

}  // namespace penumbra::cli
