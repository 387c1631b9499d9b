// The frame pipeline, planned then recorded: camera G-buffer (rasterizer) -> technique (shadow map(s),
// filtering stages, visibility kernel) -> shaded preview -> one Image with every output channel and the
// per-pass device times from OpenCL profiling events.
#pragma once

#include <string>
#include <vector>

#include "host/cl/context.h"
#include "host/cl/profiler.h"
#include "host/io/image.h"
#include "host/scene/scene.h"
#include "host/techniques/technique.h"
#include "raster/rasterizer.h"

namespace penumbra {

struct RenderResult {
  // R,G,B,A (shaded preview, A = 1 where a surface is seen), visibility.Y, P.X/Y/Z, N.X/Y/Z, depth.Z and
  // the technique's debug channels; rows top-down; provenance in the attributes.
  Image image;
  std::vector<PassTime> passes;  // device time per named pass, in recording order
};

class Renderer {
 public:
  // Uploads the scene's triangles once; render() may be called for many cameras, lights and techniques.
  Renderer(Context& ctx, const Scene& scene);

  RenderResult render(const Camera& camera, const Light& light, const TechniqueInfo& technique, const Params& params);

 private:
  Context& ctx_;
  const Scene& scene_;
  Rasterizer raster_;
  GBuffer gbuffer_;
};

}  // namespace penumbra
