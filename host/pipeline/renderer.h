// The frame pipeline, planned then recorded: camera G-buffer (rasterizer) -> technique (shadow map(s),
// filtering stages, visibility kernel) -> shaded preview -> one Image with every output channel and the
// per-pass device times from OpenCL profiling events.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/cl/context.h"
#include "host/cl/profiler.h"
#include "host/io/image.h"
#include "host/io/image_rows.h"
#include "host/pipeline/map_size.h"
#include "host/pipeline/memory_plan.h"
#include "host/pipeline/point_light.h"
#include "host/scene/scene.h"
#include "host/techniques/technique.h"
#include "raster/rasterizer.h"

namespace penumbra {

// One light of a frame and the technique that shadows it.
struct FrameLight {
  Light light;
  const TechniqueInfo* technique;
  Params params;
};

struct RenderResult {
  // R,G,B,A (shaded preview of every light, A = 1 where a surface is seen), visibility.Y (the first light's),
  // visibility.<layer>.Y per light (light_names.h lightLayer), P.X/Y/Z, N.X/Y/Z, depth.Z and the first light's
  // technique's debug channels (a point light: cubeFace.Y, each pixel's cube face 0..5 = +X -X +Y -Y +Z -Z, -1 for
  // background, instead: a technique's debug layers would hold its last face's alone), those the frame's FrameOutputs
  // keep; rows top-down; provenance in the attributes.
  // FrameDownload::Deferred: the header and the debug channels alone; the rest is in `deferred`.
  Image image;
  // FrameDownload::Deferred: every other channel, read on demand from the device (rows top-down); write the frame
  // through ImageRows(image, deferred). They read the renderer's buffers, so only until its next render().
  std::vector<DeferredChannel> deferred;
  std::vector<PassTime> passes;       // device time per named pass, in recording order (not with OnRequest)
  Profiler profile;                   // FrameDownload::OnRequest: the frame's events, resolved when asked
  Buffer<cl_float4> preview;          // the shaded preview on the device (R, G, B, A per pixel), rows bottom-up;
                                      // empty without FrameOutputs::preview
  std::vector<std::string> warnings;  // e.g. a frame that sees no surface (frame_check.h); the caller prints them
};

class Renderer {
 public:
  // Uploads the scene's triangles once; render() may be called for many cameras, lights and techniques. The
  // renderer keeps a reference to `scene`, which must outlive it (a temporary does not compile).
  Renderer(Context& ctx, const Scene& scene);
  Renderer(Context& ctx, const Scene&& scene) = delete;

  // The technique instance (and the device buffers it keeps) lives on across calls while the technique and its
  // parameters stay the same, so repeated frames measure the steady state; a change creates a new one.
  RenderResult render(const Camera& camera, const Light& light, const TechniqueInfo& technique, const Params& params);

  // Several lights in one frame (one G-buffer), each with its own technique. The renderer keeps one technique
  // instance and visibility buffer per position in `lights`, so repeated frames of the same lights stay in the
  // steady state. A point light is shadowed as six cube faces (host/pipeline/point_light.h). Every light is checked
  // against its technique (refuseUnsupportedLight) before any work.
  // FrameDownload::Deferred is for a frame written once (penumbra render): no channel is downloaded whole, the
  // G-buffer's triangle and object ids are released once the lights are done (the next frame allocates them again),
  // and the memory plan counts the writers' bands instead of the image (docs/robustness.md).
  // `outputs` leaves out what the caller does not read (the preview and its pass, the surface and debug channels);
  // each light's visibility is always made.
  RenderResult render(const Camera& camera, const std::vector<FrameLight>& lights,
                      FrameDownload download = FrameDownload::Image, FrameOutputs outputs = {});

  // A frame whose memory plan (host/pipeline/memory_plan.h) needs more than `bytes` of device or host memory is
  // refused (MemoryError) before anything is allocated; none: the device's own limits alone.
  void setMemoryLimit(std::optional<uint64_t> bytes) { memoryLimit_ = bytes; }
  // The device memory the last frame's plan counted (0 before the first frame): what this renderer holds between
  // frames, for callers that keep several (penumbra bench --interleave) and share one budget among them.
  uint64_t plannedDeviceBytes() const { return plannedDeviceBytes_; }

  // Light `index`'s visibility buffer of the last frame (rows bottom-up); the next render() overwrites it.
  const Buffer<float>& visibility(size_t index) const { return slots_.at(index).visibility; }
  // The last frame's G-buffer (rows bottom-up); the next render() overwrites it.
  const GBuffer& gbuffer() const { return gbuffer_; }

 private:
  struct Slot {
    std::unique_ptr<Technique> technique;
    const TechniqueInfo* info = nullptr;  // what `technique` is an instance of
    Buffer<float> visibility;
    CubeShadows cube;  // a point light's faces
    MapProbe probe;    // --map-size auto's drawn probe (host/pipeline/map_size.h)
  };
  // The slot's instance while it matches `technique`, `params` and the frame's `mapSize` (Technique::matches), else a
  // new one in its place.
  Technique& techniqueFor(Slot& slot, const TechniqueInfo& technique, const Params& params, int mapSize);
  // One light's visibility into slot.visibility: a point light's cube faces, or the technique on the light's frame
  // fitted to the receivers it sees. Returns what the technique recorded for the header.
  std::map<std::string, std::string> shadow(const Camera& camera, const FrameLight& light, Slot& slot);
  void addDebugChannels(const Light& light, Slot& slot, Image& image);

  Context& ctx_;
  const Scene& scene_;
  Solids solids_;  // found once: the rasterizer's light views and izb's casters use them
  Rasterizer raster_;
  GBuffer gbuffer_;
  std::vector<Slot> slots_;  // one per light of the frame, in order
  std::optional<uint64_t> memoryLimit_;
  uint64_t plannedDeviceBytes_ = 0;
};

}  // namespace penumbra
