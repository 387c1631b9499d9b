// The technique registry: one line per technique in registry.cpp, one factory per technique file.
#pragma once

#include "host/cl/kernel.h"
#include "host/techniques/technique.h"

namespace penumbra {

inline constexpr size_t kPixelGroup = 64;  // work-group size of the per-pixel visibility kernels

TechniqueInfo smTechnique();
TechniqueInfo pcfTechnique();
TechniqueInfo pcssTechnique();

}  // namespace penumbra
