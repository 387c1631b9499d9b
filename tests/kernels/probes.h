// The probe kernels of tests/kernels/ (embedded by tests/kernels/CMakeLists.txt as probeKernelSources): entry points
// into the library's kernel code that only the tests and benchmarks call. A context builds them once they are added
// to it (Context::addSources); the library's own table never holds them.
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
