// `penumbra render SCENE [options] -o out.exr`: renders a scene's lights (each with the command line's technique or
// its own) entirely in OpenCL kernels, writes the EXR (all channels + provenance) and a PNG preview (or, with
// -o x.png, the preview alone), and prints per-pass device times.
#include <fmt/format.h>

#include <memory>
#include <vector>

#include "host/cl/context.h"
#include "host/pipeline/frame_lights.h"
#include "host/pipeline/renderer.h"
#include "host/scene/load.h"
#include "host/techniques/technique.h"
#include "host/techniques/warp.h"
#include "tools/cli/commands.h"
#include "tools/cli/image_output.h"
#include "tools/cli/technique_options.h"
#include "tools/cli/timings.h"
#include "tools/cli/view_options.h"

namespace penumbra::cli {
namespace {

struct RenderOptions {
  ViewOptions view;
  std::string technique = "pcss", device;
  ImageOutput output{"out/render.exr", {}};
  bool quiet = false;
  ParamValues params;  // technique parameters given on the command line
};

int run(const RenderOptions& options) {
  const ImageOutputPlan plan = planImageOutput(options.output);  // a bad -o is a usage error before any work
  const TechniqueInfo& technique = findTechnique(options.technique);
  const Params params = techniqueParams(technique, options.params);
  const Scene scene = loadViewScene(options.view);
  const Camera camera = resolveCamera(options.view, scene);
  const std::vector<Light> lights = resolveLights(options.view, scene);
  // Each light's technique: the command line's, or a scene file light's own (a usage error when it is bad).
  const std::vector<FrameLight> frame =
      resolveFrameLights(lights, technique, params, options.params, options.view.scene);
  const std::optional<uint64_t> limit = memoryLimit(options.view);
  for (const FrameLight& l : frame) refuseUnsupportedLight(l.light, *l.technique);  // before a device is opened
  if (camera.orthographic() && lispsmEnabled(params))
    fmt::print(stderr,
               "penumbra: warning: --warp lispsm with an orthographic camera: no eye point to warp towards, "
               "using the uniform map\n");

  Context ctx(options.device);
  Renderer renderer(ctx, scene);
  renderer.setMemoryLimit(limit);
  RenderResult result = renderer.render(camera, frame);
  for (const std::string& warning : result.warnings) fmt::print(stderr, "penumbra: warning: {}\n", warning);
  result.image.attributes()["penumbra:scene"] = sceneProvenance(options.view);
  recordMaterials(scene, result.image);

  const std::string wrote = writeImageOutput(plan, result.image);
  if (!options.quiet) {
    fmt::print("{} on {}: {}x{}, {} triangles, technique {} ({})\n", sceneProvenance(options.view), ctx.info().name,
               camera.width, camera.height, scene.triangleCount(), technique.name, params.describe());
    if (const std::string materials = describeMaterials(scene); !materials.empty())
      fmt::print("materials: {}\n", materials);
    fmt::print("{}\n", describeLightChoice(options.view, scene, lights));
    for (const FrameLight& l : frame)
      if (!l.light.technique.empty())
        fmt::print("light {} shadowed by its own technique {} ({})\n", l.light.label(), l.technique->name,
                   l.params.describe());
    fmt::print("camera {}\n", cameraSummary(options.view, scene, camera));
    fmt::print("{}", formatTimings(result.passes));
    fmt::print("{}\n", wrote);
  }
  return 0;
}

}  // namespace

Command addRenderCommand(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("render", "Render a scene with a shadow technique");
  auto options = std::make_shared<RenderOptions>();
  addViewOptions(sub, options->view);
  std::string names;
  for (const TechniqueInfo& info : techniques()) names += (names.empty() ? "" : ", ") + info.name;
  sub->add_option("-t,--technique", options->technique, "Shadow technique: " + names)->capture_default_str();
  sub->add_option("--device", options->device, "OpenCL device: auto, cpu, gpu, a name substring, or P:D")
      ->envname("PENUMBRA_DEVICE");
  addImageOutputOptions(sub, options->output);
  sub->add_flag("-q,--quiet", options->quiet, "Print nothing on success");
  addTechniqueOptions(sub, options->params);
  return {sub, [options] { return run(*options); }};
}

}  // namespace penumbra::cli
