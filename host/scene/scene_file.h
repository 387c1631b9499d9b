// JSON scene descriptions: glTF models placed in the world, built-in scenes, an optional ground plane,
// cameras and lights. Every key is checked (unknown keys are errors, so typos are never silent).
#pragma once

#include <filesystem>
#include <string>

#include "host/scene/contained_fs.h"
#include "host/scene/load_options.h"
#include "host/scene/scene.h"

namespace penumbra {

// The format:
//
// {"models": [{"path": "AntiqueCamera.glb", "translation": [x, y, z], "rotation_deg": [x, y, z] (or
//   "rotation_quat": [x, y, z, w]), "scale": s or [x, y, z]}],
//  "procedural": [{"name": "box", "size": 1.0}],            // built-in scenes, with their parameters
//  "ground": {"enabled": true, "margin": 1.0, "y": 0.0},    // y defaults to the geometry's min y
//  "camera": {"eye": [..], "target": [..], "fovy_deg": 45, "size": [1280, 720]}, "cameras": [...],
//  "camera": "gltf:INDEX|NAME" (instead: one of the models' glTF cameras, placed with its model),
//  "lights": [{"type": "spot", "position": [..], "target": [..], "fov_deg": 60, "radius": 0.5},
//             {"type": "dir", "direction": [..], "angular_radius_deg": 0.5},
//             {"type": "point", "position": [..], "radius": 0.5}]}     // each may have a "name"
//
// A "lights" entry without "type" sets the size of a light a model brings (KHR_lights_punctual), by its name:
// {"name": "Lamp", "radius": 0.2} or {"name": "Sun", "angular_radius_deg": 0.27}; it cannot be mixed with entries
// that define lights. A model's lights move with its placement (sizes, cones and ranges do not scale).
//
// Model paths are absolute or relative to the JSON file's folder (".." allowed: the scene file is the user's
// own); the URIs inside each model must stay inside that model's folder. Cameras and lights given in
// the file replace those the models and built-in scenes bring; the models' glTF cameras (gltfIndex counted across
// the models in order) stay behind a given camera for --camera gltf:, and without one the first model camera is the
// default. Lights get unique, channel-safe names (light_names.h). Throws SceneError "FILE: /json/pointer: message".
Scene loadSceneFile(const std::string& path, const LoadOptions& options = {});

namespace detail {
Scene loadSceneFileResolved(const std::filesystem::path& path, const std::string& display, const LoadOptions& options,
                            FileReader& reader);
}  // namespace detail

}  // namespace penumbra
