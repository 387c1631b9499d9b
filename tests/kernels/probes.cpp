// Adds the probe kernels of tests/kernels/ (embedded by tests/CMakeLists.txt as probeKernelSources) to the kernel
// lookup before main runs. Linked as an object library, so every program that links it has them.
#include "host/cl/embedded_sources.h"

namespace penumbra {

std::span<const EmbeddedSource> probeKernelSources();  // generated (cmake/EmbedKernels.cmake)

namespace {

const bool kProbesAdded = (addEmbeddedSources(probeKernelSources()), true);

}  // namespace
}  // namespace penumbra
