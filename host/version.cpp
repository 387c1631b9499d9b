// PENUMBRA_VERSION is defined for this file alone (host/CMakeLists.txt), so a new version rebuilds one file.
#include "host/version.h"

namespace penumbra {

std::string_view version() { return PENUMBRA_VERSION; }

}  // namespace penumbra
