// `penumbra reference` as a function: the camera's G-buffer from our rasterizer (the same pixels `render`
// shades), Embree shadow rays from every covered pixel to the light, and the Image with the same channels as
// `render` plus the per-pixel standard error "stderr.Y".
#pragma once

#include <cstddef>
#include <vector>

#include "host/cl/context.h"
#include "host/io/image.h"
#include "host/scene/scene.h"
#include "raster/rasterizer.h"
#include "tools/reference/tracer.h"

namespace penumbra::reference {

struct ReferenceResult {
  // R,G,B,A, visibility.Y, stderr.Y, lit.Y (litMask in host/pipeline/frame_image.h), P.*, N.*, depth.Z; rows
  // top-down; provenance in the attributes (penumbra:technique = "reference", penumbra:parameters) and numbers
  // (penumbra:stderr-mean/-rms/-max, penumbra:rays, penumbra:spp: EXR doubles).
  Image image;
  size_t covered = 0;  // pixels that see a surface (the ones traced)
  uint64_t rays = 0;
  int spp = 1, threads = 0;
  double rasterSeconds = 0, buildSeconds = 0, traceSeconds = 0;  // wall times
  double stderrMean = 0, stderrRms = 0, stderrMax = 0;           // of stderr.Y over covered pixels
};

// The rasterizer the reference draws its G-buffer with, the scene uploaded once and its buffers reused from frame to
// frame, as the Renderer keeps them for the techniques: bench's steady frames of the traced peer pay for drawing and
// reading back the G-buffer, not for a new rasterizer, the scene's upload and fresh pages each frame. `scene` must
// outlive it.
class ReferenceRaster {
 public:
  ReferenceRaster(Context& ctx, const Scene& scene);
  ReferenceRaster(Context& ctx, const Scene&& scene) = delete;
  Context& ctx() { return ctx_; }
  const Scene& scene() const { return scene_; }
  Rasterizer& raster() { return raster_; }
  GBuffer& gbuffer() { return gbuffer_; }

 private:
  Context& ctx_;
  const Scene& scene_;
  Rasterizer raster_;
  GBuffer gbuffer_;
};

ReferenceResult renderReference(Context& ctx, const Scene& scene, const Camera& camera, const Light& light,
                                const TraceSettings& settings);

// Every light traced (same G-buffer, same settings and seed for each) into the layers `render` writes:
// visibility.<layer>.Y, stderr.<layer>.Y and lit.<layer>.Y per light (light_names.h lightLayer), and the first
// light's also as visibility.Y, stderr.Y and lit.Y. rays and traceSeconds count every light; spp and the
// standard-error summary are the first light's.
ReferenceResult renderReference(Context& ctx, const Scene& scene, const Camera& camera,
                                const std::vector<Light>& lights, const TraceSettings& settings);
// The same frame drawn with `raster`'s kept rasterizer (its scene); rasterSeconds counts the draw, the read-back and
// the receivers, not the rasterizer's set-up.
ReferenceResult renderReference(ReferenceRaster& raster, const Camera& camera, const std::vector<Light>& lights,
                                const TraceSettings& settings);

}  // namespace penumbra::reference
