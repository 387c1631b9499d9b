// The technique registry: one line per technique in registry.cpp, one factory per technique file.
#pragma once

#include "host/techniques/technique.h"

namespace penumbra {

TechniqueInfo smTechnique();
TechniqueInfo pcfTechnique();
TechniqueInfo pcssTechnique();

}  // namespace penumbra
