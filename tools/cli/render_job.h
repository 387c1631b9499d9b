// One render job: the options of `penumbra render` (declared once, here, for the command line and for manifest
// lines alike) and the steps from options to a finished frame, shared by `render` and `run`.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "host/pipeline/renderer.h"
#include "host/scene/scene.h"
#include "host/techniques/technique.h"
#include "tools/cli/image_output.h"
#include "tools/cli/technique_options.h"
#include "tools/cli/view_options.h"

namespace penumbra::cli {

struct RenderOptions {
  ViewOptions view;
  std::string technique = "pcss", device;
  ImageOutput output{"out/render.exr", {}};
  bool quiet = false;
  ParamValues params;  // technique parameters given on the command line
};

// Declares every option of `render` on `sub`: the scene, view, technique, parameters, device, output and -q.
void addRenderOptions(CLI::App* sub, RenderOptions& options);

// The command line's technique and its parameters, checked (std::invalid_argument) before any scene is loaded.
struct TechniqueChoice {
  const TechniqueInfo* info;
  Params params;
};
TechniqueChoice chooseTechnique(const RenderOptions& options);

// What one frame renders: the camera, the lights and each light's technique, every light checked against its
// technique (std::invalid_argument) before a device is needed.
struct FramePlan {
  Camera camera;
  std::vector<Light> lights;
  std::vector<FrameLight> frame;
  std::optional<uint64_t> memoryLimit;  // --memory-limit (host/pipeline/memory_plan.h); none: the device's
};
FramePlan planFrame(const RenderOptions& options, const TechniqueChoice& technique, const Scene& scene);

// Renders the plan under its memory limit, prints the frame's warnings (a frame that sees nothing, ...) on stderr
// unless the caller reports them itself (`printWarnings` false: `run` names their job), and records the scene's
// provenance and materials in the image's header. `download`: as Renderer::render's (Deferred for a frame written
// once and dropped).
RenderResult renderFrame(Renderer& renderer, const RenderOptions& options, const Scene& scene, const FramePlan& plan,
                         FrameDownload download = FrameDownload::Image, bool printWarnings = true);

}  // namespace penumbra::cli
