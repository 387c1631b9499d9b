#include "tools/cli/bench_reference.h"

#include <utility>

#include "tools/reference/reference.h"

namespace penumbra::cli {

// Another seed than `penumbra reference`'s default, which bench's ground truth uses.
constexpr uint64_t kPeerSeed = 0x9e3779b97f4a7c15ull;

const TechniqueInfo& referenceTechnique() {
  static const TechniqueInfo kReference{
      "reference",
      "the Embree ray tracer as a peer: shadow rays from every covered pixel (host wall-clock times)",
      {{"spp", 16, 4, 16384, "Samples per pixel for area lights, 4k^2 (4 jittered k x k grids)"}},
      nullptr};
  return kReference;
}

bool isReferenceTechnique(const TechniqueInfo& technique) { return &technique == &referenceTechnique(); }

RenderResult traceFrame(reference::ReferenceRaster& peer, const Camera& camera, const Light& light,
                        const Params& params) {
  reference::TraceSettings trace;
  trace.spp = params.getInt("spp");
  trace.seed = kPeerSeed;
  if (light.isArea()) reference::SampleLayout::fromSpp(trace.spp);  // a bad spp: std::invalid_argument
  reference::ReferenceResult traced = reference::renderReference(peer, camera, {light}, trace);
  RenderResult result;
  result.image = std::move(traced.image);
  result.passes = {{"reference/gbuffer", traced.rasterSeconds * 1e3, 1, 0},
                   {"reference/bvh_build", traced.buildSeconds * 1e3, 1, 0},
                   {"reference/trace", traced.traceSeconds * 1e3, 1, 0}};
  return result;
}

}  // namespace penumbra::cli
