// OpenCL C sources embedded into the binary at build time (cmake/EmbedKernels.cmake), looked up by their
// path relative to the repository root ("kernels/vsm.cl", "raster/constants.h"). `#include "path"` lines in a
// source are resolved against the same table, so headers shared with C++ are embedded once and used by both.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

struct EmbeddedSource {
  std::string_view name;  // path relative to the repository root
  std::string_view text;
};

// The library's generated table (sorted by name).
std::span<const EmbeddedSource> embeddedSources();

// More tables a Context builds from after the library's (Context::addSources): the probe kernels the tests and
// benchmarks compile beside the library's (tools/selftest/kernels/), which the library does not ship.
using SourceTables = std::vector<std::span<const EmbeddedSource>>;

// Throws std::logic_error when a name of `table` is already in the library's table or in `tables`.
void checkNewSources(std::span<const EmbeddedSource> table, const SourceTables& tables);

// The text of one source with its `#include "..."` lines resolved recursively (each header once), ready for
// clCreateProgramWithSource. With PENUMBRA_KERNEL_DIR set, every file is read from that directory instead (a
// quick edit-run loop for kernel developers); otherwise only the embedded table is used. Throws
// std::runtime_error naming the file on a missing source or include (and the folder when it is the override's).
// `more`: tables searched after the library's, for the source and its includes.
std::string resolveKernelSource(std::string_view name, const SourceTables& more = {});

}  // namespace penumbra
