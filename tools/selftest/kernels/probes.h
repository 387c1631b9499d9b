// The probe kernels of tools/selftest/kernels/ (embedded by its CMakeLists.txt as probeKernelSources): entry points
// into the library's kernel code that only `penumbra selftest`, the tests and the benchmarks call. A context builds
// them once they are added to it (Context::addSources); the library's own table never holds them.
#pragma once

#include <span>

#include "host/cl/context.h"
#include "host/cl/embedded_sources.h"

namespace penumbra {

std::span<const EmbeddedSource> probeKernelSources();  // generated (cmake/EmbedKernels.cmake)

inline Context& withProbeKernels(Context& ctx) {
  ctx.addSources(probeKernelSources());
  return ctx;
}

}  // namespace penumbra
