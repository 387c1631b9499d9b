// OpenCL C sources embedded into the binary at build time (cmake/EmbedKernels.cmake), looked up by their
// path relative to the repository root ("kernels/vsm.cl", "raster/constants.h"). `#include "path"` lines in a
// source are resolved against the same table, so headers shared with C++ are embedded once and used by both.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace penumbra {

struct EmbeddedSource {
  std::string_view name;  // path relative to the repository root
  std::string_view text;
};

// The library's generated table (sorted by name).
std::span<const EmbeddedSource> embeddedSources();

// Adds a program's own table to the lookup, after the library's: the probe kernels the tests and benchmarks compile
// beside the library's (tests/kernels/), which the library does not ship. Thread-safe; throws std::logic_error when a
// name is already in the library's table or an added one.
void addEmbeddedSources(std::span<const EmbeddedSource> table);

// The text of one source with its `#include "..."` lines resolved recursively (each header once), ready for
// clCreateProgramWithSource. With PENUMBRA_KERNEL_DIR set, every file is read from that directory instead (a
// quick edit-run loop for kernel developers); otherwise only the embedded table is used. Throws
// std::runtime_error naming the file on a missing source or include (and the folder when it is the override's).
std::string resolveKernelSource(std::string_view name);

}  // namespace penumbra
