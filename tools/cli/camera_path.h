// Camera paths of a sweep (`penumbra plan`): per frame, the camera as `--camera` reads it, "EX,EY,EZ:TX,TY,TZ:FOVY".
//   {"orbit": {"target": [x, y, z], "radius": r, "height": h, "fov": deg, "degrees": [from, to]}}: the eye circles
//     the target at `radius`, `height` above it, from `from` to `to` degrees (default 0..360) over the frames (frame
//     f of n at from + (to - from) f / n, so a full turn does not repeat its first frame);
//   {"keyframes": [{"frame": 0, "eye": [...], "target": [...], "fov": 45}, ...]}: eye, target and fov linear between
//     the keys (frames strictly increasing), held before the first and after the last.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace penumbra::cli {

// Throws std::invalid_argument (naming the member) for a malformed path.
std::string cameraOnPath(const nlohmann::json& path, long long frame, long long frameCount);

}  // namespace penumbra::cli
