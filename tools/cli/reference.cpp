// `penumbra reference SCENE [view options] -o ref.exr [--spp N] [--seed S]`: ray-traced (Embree) visibility for
// the same camera, lights and G-buffer as `render`, written with the same channels plus "stderr.Y" and "lit.Y" (and
// per light stderr.<layer>.Y, lit.<layer>.Y), a PNG preview beside it, and the cost and the first light's noise.
#include "tools/reference/reference.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <memory>
#include <vector>

#include "host/cl/context.h"
#include "host/pipeline/frame_check.h"
#include "host/scene/load.h"
#include "kernels/shared/izb.h"
#include "tools/cli/commands.h"
#include "tools/cli/image_output.h"
#include "tools/cli/view_options.h"

namespace penumbra::cli {
namespace {

struct ReferenceOptions {
  ViewOptions view;
  std::string device;
  ImageOutput output{"out/reference.exr", {}};
  reference::TraceSettings trace;
  bool quiet = false;
};

void printSummary(const ReferenceOptions& options, const Context& ctx, const Scene& scene, const Camera& camera,
                  const std::vector<Light>& lights, const reference::ReferenceResult& r) {
  fmt::print("{} (reference) with G-buffer on {}: {}x{}, {} triangles\n", sceneProvenance(options.view),
             ctx.info().name, camera.width, camera.height, scene.triangleCount());
  if (const std::string materials = describeMaterials(scene); !materials.empty())
    fmt::print("materials: {}\n", materials);
  fmt::print("camera {}\n", cameraSummary(options.view, scene, camera));
  fmt::print("{}\n", describeLightChoice(options.view, scene, lights));
  fmt::print("  {:<22} {:>9.3f} s\n", "G-buffer (OpenCL)", r.rasterSeconds);
  fmt::print("  {:<22} {:>9.3f} s\n", "BVH build (Embree)", r.buildSeconds);
  fmt::print("  {:<22} {:>9.3f} s  {} rays ({} per pixel, {} covered pixels), {} threads, {:.2f} Mrays/s\n",
             "shadow rays", r.traceSeconds, r.rays, r.spp, r.covered, r.threads,
             r.traceSeconds > 0 ? static_cast<double>(r.rays) / r.traceSeconds * 1e-6 : 0.0);
  fmt::print("  standard error of visibility over covered pixels: mean {:.3g}, rms {:.3g}, max {:.3g}\n", r.stderrMean,
             r.stderrRms, r.stderrMax);
}

int run(const ReferenceOptions& options) {
  const ImageOutputPlan plan = planImageOutput(options.output);  // a bad -o is a usage error before any work
  const Scene scene = loadViewScene(options.view);
  const Camera camera = resolveCamera(options.view, scene);
  const std::vector<Light> lights = resolveLights(options.view, scene);
  for (const Light& light : lights)
    if (light.isArea()) reference::SampleLayout::fromSpp(options.trace.spp);  // a bad --spp is a usage error
  for (const Light& light : lights)
    if (const std::optional<std::string> reach = lightReachWarning(scene, light))
      fmt::print(stderr, "penumbra: warning: {}\n", *reach);
  const std::optional<uint64_t> limit = memoryLimit(options.view);
  Context ctx(options.device);
  checkMemoryPlan(planFrame(camera, {}, FrameDownload::Image, {scene.triangles.size(), scene.positions.size()}),
                  ctx.info(), limit);  // the G-buffer and the image; the tracer's BVH aside
  reference::ReferenceResult result = reference::renderReference(ctx, scene, camera, lights, options.trace);
  result.image.attributes()["penumbra:scene"] = sceneProvenance(options.view);
  recordMaterials(scene, result.image);

  const std::string wrote = writeImageOutput(plan, result.image);
  if (!options.quiet) {
    printSummary(options, ctx, scene, camera, lights, result);
    fmt::print("{}\n", wrote);
  }
  return 0;
}

}  // namespace

Command addReferenceCommand(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("reference", "Ray-trace reference visibility (Embree) for render's G-buffer");
  auto options = std::make_shared<ReferenceOptions>();
  addViewOptions(sub, options->view);
  sub->add_option("--spp", options->trace.spp,
                  "Light samples per pixel for disk and sun lights: 4 k^2 (4 independent k x k stratified grids)")
      ->capture_default_str();
  sub->add_option("--seed", options->trace.seed, "Seed of the light samples")->capture_default_str();
  sub->add_option_function<int>(
         "--izb-light-samples",
         [options](int n) {
           options->trace.izbLightGrid = izb_light_grid_of(n);
           if (options->trace.izbLightGrid == 0)
             throw CLI::ValidationError("--izb-light-samples", fmt::format("{} is not k^2 for k in 4..16", n));
         },
         "Instead of --spp: the N light points per pixel `izb` traces under an area light (its pattern, jittered per "
         "pixel: N = k^2, k in 4..16), for a sample-for-sample comparison")
      ->excludes("--spp");
  sub->add_option("--threads", options->trace.threads, "Tracing threads (0: one per hardware thread)")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  sub->add_option("--device", options->device, "OpenCL device for the G-buffer: auto, cpu, gpu, a name, or P:D")
      ->envname("PENUMBRA_DEVICE");
  addImageOutputOptions(sub, options->output);
  sub->add_flag("-q,--quiet", options->quiet, "Print nothing on success");
  return {sub, [options] { return run(*options); }};
}

}  // namespace penumbra::cli
