// The names of a scene's lights: made unique and safe as a part of an EXR channel name
// ("visibility.<name>.Y"), and the selection of one light by index or name (`--light gltf:INDEX|NAME`).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "host/scene/light.h"

namespace penumbra {

inline constexpr size_t kMaxLightNameLength = 64;  // characters; EXR channel names stay far below 255

// `name` with every character other than ASCII letters, digits, '_' and '-' replaced by '_', cut to
// kMaxLightNameLength; empty when `name` is.
std::string channelSafeName(std::string_view name);

// Gives every light a channel-safe name: empty names become "light<I>" (I: the light's index in `lights`),
// and a name already taken gets "-2", "-3", ... ("Lamp", "Lamp-2"). Names already unique and safe are kept.
void nameLights(std::vector<Light>& lights);

// The index of the light `key` names: a decimal index into `lights`, else a name (exact match). Throws
// std::invalid_argument "--light gltf:KEY: ..." listing the lights there are, for a bad index or unknown name.
size_t findLight(const std::vector<Light>& lights, std::string_view key);

// The light's layer in a frame's EXR: its name, or kUnnamedLightLayer for a light without one (one given with
// --light SPEC, or the framing light of a scene that has none).
inline constexpr std::string_view kUnnamedLightLayer = "light";
std::string lightLayer(const Light& light);

// "PREFIX.LAYER.Y", e.g. lightChannel("visibility", "Key") == "visibility.Key.Y".
std::string lightChannel(std::string_view prefix, std::string_view layer);

// "0 \"Key\" (spot), 1 \"Sun\" (dir)", or "none" for no lights.
std::string listLights(const std::vector<Light>& lights);

}  // namespace penumbra
