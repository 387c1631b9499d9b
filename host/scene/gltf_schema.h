// Checks a glTF document's JSON before tinygltf sees it: the type of every core property (tinygltf
// silently drops mistyped optional ones), index ranges, the asset version and extensionsRequired.
#pragma once

#include <string>

#include "host/scene/json_util.h"

namespace penumbra::detail {

// Throws SceneError "FILE: POINTER: MESSAGE" for the first property of the wrong type or range, and
// "FILE: extension NAME is required but not supported" for a required extension that changes geometry
// or that this loader does not know (only material, texture and light extensions can be ignored).
void checkGltfJson(const Json& doc, const std::string& file);

}  // namespace penumbra::detail
