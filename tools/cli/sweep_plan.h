// A sweep (`penumbra plan`'s input) expanded into jobs. Every member is a job key (`render` options by their long
// names, "scene", "output"), except:
//   a list          one axis of the cartesian product, in the sweep's member order (the first varies slowest);
//   "frames"        N (frames 0..N-1), {"start": a, "end": b} (inclusive) or {"start": a, "count": n}: the
//                   innermost axis, so a sequence's frames follow one another;
//   "camera" {...}  a camera path (camera_path.h), evaluated per frame;
//   "time" {...}    {"fps": 24, "start": 0}: the time of frame f, start + f / fps (seconds);
//   "output"        a template: {KEY} for any member's value (dashes as underscores: {map_size}), {frame},
//                   {index} (the job's place), {scene_name} (the scene file's stem), with fmt's format specs
//                   ({frame:04}).
#pragma once

#include <nlohmann/json.hpp>

#include <vector>

namespace penumbra::cli {

// Throws std::invalid_argument (message without the file name) for a malformed sweep.
std::vector<nlohmann::ordered_json> expandSweep(const nlohmann::ordered_json& sweep);

}  // namespace penumbra::cli
