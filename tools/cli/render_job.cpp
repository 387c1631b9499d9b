// The render job's steps, in the order `render` takes them: options, technique, scene, frame plan, frame. Each light
// takes the command line's technique or a scene file light's own ("technique", with its "params" on top).
#include "tools/cli/render_job.h"

#include <fmt/format.h>

#include "host/pipeline/frame_lights.h"
#include "host/techniques/warp.h"

namespace penumbra::cli {

void addRenderOptions(CLI::App* sub, RenderOptions& options) {
  addViewOptions(sub, options.view);
  std::string names;
  for (const TechniqueInfo& info : techniques()) names += (names.empty() ? "" : ", ") + info.name;
  sub->add_option("-t,--technique", options.technique, "Shadow technique: " + names)->capture_default_str();
  sub->add_option("--device", options.device, "OpenCL device: auto, cpu, gpu, a name substring, or P:D")
      ->envname("PENUMBRA_DEVICE");
  addImageOutputOptions(sub, options.output);
  sub->add_flag("-q,--quiet", options.quiet, "Print nothing on success");
  addTechniqueOptions(sub, options.params);
}

TechniqueChoice chooseTechnique(const RenderOptions& options) {
  const TechniqueInfo& info = findTechnique(options.technique);
  return {&info, techniqueParams(info, options.params)};
}

FramePlan planFrame(const RenderOptions& options, const TechniqueChoice& technique, const Scene& scene) {
  FramePlan plan{resolveCamera(options.view, scene), resolveLights(options.view, scene), {}, {}};
  // Each light's technique: the command line's, or a scene file light's own (a usage error when it is bad).
  plan.frame = resolveFrameLights(plan.lights, *technique.info, technique.params, options.params, options.view.scene);
  plan.memoryLimit = memoryLimit(options.view);  // a bad --memory-limit is a usage error before any work
  for (const FrameLight& l : plan.frame) refuseUnsupportedLight(l.light, *l.technique);  // before a device is opened
  if (plan.camera.orthographic() && lispsmEnabled(technique.params))
    fmt::print(stderr,
               "penumbra: warning: --warp lispsm with an orthographic camera: no eye point to warp towards, "
               "using the uniform map\n");
  return plan;
}

RenderResult renderFrame(Renderer& renderer, const RenderOptions& options, const Scene& scene, const FramePlan& plan,
                         FrameDownload download, bool printWarnings) {
  renderer.setMemoryLimit(plan.memoryLimit);
  RenderResult result = renderer.render(plan.camera, plan.frame, download);
  if (printWarnings)
    for (const std::string& warning : result.warnings) fmt::print(stderr, "penumbra: warning: {}\n", warning);
  result.preview = {};  // for the library's callers (a deferred frame's readers keep their own reference)
  result.image.attributes()["penumbra:scene"] = sceneProvenance(options.view);
  recordMaterials(scene, result.image);
  return result;
}

}  // namespace penumbra::cli
