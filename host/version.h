// The project's version (CMakeLists.txt's project(VERSION ...), the one place it is defined): printed by
// `penumbra --version` and written into every EXR the tools write (penumbra:version).
#pragma once

#include <string_view>

namespace penumbra {

std::string_view version();  // "MAJOR.MINOR.PATCH"

}  // namespace penumbra
