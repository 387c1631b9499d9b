// std::async with launch::async: one thread per write, joined by finish() before the next starts.
#include "tools/cli/output_writer.h"

#include <exception>
#include <stdexcept>
#include <utility>

namespace penumbra::cli {

OutputWriter::~OutputWriter() {
  if (pending_.valid()) pending_.wait();
}

void OutputWriter::start(ImageOutputPlan plan, Image image) {
  if (pending_.valid()) throw std::logic_error("OutputWriter::start: the previous write was not finished");
  pending_ = std::async(std::launch::async,
                        [plan = std::move(plan), image = std::move(image)] { writeImageOutput(plan, image); });
}

std::string OutputWriter::finish() {
  if (!pending_.valid()) return {};
  try {
    pending_.get();
    return {};
  } catch (const std::exception& e) {
    return e.what();
  }
}

}  // namespace penumbra::cli
