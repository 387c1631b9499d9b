// Double-precision reference of the alpha test (kernels/shared/alpha.h), written from the glTF 2.0 and
// KHR_texture_transform texts alone: the transform composed from offset, rotation and scale, wrap modes applied to the
// texel indices of the unreduced coordinate, NEAREST and bilinear LINEAR filtering on the base level, the factor and
// the MASK rule (opaque when alpha >= cutoff). A non-finite transformed coordinate counts as 0, the rule alpha.h
// defines.
#pragma once

#include <cstdint>
#include <vector>

#include "host/scene/material.h"

namespace penumbra::ref {

// The material's alpha coverage at texture coordinate (u, v) (before its transform); `textures` and `texels` as in
// Scene::alphaTextures and Scene::alphaTexels. A material that cannot discard has coverage 1.
double alphaCoverage(const Material& m, const std::vector<AlphaTexture>& textures, const std::vector<uint8_t>& texels,
                     double u, double v);

// The cutoff alphaCoverage is compared with (0 for a material that cannot discard).
double alphaCutoff(const Material& m);

}  // namespace penumbra::ref
