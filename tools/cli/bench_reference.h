// The ray tracer as bench's peer (issue 20): `--techniques ...,reference` runs the Embree reference like a
// technique, with its own parameter `spp` (`--sweep spp=4,16,64`), timed by wall clock on the host (the G-buffer
// rasterized and read back, the BVH built, the shadow rays traced: what a user of the tracer pays per frame) and
// measured against bench's ground truth like every technique. Its samples use another seed than the ground truth's,
// so equal sample counts do not make equal estimates.
#pragma once

#include "host/pipeline/renderer.h"
#include "host/scene/scene.h"
#include "host/techniques/technique.h"
#include "tools/reference/reference.h"

namespace penumbra::cli {

// Not in the registry: `render` and the library cannot pick it. Parameters: spp (4k^2 samples per pixel for area
// lights, k = 1..64; hard lights trace one exact ray whatever it is).
const TechniqueInfo& referenceTechnique();
bool isReferenceTechnique(const TechniqueInfo& technique);

// One frame of the reference of `light` alone, drawn with `peer`'s kept rasterizer (bench keeps one per reference
// setting, as the techniques' Renderer keeps its own): its image, and as passes the wall times "reference/gbuffer",
// "reference/bvh_build" and "reference/trace" in milliseconds. Throws std::invalid_argument for an spp that is
// not 4k^2 under an area light.
RenderResult traceFrame(reference::ReferenceRaster& peer, const Camera& camera, const Light& light,
                        const Params& params);

}  // namespace penumbra::cli
