// The technique registry: one line per technique in registry.cpp, one factory per technique file.
#pragma once

#include "host/techniques/technique.h"

namespace penumbra {

TechniqueInfo smTechnique();
TechniqueInfo pcfTechnique();
TechniqueInfo pcssTechnique();
TechniqueInfo vsmTechnique();    // vsm.cpp
TechniqueInfo evsm2Technique();  // evsm.cpp
TechniqueInfo evsm4Technique();  // evsm.cpp
TechniqueInfo esmTechnique();    // esm.cpp
TechniqueInfo msmTechnique();    // msm.cpp
TechniqueInfo savsmTechnique();  // savsm.cpp
TechniqueInfo vssmTechnique();   // vssm.cpp
TechniqueInfo lvsmTechnique();   // lvsm.cpp
TechniqueInfo pssmTechnique();   // pssm.cpp
TechniqueInfo psvsmTechnique();  // psvsm.cpp
TechniqueInfo jitteredTechnique();  // jittered.cpp
TechniqueInfo izbTechnique();       // izb.cpp
TechniqueInfo fvsmTechnique();      // fvsm.cpp

}  // namespace penumbra
