// std::async with launch::async: one thread per write, joined by finish() before the next starts.
#include "tools/cli/output_writer.h"

#include <exception>
#include <stdexcept>
#include <utility>

#include "host/io/atomic_file.h"

namespace penumbra::cli {

OutputWriter::~OutputWriter() {
  if (pending_.valid()) pending_.wait();
}

void OutputWriter::start(ImageOutputPlan plan, Image image) {
  if (pending_.valid()) throw std::logic_error("OutputWriter::start: the previous write was not finished");
  pending_ = std::async(std::launch::async,
                        [plan = std::move(plan), image = std::move(image)] { writeImageOutput(plan, image); });
}

OutputWriter::Outcome OutputWriter::finish() {
  if (!pending_.valid()) return {};
  try {
    pending_.get();
    return {};
  } catch (const OutputError& e) {
    return {e.what(), e.errorNumber()};
  } catch (const std::exception& e) {
    return {e.what(), 0};
  }
}

}  // namespace penumbra::cli
