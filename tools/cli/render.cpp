// `penumbra render SCENE [options] -o out.exr`: renders a scene's lights (each with the command line's technique or
// its own) entirely in OpenCL kernels, writes the EXR (all channels + provenance) and a PNG preview (or, with
// -o x.png, the preview alone), and prints per-pass device times. The options and steps live in render_job.h.
#include <fmt/format.h>

#include <memory>

#include <CLI/CLI.hpp>

#include "host/cl/context.h"
#include "host/scene/load.h"
#include "tools/cli/commands.h"
#include "tools/cli/render_job.h"
#include "tools/cli/timings.h"

namespace penumbra::cli {
namespace {

void printSummary(const RenderOptions& options, const Context& ctx, const Scene& scene, const TechniqueChoice& choice,
                  const FramePlan& plan, const RenderResult& result) {
  fmt::print("{} on {}: {}x{}, {} triangles, technique {} ({})\n", sceneProvenance(options.view), ctx.info().name,
             plan.camera.width, plan.camera.height, scene.triangleCount(), choice.info->name, choice.params.describe());
  if (const std::string materials = describeMaterials(scene); !materials.empty())
    fmt::print("materials: {}\n", materials);
  fmt::print("{}\n", describeLightChoice(options.view, scene, plan.lights));
  for (const FrameLight& l : plan.frame)
    if (!l.light.technique.empty())
      fmt::print("light {} shadowed by its own technique {} ({})\n", l.light.label(), l.technique->name,
                 l.params.describe());
  fmt::print("camera {}\n", cameraSummary(options.view, scene, plan.camera));
  fmt::print("{}", formatTimings(result.passes));
}

int run(const RenderOptions& options) {
  const ImageOutputPlan output = planImageOutput(options.output);  // a bad -o is a usage error before any work
  const TechniqueChoice choice = chooseTechnique(options);
  const Scene scene = loadViewScene(options.view);
  const FramePlan plan = planFrame(options, choice, scene);
  Context ctx(options.device);
  Renderer renderer(ctx, scene);
  // Written once: the channels stay on the device and go to the files band by band (docs/robustness.md).
  const RenderResult result = renderFrame(renderer, options, scene, plan, FrameDownload::Deferred);
  const std::string wrote = writeImageOutput(output, ImageRows(result.image, result.deferred));
  if (!options.quiet) {
    printSummary(options, ctx, scene, choice, plan, result);
    fmt::print("{}\n", wrote);
  }
  return 0;
}

}  // namespace

Command addRenderCommand(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("render", "Render a scene with a shadow technique");
  auto options = std::make_shared<RenderOptions>();
  addRenderOptions(sub, *options);
  return {sub, [options] { return run(*options); }};
}

}  // namespace penumbra::cli
